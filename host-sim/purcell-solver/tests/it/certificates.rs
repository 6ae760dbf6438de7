//! The certificates of `purcell_solver::solver::certificate` shown to reject: each accepts a real
//! extremal of a small problem (the displacement `ḡ = (0.001, 0, 0)` in `T = 10 s` of
//! `h = 0.01 s`) and rejects the same extremal perturbed (controls nudged, a wrong `μ`, a
//! gait off its arc, a reversed costate) by at least three orders of magnitude above the
//! bound the tests hold every returned extremal to (`purcell_solver::testkit::check_extremal`);
//! and `local_min` is false on a saddle that passes every first-order certificate.

use nalgebra::{Vector2, Vector3, Vector5};
use purcell_core::State;
use purcell_solver::problem::Problem;
use purcell_solver::solver::certificate::{kkt, law_residual, terminal_residual};
use purcell_solver::solver::direct;
use purcell_solver::solver::grid::{Grid, Point};
use purcell_solver::solver::linearisation::Linearisation;
use purcell_solver::solver::refinement::extremal;
use purcell_solver::solver::riccati::Factor;
use purcell_solver::solver::settings::{KKT_TOL, LAW_TOL, Settings, TERMINAL_TOL};
use purcell_solver::solver::stage::Rule;
use purcell_solver::solver::{Extremal, Trajectory};
use purcell_solver::testkit::{cheapest, small};

/// How far above its bound a perturbed extremal's residual must be.
const MARGIN: f64 = 1e3;

/// The trajectory of `controls` through the core's kinematics, with the costates `xis` kept.
fn rolled(p: &Problem, controls: Vec<Vector2<f64>>, xis: &[Vector2<f64>]) -> Trajectory {
    let kin = p.kinematics::<f64>().unwrap();
    let mut states = vec![State::at_origin(p.alpha0)];
    for u in &controls {
        states.push(kin.step(states.last().unwrap(), u).unwrap());
    }
    Trajectory {
        states,
        controls,
        xis: xis.to_vec(),
    }
}

fn umax(t: &Trajectory) -> f64 {
    t.controls.iter().fold(0.0, |m, u| m.max(u.amax()))
}

/// Each control nudged by `1e-3` of the largest one, alternating in sign along the path (the
/// shape still closes when the count is even): a trajectory of the swimmer a hair off the
/// extremal.
fn nudged(p: &Problem, t: &Trajectory) -> Trajectory {
    let d = 1e-3 * umax(t);
    let controls = t
        .controls
        .iter()
        .enumerate()
        .map(|(k, u)| u + Vector2::new(d, -d) * if k % 2 == 0 { 1.0 } else { -1.0 })
        .collect();
    rolled(p, controls, &t.xis)
}

/// A certificate's `residual` of the extremal `x` of `p`: as found, with its controls
/// [`nudged`], and with `μ` off by 1e-4 of its size in one component.
fn judged(
    p: &Problem,
    x: &Extremal,
    residual: impl Fn(&Trajectory, &Vector3<f64>) -> f64,
) -> [f64; 3] {
    let t = &x.trajectory;
    let mu = x.mu + Vector3::new(1e-4 * x.mu.amax(), 0.0, 0.0);
    [
        residual(t, &x.mu),
        residual(&nudged(p, t), &x.mu),
        residual(t, &mu),
    ]
}

