//! Golden digests of the committed gaits, pinned so that a change of any bit of a flight is
//! noticed (`firmware/check.sh` compares the host with the MCU only, so a change on both
//! sides would pass it).
//!
//! Sources: both gaits are the main job's (`purcell-sim solve`, and `solve --alpha-max 1.5`,
//! each exported by `purcell-sim export`), regenerated on 2026-11-26. The f32 digests and
//! final-state bits are the M4F flights in QEMU as recorded in `firmware/README.md` (the paper's
//! gait: `digest: 0x72d34043226bae86`, `final_state_bits: 0x34048800 0x34350000 0x3dccccdc
//! 0x3dcccccd 0x3f800000 0xb3fb0000`; the constrained gait: `0x5b40ab4d18679a01`), which
//! `check.sh` holds bit-identical to the host's f32 replay. The f64 digests are the host's
//! replay of the same files (the M7's f64 flight is held bit-identical to it by `check.sh`,
//! step 5).

use purcell_core::{Gait, Replay};

static PAPER: &[u8] = include_bytes!("../../examples/paper.gait");
static PAPER_LIMIT: &[u8] = include_bytes!("../../examples/paper-limit.gait");

#[test]
fn the_committed_gaits_fly_to_their_pinned_digests() {
    for (name, bytes, f32_digest, f64_digest) in [
        ("paper", PAPER, 0x72d3_4043_226b_ae86, F64_PAPER),
        (
            "paper-limit",
            PAPER_LIMIT,
            0x5b40_ab4d_1867_9a01,
            F64_PAPER_LIMIT,
        ),
    ] {
        let gait = Gait::from_bytes(bytes).unwrap();
        let f32_flight = gait.replay::<f32>().unwrap().fly(Replay::step).unwrap();
        let f64_flight = gait.replay::<f64>().unwrap().fly(Replay::step).unwrap();
        assert_eq!(f32_flight.digest.value(), f32_digest, "{name} f32");
        assert_eq!(f64_flight.digest.value(), f64_digest, "{name} f64");
    }
}

#[test]
fn the_paper_gait_ends_on_the_m4f_final_state() {
    let gait = Gait::from_bytes(PAPER).unwrap();
    let flight = gait.replay::<f32>().unwrap().fly(Replay::step).unwrap();
    let bits = [
        0x3404_8800,
        0x3435_0000,
        0x3dcc_ccdc,
        0x3dcc_cccd,
        0x3f80_0000,
        0xb3fb_0000,
    ];
    assert_eq!(flight.final_bits(), bits.map(|b: u32| u64::from(b)));
}

/// The host's f64 flights of the committed gaits.
const F64_PAPER: u64 = 0xbc72_ceca_a575_b173;
const F64_PAPER_LIMIT: u64 = 0x0ef9_c4af_6e73_eda1;
