//! A bit-exact fingerprint of a trajectory, to prove that two runs computed the same numbers.
//!
//! FNV-1a (64 bit) over the IEEE 754 bit patterns, in this order for each sample:
//! `u_k (2)`, `α_k (2)`, `g_k` as `(x, y, cos θ, sin θ)`; [`TrajectoryDigest::push_state`]
//! adds a final state the same way without `u`. Not cryptographic: it detects differences,
//! it does not resist forgery.

use crate::kinematics::State;
use crate::real::Real;
use crate::sample::Sample;

/// Running FNV-1a 64 hash of a trajectory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TrajectoryDigest(u64);

impl Default for TrajectoryDigest {
    fn default() -> Self {
        Self::new()
    }
}

impl TrajectoryDigest {
    const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;

    /// The digest of nothing.
    pub const fn new() -> Self {
        TrajectoryDigest(Self::OFFSET)
    }

    /// Adds the bit pattern of one number (its 8 little-endian bytes, widened for `f32`).
    #[inline]
    pub fn push<T: Real>(&mut self, x: T) {
        for byte in x.to_bits().to_le_bytes() {
            self.0 = (self.0 ^ u64::from(byte)).wrapping_mul(Self::PRIME);
        }
    }

    /// Adds `α`, then `g` as `(x, y, cos θ, sin θ)`.
    pub fn push_state<T: Real>(&mut self, state: &State<T>) {
        self.push(state.alpha.x);
        self.push(state.alpha.y);
        self.push(state.g.x());
        self.push(state.g.y());
        self.push(state.g.cos());
        self.push(state.g.sin());
    }

    /// Adds `u_k`, then the state `(α_k, g_k)`.
    pub fn push_sample<T: Real>(&mut self, sample: &Sample<T>) {
        self.push(sample.u.x);
        self.push(sample.u.y);
        self.push_state(&sample.state);
    }

    /// The digest so far.
    pub fn value(&self) -> u64 {
        self.0
    }
}
