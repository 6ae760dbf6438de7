//! What the test crates share (behind the `test-kit` feature, as nalgebra exports its
//! proptest strategies behind one): a small problem that solves in a moment ([`small`]), the
//! extremal a solve returns ([`cheapest`]), and the contract every returned extremal is held
//! to ([`check_extremal`], with the certificates' bounds of [`crate::solver::settings`]), the
//! seeds' agreement on a problem's cheapest coarse minimum ([`seeds_agree`]), and the power a
//! swimmer dissipates computed link by link ([`dissipated`]), independently of the power
//! cost's metric.

use crate::problem::{Problem, Spec};
use crate::solver::grid::same_path;
use crate::solver::settings::{KKT_TOL, LAW_TOL, TERMINAL_TOL};
use crate::solver::{Extremal, SolveOptions, coarse_grid, search_coarse, solve};
use nalgebra::Vector2;
use purcell_core::Swimmer;

/// The small problem: the displacement `ḡ = (0.001, 0, 0)` in `T = 10 s` of `h = 0.01 s`,
/// otherwise the paper's, with the joint limit `alpha_max`.
pub fn small(alpha_max: Option<f64>) -> Problem {
    Problem::new(&Spec {
        target: [0.001, 0.0, 0.0],
        horizon: 10.0,
        step: 0.01,
        alpha_max,
        ..Spec::default()
    })
    .expect("the small problem is valid")
}

/// The extremal the default solve returns for `problem`.
///
/// # Panics
/// If the solve returns none.
pub fn cheapest(problem: &Problem) -> Extremal {
    let s = solve(problem, &SolveOptions::default(), &|| {}).expect("the problem solves");
    s.extremals[s.best].clone()
}

/// Checks that the global search of `problem` with each seed of `seeds` finds the same
/// cheapest admissible coarse minimum: the same shape path as the first seed's, its cost within
/// `error` (relative) of `cheapest`, the problem's cost on its own grid (`name` in the
/// messages).
///
/// # Panics
/// If a seed finds no admissible minimum, or the seeds disagree.
pub fn seeds_agree(
    name: &str,
    problem: &Problem,
    seeds: core::ops::Range<u64>,
    cheapest: f64,
    error: f64,
) {
    let h = coarse_grid(problem, &SolveOptions::default())
        .expect("the coarse grid")
        .h();
    let mut first: Option<Vec<Vector2<f64>>> = None;
    for seed in seeds {
        let options = SolveOptions {
            seed,
            ..SolveOptions::default()
        };
        let found = search_coarse(problem, &options, &|| {}).expect("the search runs");
        let b = (found.candidates.iter())
            .find(|c| problem.admits(c.max_abs_alpha))
            .unwrap_or_else(|| panic!("{name}, seed {seed}: no admissible minimum"));
        assert!(
            (b.cost / cheapest - 1.0).abs() <= error,
            "{name}, seed {seed}: cheapest admissible coarse minimum {} (the problem's {cheapest})",
            b.cost
        );
        let u = first.get_or_insert_with(|| b.u.clone());
        assert!(
            same_path(&b.u, u, h),
            "{name}: seed {seed} vs the first seed"
        );
    }
}

/// Checks what a returned extremal `x` of `problem` must satisfy (`name` in the messages):
/// admissible, a strict local minimum, its terminal defect (the direct method's and through
/// the core's kinematics) within [`TERMINAL_TOL`], KKT within [`KKT_TOL`], the core's law
/// within [`LAW_TOL`], the joint limit's multipliers `η ≥ 0` on its arcs (none without), and
/// with a `reference` cost, at most that (to 1e-6 relative).
///
/// # Panics
/// On the first condition that fails.
pub fn check_extremal(name: &str, problem: &Problem, x: &Extremal, reference: Option<f64>) {
    assert!(x.admissible, "{name}");
    assert!(problem.admits(x.max_abs_alpha), "{name}");
    if x.arcs.is_empty() {
        assert!(x.min_eta.is_none(), "{name}");
    } else {
        let eta = x.min_eta.expect("arcs, so multipliers");
        assert!(
            eta >= 0.0,
            "{name}: a joint-limit multiplier is negative: {eta}"
        );
    }
    if let Some(r) = reference {
        assert!(
            x.cost <= r * (1.0 + 1e-6) + 1e-15,
            "{name}: cost {} above the reference {r}",
            x.cost
        );
    }
    let kkt = x.kkt_residual.expect("admissible, so checked");
    let term = x.terminal_residual.expect("admissible, so checked");
    let law = x.law_residual.expect("admissible, so checked");
    assert!(
        x.residual <= TERMINAL_TOL && term <= TERMINAL_TOL,
        "{name}: {x:?}"
    );
    assert!(kkt <= KKT_TOL, "{name}: kkt {kkt}");
    assert!(
        law <= LAW_TOL,
        "{name}: the core's law is off the controls by {law}"
    );
    assert!(
        x.local_min,
        "{name}: returned extremal is not a strict local minimum"
    );
}

/// The power `P(α, u)` the fluid dissipates, from the links' velocities directly (MODEL.md §2,
/// §11): `ξ = −A(α)u` from the core's closed-form connection, each link's centre velocity and
/// turning rate, `Σ_links k·l·v∥² + r·k·l·v⊥² + r·k·l³/12·w²`.
///
/// # Panics
/// If the connection cannot be computed at `α`.
pub fn dissipated(sw: &Swimmer<f64>, alpha: &Vector2<f64>, u: &Vector2<f64>) -> f64 {
    let xi = -(sw.connection(alpha).expect("an admissible shape") * u);
    let [l0, l1, l2] = sw.lengths();
    let (k, r) = (sw.drag(), sw.ratio());
    let (a1, a2) = (alpha.x, alpha.y);
    // Length, centre, the centre's velocity from the joint, direction angle, joint rate.
    let links = [
        (l0, (0.0, 0.0), (0.0, 0.0), 0.0, 0.0),
        (
            l1,
            (l0 / 2.0 + l1 / 2.0 * a1.cos(), l1 / 2.0 * a1.sin()),
            (-l1 / 2.0 * a1.sin() * u.x, l1 / 2.0 * a1.cos() * u.x),
            a1,
            u.x,
        ),
        (
            l2,
            (-l0 / 2.0 - l2 / 2.0 * a2.cos(), -l2 / 2.0 * a2.sin()),
            (l2 / 2.0 * a2.sin() * u.y, -l2 / 2.0 * a2.cos() * u.y),
            a2,
            u.y,
        ),
    ];
    links
        .into_iter()
        .map(|(l, c, dc, phi, rate)| {
            let v = (xi.x - xi.z * c.1 + dc.0, xi.y + xi.z * c.0 + dc.1);
            let par = v.0 * phi.cos() + v.1 * phi.sin();
            let perp = -v.0 * phi.sin() + v.1 * phi.cos();
            let w = xi.z + rate;
            k * l * par * par + r * k * l * perp * perp + r * k * l.powi(3) / 12.0 * w * w
        })
        .sum()
}