#[test]
fn terminal_residual_rejects_nudged_controls() {
    let p = small(None);
    let x = cheapest(&p);
    let t = &x.trajectory;
    let good = terminal_residual(&p, &t.controls).unwrap();
    assert!(good <= TERMINAL_TOL, "{good:e}");
    // One control nudged by 1e-3 of the largest: the end is off by about h·1e-3·|u|.
    let mut one = t.controls.clone();
    one[t.controls.len() / 3].x += 1e-3 * umax(t);
    let bad = terminal_residual(&p, &one).unwrap();
    eprintln!("terminal: good {good:.1e}, one control nudged {bad:.1e}");
    assert!(bad >= MARGIN * TERMINAL_TOL, "{bad:e}");
    // The same controls for a target moved by 1e-6 m (1e-3 of the displacement).
    let moved = Problem {
        target: p.target + Vector3::new(0.0, 1e-6, 0.0),
        ..p
    };
    let off = terminal_residual(&moved, &t.controls).unwrap();
    assert!(off >= MARGIN * TERMINAL_TOL, "{off:e}");
}

#[test]
fn law_residual_rejects_nudged_controls_and_a_wrong_mu() {
    let p = small(None);
    let x = cheapest(&p);
    let [good, nudge, wrong] = judged(&p, &x, |t, mu| law_residual(&p, t, mu).unwrap());
    assert!(good <= LAW_TOL, "{good:e}");
    eprintln!("law: good {good:.1e}, nudged {nudge:.1e}, wrong mu {wrong:.1e}");
    assert!(nudge >= MARGIN * LAW_TOL, "{nudge:e}");
    assert!(wrong >= MARGIN * LAW_TOL, "{wrong:e}");
}

#[test]
fn kkt_rejects_nudged_controls_and_a_wrong_mu() {
    let p = small(None);
    let x = cheapest(&p);
    let t = &x.trajectory;
    let found = kkt(&p, t, &x.mu).unwrap();
    assert_eq!((found.min_eta, found.active), (None, 0));
    let [good, nudge, wrong] = judged(&p, &x, |t, mu| kkt(&p, t, mu).unwrap().residual);
    assert!(good <= KKT_TOL, "{found:?}");
    // The terminal multiplier ν = −ξ^{N−1} off too.
    let mut xis = t.xis.clone();
    *xis.last_mut().unwrap() += Vector2::new(1e-4 * x.mu.amax(), 0.0);
    let wrong_nu = kkt(&p, &Trajectory { xis, ..t.clone() }, &x.mu)
        .unwrap()
        .residual;
    eprintln!(
        "kkt: good {good:.1e}, nudged {nudge:.1e}, wrong mu {wrong:.1e}, wrong nu {wrong_nu:.1e}"
    );
    for bad in [nudge, wrong, wrong_nu] {
        assert!(bad >= MARGIN * KKT_TOL, "{bad:e}");
    }
}

/// A gait on arcs of its joint limit: the KKT certificate finds the states on the limit and
/// their multipliers `η > 0`. The same gait judged against a limit 1e-9 wider is off its
/// arcs (no state on the limit, so no `η` to balance the pull of the limit: the residual
/// jumps), and with the costate reversed (`μ`, `ξ` negated) the limit pulls the wrong way
/// (`η < 0`).
#[test]
fn kkt_rejects_a_gait_off_its_arcs_and_a_negative_eta() {
    let free = cheapest(&small(None));
    let limit = 0.8 * free.max_abs_alpha;
    let p = small(Some(limit));
    let x = cheapest(&p);
    assert!(!x.arcs.is_empty(), "the limit {limit} binds");
    let t = &x.trajectory;
    let good = kkt(&p, t, &x.mu).unwrap();
    let eta = good.min_eta.unwrap();
    assert!(good.residual <= KKT_TOL && eta > 0.0, "{good:?}");
    assert!(good.active > 0);

    let wider = Problem {
        alpha_max: Some(limit * (1.0 + 1e-9)),
        ..p
    };
    let off = kkt(&wider, t, &x.mu).unwrap();
    assert_eq!((off.min_eta, off.active), (None, 0));

    let reversed = Trajectory {
        xis: t.xis.iter().map(|xi| -xi).collect(),
        ..t.clone()
    };
    let negative = kkt(&p, &reversed, &(-x.mu)).unwrap();
    let neg_eta = negative.min_eta.unwrap();
    eprintln!(
        "kkt with a limit: good {:.1e} (min eta {eta:.1e}, {} states on it), off its arcs {:.1e}, reversed costate: {:.1e}, min eta {neg_eta:.1e}",
        good.residual, good.active, off.residual, negative.residual
    );
    assert!(off.residual >= MARGIN * KKT_TOL, "{off:?}");
    assert!(neg_eta <= -eta, "{negative:?}");
    assert!(negative.residual >= MARGIN * KKT_TOL, "{negative:?}");
}

