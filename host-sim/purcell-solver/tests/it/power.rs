//! The power cost (MODEL.md §11) through the whole solver: the small problem (`ḡ = (0.001, 0,
//! 0)` in `T = 10 s`, `h = 0.01 s`) and with a joint limit, each returned extremal certified
//! (KKT through the core, the power law's equations, the second order), its cost recomputed
//! from its controls alone by an independent route (the core's kinematics and each link's
//! dissipation), and no dearer in power than the effort-optimal gait.

use nalgebra::Vector2;
use purcell_core::{Kinematics, State};
use purcell_solver::problem::Problem;
use purcell_solver::solver::certificate::law_residual;
use purcell_solver::solver::cost::Cost;
use purcell_solver::solver::settings::LAW_TOL;
use purcell_solver::solver::{Extremal, SolveOptions, solve};
use purcell_solver::testkit::{self, check_extremal, small};

/// `Σ_k h/2·P(α_k, u_k)` from the controls alone: the shapes integrated from `ᾱ` by the core,
/// the power of each step from the links' velocities ([`testkit::dissipated`]).
fn dissipated(p: &Problem, controls: &[Vector2<f64>]) -> f64 {
    let kin = Kinematics::new(p.swimmer, p.h).unwrap();
    let mut s = State::at_origin(p.alpha0);
    let mut sum = 0.0;
    for u in controls {
        sum += testkit::dissipated(&p.swimmer, &s.alpha, u);
        s = kin.step(&s, u).unwrap();
    }
    0.5 * p.h * sum
}

/// The cheapest extremal of `p` from a small search (64 starts: the small problem's minima are
/// few, and the test keeps its CPU time short).
fn solved(p: &Problem) -> Extremal {
    let options = SolveOptions {
        starts: Some(64),
        min_starts: Some(32),
        ..SolveOptions::default()
    };
    let s = solve(p, &options, &|| {}).expect("the problem solves");
    s.extremals[s.best].clone()
}

/// Checks `x`, returned for `p`: certified ([`check_extremal`], the law check being the power
/// law's equations), its cost the links' dissipation along its controls.
fn check_power(name: &str, p: &Problem, x: &Extremal) {
    check_extremal(name, p, x, None);
    let recomputed = dissipated(p, &x.trajectory.controls);
    assert!(
        (recomputed - x.cost).abs() <= 1e-12 * x.cost,
        "{name}: cost {} but the links dissipate {recomputed}",
        x.cost
    );
}

#[test]
fn power_optimal_gaits_are_certified_cheaper_in_power_and_costed_independently() {
    let effort = small(None);
    let power = effort.with_cost(Cost::Power);
    let x = solved(&power);
    check_power("power", &power, &x);
    let e = solved(&effort);
    let e_power = dissipated(&power, &e.trajectory.controls);
    assert!(
        x.cost <= e_power * (1.0 + 1e-9),
        "{} dearer than the effort-optimal gait's power {e_power}",
        x.cost
    );
    // The law's equations are the power law's, not the effort's: the effort-optimal gait with
    // its own costate does not satisfy them.
    let wrong = law_residual(&power, &e.trajectory, &e.mu).unwrap();
    assert!(wrong > 1e3 * LAW_TOL, "effort's costate passes: {wrong}");
    println!(
        "power: J_P = {:.9}, the effort-optimal gait's J_P = {e_power:.9} (saving {:.2} %), \
         KKT {:.1e}, law {:.1e}",
        x.cost,
        100.0 * (1.0 - x.cost / e_power),
        x.kkt_residual.unwrap(),
        x.law_residual.unwrap()
    );
    // A joint limit that binds: arcs with η > 0, the law's equations hold on them with the
    // jumped costate (MODEL.md §11, "Joint limits"), and the limit costs.
    let limited = small(Some(0.8 * x.max_abs_alpha)).with_cost(Cost::Power);
    let y = solved(&limited);
    check_power("power within a limit", &limited, &y);
    assert!(!y.arcs.is_empty(), "the limit binds");
    assert!(y.min_eta.unwrap() > 0.0 && y.cost > x.cost);
    println!(
        "power within {:.4} rad: J_P = {:.9} on {} arcs, smallest eta {:.1e}, law {:.1e}",
        0.8 * x.max_abs_alpha,
        y.cost,
        y.arcs.len(),
        y.min_eta.unwrap(),
        y.law_residual.unwrap()
    );
}
