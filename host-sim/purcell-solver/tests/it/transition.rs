//! A problem with its own end shape (MODEL.md §12) through the library: every start of the
//! search runs from `ᾱ` to `β`; the returned extremal passes every certificate against `β`
//! (and fails the terminal one against `ᾱ`), costs at least `|β − ᾱ|²/2T` and agrees across
//! seeds; a loop's starts are the loop family, unchanged.

use nalgebra::Vector2;
use purcell_solver::problem::{InputError, Problem, Spec};
use purcell_solver::solver::certificate::terminal_residual;
use purcell_solver::solver::grid::Grid;
use purcell_solver::solver::stage::Rule;
use purcell_solver::solver::{SolveOptions, solve, starts};
use purcell_solver::testkit::check_extremal;

/// From `(0.5, 0.3)` to `(0, −0.2)`, to `ḡ = (0.01, 0.01, 0)` in 10 s of 0.01 s.
fn spec() -> Spec {
    Spec {
        target: [0.01, 0.01, 0.0],
        horizon: 10.0,
        step: 0.01,
        alpha0: [0.5, 0.3],
        alpha_end: Some([0.0, -0.2]),
        ..Spec::default()
    }
}

#[test]
fn every_start_of_a_transition_runs_from_the_start_to_the_end_shape() {
    let p = Problem::new(&spec()).unwrap();
    assert!(!p.is_loop() && p.stored_end() == Some([0.0, -0.2]));
    let grid = Grid::new(&p, 64, Rule::LEFT_POINT).unwrap();
    let moved = |u: &[Vector2<f64>]| u.iter().sum::<Vector2<f64>>() * grid.h();
    let want = p.alpha_end - p.alpha0;
    assert!((moved(&starts::straight(&grid)) - want).amax() < 1e-14);
    let family = starts::of_grid(&grid, 0.5, 0, 0, 200, None);
    assert_eq!(family.len(), 200);
    for s in &family {
        assert!((moved(&s.controls(&grid)) - want).amax() < 1e-12, "{s:?}");
    }
    // A loop: the family through ᾱ, closed, and the zero loop.
    let looped = Problem::new(&Spec {
        alpha_end: None,
        ..spec()
    })
    .unwrap();
    let grid = Grid::new(&looped, 64, Rule::LEFT_POINT).unwrap();
    assert!(looped.is_loop() && looped.stored_end().is_none());
    assert_eq!(
        starts::of_grid(&grid, 0.5, 0, 0, 200, None),
        starts::family(0.5, &looped.alpha0, 0, 200, true)
    );
    assert!(
        starts::straight(&grid)
            .iter()
            .all(|u| *u == Vector2::zeros())
    );
}

#[test]
fn a_transition_is_certified_against_its_end_shape_and_seeds_agree() {
    let p = Problem::new(&spec()).unwrap();
    let mut costs = Vec::new();
    for seed in [0, 1] {
        let options = SolveOptions {
            seed,
            ..SolveOptions::default()
        };
        let s = solve(&p, &options, &|| {}).expect("the transition solves");
        let x = &s.extremals[s.best];
        check_extremal("transition", &p, x, None);
        let end = x.trajectory.states.last().unwrap().alpha;
        assert!((end - p.alpha_end).amax() < 1e-10, "{end}");
        // J ≥ |β − ᾱ|²/2T (Cauchy–Schwarz, MODEL.md §12).
        let bound = (p.alpha_end - p.alpha0).norm_squared() / (2.0 * p.horizon());
        assert!(x.cost > bound, "{} vs {bound}", x.cost);
        // Against the start shape (the loop's condition), the same controls miss by |β − ᾱ|.
        let as_loop = Problem {
            alpha_end: p.alpha0,
            ..p
        };
        let miss = terminal_residual(&as_loop, &x.trajectory.controls).unwrap();
        assert!((miss - 0.5).abs() < 1e-9, "{miss}");
        costs.push(x.cost);
    }
    assert!((costs[0] - costs[1]).abs() <= 1e-9 * costs[0], "{costs:?}");
}

#[test]
fn an_end_shape_outside_the_limit_is_refused() {
    let refused = |end: [f64; 2], alpha_max: Option<f64>| {
        Problem::new(&Spec {
            alpha_end: Some(end),
            alpha_max,
            ..spec()
        })
        .err()
    };
    assert_eq!(
        refused([3.2, 0.0], None),
        Some(InputError::EndOutOfRange(3.2, 0.0, core::f64::consts::PI))
    );
    assert_eq!(
        refused([0.0, 0.9], Some(0.8)),
        Some(InputError::EndOutOfRange(0.0, 0.9, 0.8))
    );
    assert_eq!(
        refused([f64::NAN, 0.0], None),
        Some(InputError::NonFinite("alpha-end"))
    );
}
