//! The costs' one table (`purcell_core::for_each_cost!`) and what is made from it: names and
//! codes that identify one cost each, `with_cost!` running the type of the cost it is given,
//! and `AnyReplay::with_mut` running the replay its variant holds.

use purcell_core::cost::RunningCost;
use purcell_core::gait::{AnyReplay, WithAnyReplay};
use purcell_core::{Cost, Gait, Replay, with_cost};

fn cost_of<C: RunningCost>() -> Cost {
    C::COST
}

#[test]
fn each_cost_has_its_own_name_and_the_type_of_its_row() {
    for (i, cost) in Cost::ALL.into_iter().enumerate() {
        assert_eq!(Cost::named(cost.name()), Some(cost));
        assert_eq!(with_cost!(cost, C => cost_of::<C>()), cost);
        for (j, other) in Cost::ALL.into_iter().enumerate().filter(|&(j, _)| j != i) {
            assert_ne!(other, cost, "{j}");
            assert_ne!(other.name(), cost.name(), "{j}");
        }
    }
    assert_eq!(Cost::default(), Cost::Effort);
    assert_eq!(Cost::named("speed"), None);
}

#[test]
fn with_mut_runs_the_replay_of_the_variant() {
    struct Steps;
    impl<'a> WithAnyReplay<'a, f32> for Steps {
        type Output = (Cost, u32);
        fn run<C: RunningCost>(self, replay: &mut Replay<'a, f32, C>) -> (Cost, u32) {
            replay.step().unwrap();
            (C::COST, replay.steps_done())
        }
    }
    for bytes in [
        &include_bytes!("../../examples/paper.gait")[..],
        &include_bytes!("../../examples/paper-power.gait")[..],
    ] {
        let g = Gait::from_bytes(bytes).unwrap();
        let mut any: AnyReplay<'_, f32> = g.replay_any().unwrap();
        assert_eq!(any.with_mut(Steps), (g.params().cost, 1));
        assert_eq!(any.steps_done(), 1);
    }
}
