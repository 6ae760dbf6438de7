//! The committed power-optimal gait of the paper's target (`core/examples/paper-power.gait`,
//! `purcell-sim solve --cost power`, then `export`; MODEL.md §11): a version-5 file whose
//! replay runs the power's law to the target, `f64` within 1e-10 and `f32` with its
//! checkpoints within 1e-5; the effort's law from the same costate does not get there.

use purcell_core::cost::{Effort, Power};
use purcell_core::{Cost, Error, Gait, Replay, gait};

static POWER: &[u8] = include_bytes!("../../examples/paper-power.gait");

#[test]
fn the_power_gait_replays_to_the_target_through_the_power_law() {
    assert_eq!(POWER[8..10], gait::VERSION_COST.to_le_bytes());
    let g = Gait::from_bytes(POWER).unwrap();
    let p = g.params();
    assert_eq!(
        (p.cost, p.steps, g.checkpoint_count()),
        (Cost::Power, 10_000, 99)
    );
    let r64 = g.replay_for::<f64, Power>(true).unwrap();
    assert_eq!(r64.cost(), Cost::Power);
    let e64 = p.terminal_error(&r64.finish().unwrap());
    let r32 = g.replay_for::<f32, Power>(true).unwrap();
    let e32 = p.terminal_error(&r32.fly(Replay::step).unwrap().end);
    assert!(e64.alpha.max(e64.g) < 1e-10, "f64: {e64:?}");
    assert!(e32.alpha.max(e32.g) < 1e-5, "f32: {e32:?}");
    // The gait's cost is the only law it replays with: the effort's replay is refused, and
    // the effort's law from the power's costate, restarting at every checkpoint, ends far
    // from the target.
    assert_eq!(g.replay::<f64>().err(), Some(Error::InvalidParameters));
    assert_eq!(
        g.replay_for::<f32, Effort>(false).err(),
        Some(Error::InvalidParameters)
    );
    // The same file labelled with the effort.
    let params = gait::GaitParams {
        cost: Cost::Effort,
        ..*p
    };
    let records: Vec<_> = g.checkpoints().collect();
    let mut bytes = vec![0; gait::encoded_len_of(&params, records.len(), 0, 0)];
    gait::encode(&params, &records, &[], &mut bytes).unwrap();
    let effort = Gait::from_bytes(&bytes).unwrap().replay::<f64>().unwrap();
    let wrong = effort.finish().map(|end| p.terminal_error(&end));
    assert!(wrong.is_err() || wrong.is_ok_and(|e| e.alpha.max(e.g) > 1e-3));
}

#[test]
fn a_gait_file_round_trips_its_cost() {
    let g = Gait::from_bytes(POWER).unwrap();
    let records: Vec<_> = g.checkpoints().collect();
    for (cost, end) in [
        (Cost::Power, None),
        (Cost::Power, Some([0.0, 0.1])),
        (Cost::Effort, None),
    ] {
        let params = gait::GaitParams {
            cost,
            alpha_end: end,
            ..*g.params()
        };
        let mut bytes = vec![0; gait::encoded_len_of(&params, records.len(), 0, 0)];
        gait::encode(&params, &records, &[], &mut bytes).unwrap();
        let back = Gait::from_bytes(&bytes).unwrap();
        assert_eq!(back.params(), &params);
        let version = if cost == Cost::Effort {
            gait::VERSION
        } else {
            gait::VERSION_COST
        };
        assert_eq!(bytes[8..10], version.to_le_bytes());
        let power = back.replay_for::<f32, Power>(true).map(|r| r.cost());
        let effort = back.replay::<f32>().map(|r| r.cost());
        let expected = Ok(cost);
        assert!(power == expected || effort == expected, "{cost:?}");
        assert!(power.is_err() || effort.is_err());
    }
    // An unknown cost code, the effort's (its gaits are the older versions), an end-shape flag neither 0 nor 1 and an end shape stored as
    // absent but not zero are refused: `PARM` at 80 (header, four directory entries), its
    // code after version 2's 144 bytes, then the flag, then the end shape.
    let code = 16 + 4 * 16 + 144;
    for (at, value) in [(code, 7u32), (code, 0), (code + 4, 2), (code + 8, 1)] {
        let mut bytes = POWER.to_vec();
        bytes[at..at + 4].copy_from_slice(&value.to_le_bytes());
        let n = bytes.len();
        let crc = gait::crc32(&bytes[..n - 4]);
        bytes[n - 4..].copy_from_slice(&crc.to_le_bytes());
        assert_eq!(
            Gait::from_bytes(&bytes).err(),
            Some(purcell_core::Error::GaitLayout)
        );
    }
}

/// A replay of whichever cost the gait has (`Gait::replay_any`, `Gait::with_replay`) is the
/// replay of that cost, sample for sample, for the effort's gait and the power's.
#[test]
fn a_replay_of_any_cost_is_the_gaits_own_cost_replay() {
    struct Samples;
    impl<'a> gait::WithReplay<'a, f32> for Samples {
        type Output = Vec<purcell_core::Sample<f32>>;
        fn run<C: purcell_core::cost::RunningCost>(self, r: Replay<'a, f32, C>) -> Self::Output {
            assert_eq!(r.cost(), C::COST);
            r.map(Result::unwrap).collect()
        }
    }
    static PAPER: &[u8] = include_bytes!("../../examples/paper.gait");
    for (bytes, cost) in [(PAPER, Cost::Effort), (POWER, Cost::Power)] {
        let g = Gait::from_bytes(bytes).unwrap();
        let (own, end) = if cost == Cost::Effort {
            let r = g.replay::<f32>().unwrap();
            (
                r.clone().map(Result::unwrap).collect::<Vec<_>>(),
                r.finish(),
            )
        } else {
            let r = g.replay_for::<f32, Power>(true).unwrap();
            (r.clone().map(Result::unwrap).collect(), r.finish())
        };
        assert_eq!(g.with_replay(true, Samples).unwrap(), own);
        let mut any = g.replay_any::<f32>().unwrap();
        assert!(matches!(
            (&any, cost),
            (gait::AnyReplay::Effort(_), Cost::Effort) | (gait::AnyReplay::Power(_), Cost::Power)
        ));
        assert_eq!(any.last_sample(), None);
        for s in &own {
            assert_eq!(any.step().unwrap(), Some(s));
            assert_eq!(any.last_sample(), Some(s));
        }
        assert_eq!(any.step().unwrap(), None);
        assert_eq!(any.steps_done(), g.params().steps);
        assert_eq!(any.state(), &end.unwrap());
    }
}