/// The extremal that runs the cheapest one's loop twice at `1/√2` of its size (Newton's
/// method on the KKT system, without the solver's inertia correction, from the loop so
/// compressed) passes every first-order certificate, yet is a saddle: `local_min` is false,
/// it costs more than the cheapest, and the solver's own Newton method with inertia
/// correction, started a hair off it, leaves it for a cheaper extremal.
#[test]
fn local_min_is_false_on_a_saddle() {
    let p = small(None);
    let min = cheapest(&p);
    let grid = Grid::new(&p, p.steps as usize, Rule::LEFT_POINT).unwrap();
    let n = grid.steps;
    let once = &min.trajectory.controls;
    let twice: Vec<_> = (0..n)
        .map(|k| once[(2 * k) % n] * core::f64::consts::SQRT_2)
        .collect();
    let mut pt = Point::new(&grid, twice, Vector5::zeros()).unwrap();
    for _ in 0..30 {
        let c = grid.terminal.defect(&pt.states);
        let lz = Linearisation::new(&grid, (&pt.states, &pt.u), &pt.nu, &pt.z).unwrap();
        if c.amax() <= 1e-15 && lz.kkt <= 1e-12 {
            break;
        }
        let f = Factor::new(&lz.lin, &lz.grad, grid.h(), 0.0, None).unwrap();
        let (du, dnu) = f.solve(&lz.lin, &(-c), true).unwrap();
        let u = pt.u.iter().zip(&du).map(|(u, d)| u + d).collect();
        pt = Point::new(&grid, u, pt.nu + dnu).unwrap();
    }
    let settings = Settings::fine(&p, &pt.u);
    let run = direct::newton(&grid, pt.clone(), &settings).unwrap();
    assert!(run.converged() && run.iterations == 0, "{}", run.defect);
    let saddle = extremal(&p, &grid, &run);
    eprintln!(
        "saddle: J {} (cheapest {}), kkt {:?}, law {:?}, terminal {:?}",
        saddle.cost, min.cost, saddle.kkt_residual, saddle.law_residual, saddle.terminal_residual
    );
    assert!(saddle.kkt_residual.unwrap() <= KKT_TOL);
    assert!(saddle.law_residual.unwrap() <= LAW_TOL);
    assert!(saddle.terminal_residual.unwrap() <= TERMINAL_TOL);
    assert!(!saddle.local_min);
    assert!(saddle.cost > 1.5 * min.cost);

    // Off the saddle by 1e-3 of its controls, descent with inertia correction finds a
    // cheaper extremal.
    let d = 1e-3 * umax(&saddle.trajectory);
    let u =
        pt.u.iter()
            .enumerate()
            .map(|(k, u)| u + Vector2::new(d * (k as f64 * 0.01).sin(), 0.0))
            .collect();
    let start = Point::new(&grid, u, pt.nu).unwrap();
    let away = direct::newton(
        &grid,
        start,
        &Settings {
            max_iterations: 200,
            ..settings
        },
    )
    .unwrap();
    let cost = grid.cost(&away.point.u, &away.point.states);
    eprintln!(
        "from a hair off the saddle: J {cost}, converged {}, local min {}",
        away.converged(),
        away.local_min()
    );
    assert!(away.converged() && away.local_min(), "{away:?}");
    assert!(cost < saddle.cost * (1.0 - 1e-3), "{cost} {}", saddle.cost);
}
