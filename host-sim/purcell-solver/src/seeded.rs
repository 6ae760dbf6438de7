//! Seeded draws, reproducible on every machine: SplitMix64 (Steele, Lea, Flood 2014), for the
//! order of the search's start loops ([`crate::solver::starts`]) and the measurement noise of
//! a flight ([`crate::tracking`]).

/// The increment of SplitMix64's state: `2⁶⁴/φ`, odd.
pub const GOLDEN_GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// SplitMix64's output mix of a state `z`.
pub fn splitmix64(z: u64) -> u64 {
    let z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    let z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
