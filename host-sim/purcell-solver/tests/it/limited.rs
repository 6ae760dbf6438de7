//! The global search under a joint limit (`purcell_solver::solver::search`): what it must file
//! whatever the seed.

use purcell_solver::problem::{Problem, Spec};
use purcell_solver::solver::{SolveOptions, solve};

/// The zero target from a bent start within a limit: the zero control (every state at `ᾱ`,
/// inside the limit) is the exact global minimum, `J = 0`, which the barrier's gradient at a
/// bent `ᾱ` pushed every start off (exit 3, "no start reached the target").
#[test]
fn the_zero_target_from_a_bent_start_is_the_zero_gait() {
    let problem = Problem::new(&Spec {
        target: [0.0; 3],
        alpha0: [0.0, 0.9],
        alpha_max: Some(1.5),
        ..Spec::default()
    })
    .unwrap();
    for seed in 0..2 {
        let options = SolveOptions {
            seed,
            ..SolveOptions::default()
        };
        let s = solve(&problem, &options, &|| {}).unwrap();
        let best = &s.extremals[s.best];
        assert_eq!(best.cost, 0.0, "seed {seed}");
        assert!(best.arcs.is_empty() && best.admissible, "seed {seed}");
        assert!(best.trajectory.controls.iter().all(|u| u.norm() == 0.0));
    }
}
