//! The joint limit `|α_{k,i}| ≤ α_max` as a state constraint (MODEL.md §9).
//!
//! 1. **Interior point.** The direct method with a logarithmic barrier ([`Limits::Barrier`]):
//!    from strictly feasible starts ([`shrink_into`], [`clip_into`]), Newton at decreasing
//!    weights `τ` ([`walk`]); the barrier's minimisers approach the constrained
//!    minimum, resting a distance `O(τ)` from the limit where it is active. Line-search
//!    trials past the limit are skipped without a rollout; in the refinement every step also
//!    stops at the fraction to the boundary ([`Settings::fraction_to_boundary`]). The search
//!    does without the fraction rule: its plain steps, pinning states to the limit, reach the
//!    cheapest basin at `α_max = 1.5` from 15 of 160 starts, the rule's from none.
//! 2. **Active set.** The stretches within [`NEAR`] of the limit become arcs ([`arcs_of`];
//!    within [`LOOSE_NEAR`] if the rounds from those fail);
//!    the problem with the limit imposed exactly on them ([`Limits::Arcs`]: controls fixed
//!    inside an arc, the entry control set by the state) is solved by Newton
//!    ([`polish`]), which returns the multipliers `η_k` of the limit with it (the jumps of
//!    the shape costate). A state that leaves the limit elsewhere adds an arc; an arc state
//!    with `η_k < 0` leaves it; repeat.
//!
//! The result is a KKT point of the constrained problem: stationarity in every free
//! control, the limit active with `η ≥ 0` on the arcs and inactive elsewhere.

use super::constraints::joint_limit::{Limits, arcs_of, merged};
use super::direct::{self, Run};
use super::grid::{self, Grid, Point};
use super::settings::{
    ETA_ROUNDING, LOOSE_NEAR, NEAR, PAST_LIMIT, PATIENCE, QUICK_PATIENCE, ROUNDS, SHRINK, Settings,
};
use nalgebra::Vector2;
use purcell_core::{Arc, Error};

/// The controls `u` (from `ᾱ`) with their shape path shrunk about `ᾱ` so that it stays within
/// [`SHRINK`] of the limit.
pub fn shrink_into(
    u: Vec<Vector2<f64>>,
    alpha0: &Vector2<f64>,
    alpha_max: f64,
    h: f64,
) -> Vec<Vector2<f64>> {
    let reach = grid::shape_reach(&u, h);
    let room = SHRINK * alpha_max - alpha0.amax();
    if reach <= room || room <= 0.0 {
        return u;
    }
    let f = room / reach;
    u.into_iter().map(|v| v * f).collect()
}

/// The controls `u` (from `ᾱ`) with their shape path clipped to `|α_i| ≤ bound` (the last
/// state, `ᾱ`, kept): a path on the limit pulled just inside it, the rest unchanged.
pub fn clip_into(
    u: &[Vector2<f64>],
    alpha0: &Vector2<f64>,
    bound: f64,
    h: f64,
) -> Vec<Vector2<f64>> {
    let n = u.len();
    let mut alpha = *alpha0;
    let mut prev = *alpha0;
    u.iter()
        .enumerate()
        .map(|(k, v)| {
            alpha += v * h;
            let next = if k + 1 == n {
                alpha
            } else {
                alpha.map(|x| x.clamp(-bound, bound))
            };
            let w = (next - prev) / h;
            prev = next;
            w
        })
        .collect()
}

/// Where a barrier path ended ([`walk`]).
#[derive(Clone, Debug)]
pub struct Walk {
    /// The run at the last weight tried: the path's end if it converged.
    pub run: Run,
    /// If `run` did not converge: the index in the path of the last weight that did, and its
    /// run (`None` if the first weight did not).
    pub reached: Option<(usize, Run)>,
    /// Whether [`walk_watched`]'s watch ended the path early, at `run`'s weight.
    pub cut: bool,
}

/// Newton on `grid` with the barrier at each weight of `taus` in turn, each from the last
/// (`pulse` before each Newton iteration; each weight but the last to
/// [`super::settings::BARRIER_KAPPA`] times itself, [`Settings::at_weight`]), up to the last
/// weight or the first that did not converge, keeping the run at the last weight that
/// converged when a later one stalls (as Newton can at the smallest weights, where the
/// barrier's Hessian `τ/d²` is largest and the line search stops on rounding).
pub fn walk(
    grid: &Grid,
    alpha_max: f64,
    taus: &[f64],
    start: Point,
    settings: &Settings,
    pulse: &dyn Fn(),
) -> Result<Walk, Error> {
    walk_watched(
        grid,
        alpha_max,
        taus,
        start,
        settings,
        pulse,
        &mut |_, _| false,
    )
}

/// [`walk`], showing `watch` the point each weight converged to (with the weight's index in
/// `taus`); the path ends there ([`Walk::cut`]) once `watch` returns true.
pub fn walk_watched(
    grid: &Grid,
    alpha_max: f64,
    taus: &[f64],
    start: Point,
    settings: &Settings,
    pulse: &dyn Fn(),
    watch: &mut dyn FnMut(usize, &Point) -> bool,
) -> Result<Walk, Error> {
    let path = (alpha_max, taus);
    walk_on(grid, path, (start, None), settings, pulse, watch)
}

/// [`walk_watched`] along `(alpha_max, taus)` from `point`, after the weights up to the index
/// of `reached` (if any: its run), which converged.
fn walk_on(
    grid: &Grid,
    (alpha_max, taus): (f64, &[f64]),
    (mut point, mut reached): (Point, Option<(usize, Run)>),
    settings: &Settings,
    pulse: &dyn Fn(),
    watch: &mut dyn FnMut(usize, &Point) -> bool,
) -> Result<Walk, Error> {
    let first = reached.as_ref().map_or(0, |(i, _)| i + 1);
    for (i, &tau) in taus.iter().enumerate().skip(first) {
        let g = barrier_grid(grid, alpha_max, tau);
        // The bound multipliers of a primal–dual path go on to the next weight, as IPOPT's do.
        let p = Point {
            z: point.z.clone(),
            ..Point::new(&g, point.u.clone(), point.nu)?
        };
        let at = settings.at_weight(tau, i + 1 == taus.len());
        let run = direct::newton_pulsed(&g, p, &at, pulse)?;
        if !run.converged() {
            return Ok(Walk {
                run,
                reached,
                cut: false,
            });
        }
        if watch(i, &run.point) {
            return Ok(Walk {
                run,
                reached: None,
                cut: true,
            });
        }
        point = run.point.clone();
        reached = Some((i, run));
    }
    let (_, run) = reached.ok_or(Error::NonFinite)?;
    Ok(Walk {
        run,
        reached: None,
        cut: false,
    })
}

/// `grid` with the barrier of weight `tau`.
fn barrier_grid(grid: &Grid, alpha_max: f64, tau: f64) -> Grid {
    let mut g = grid.clone();
    g.limits = Limits::Barrier { alpha_max, tau };
    g
}

/// Why [`polish`] gave up.
#[derive(Clone, Debug)]
pub enum PolishError {
    /// Newton failed (a rollout or a step could not be computed).
    Failed,
    /// Newton did not converge: its run.
    NotConverged(Box<Run>),
    /// The active set did not settle within the rounds allowed.
    Unsettled,
}

/// The constrained extremal near `start` on `grid`: active-set rounds of Newton with the
/// limit imposed on the arcs (see the module docs), the first arcs the stretches of `start`
/// within [`NEAR`] of the limit; if Newton does not converge from them or the rounds do not
/// settle, once more from the stretches within [`LOOSE_NEAR`]` · α_max` (the first failure is
/// returned if that fails too). Returns the grid (with its final arcs) and the run.
///
/// At a barrier weight `τ` a state on an arc rests `τ/η_k` from the limit, and towards an
/// arc's ends `η_k` falls to 0: the states there may lie beyond [`NEAR`], and Newton with
/// arcs that short can fail to converge at all, so that no round follows to lengthen them.
/// Seen with `--step 0.05 --alpha-max 1 --links 1,0.93,0.93 --target 0.144,0.023,-0.44` from
/// the gait of `--step 0.1` (`solve --from`): the barrier path on the problem's 2 000 steps
/// converged (J 8.626016), the rounds from [`NEAR`] stopped with defect 2.2e-3 after 30
/// iterations, and from [`LOOSE_NEAR`] they settle 16 arcs in one round (two Newton
/// iterations), 8.6260113.
pub fn polish(
    grid: &Grid,
    alpha_max: f64,
    start: &Point,
    settings: &Settings,
    pulse: &dyn Fn(),
) -> Result<(Grid, Run), PolishError> {
    rounds(grid, alpha_max, start, NEAR, settings, pulse).or_else(|first| {
        rounds(
            grid,
            alpha_max,
            start,
            LOOSE_NEAR * alpha_max,
            settings,
            pulse,
        )
        .map_err(|_| first)
    })
}

/// [`polish`]'s active-set rounds from the stretches of `start` within `near` of the limit.
fn rounds(
    grid: &Grid,
    alpha_max: f64,
    start: &Point,
    near: f64,
    settings: &Settings,
    pulse: &dyn Fn(),
) -> Result<(Grid, Run), PolishError> {
    let mut arcs = arcs_of(&start.states, alpha_max, near);
    let mut point = start.clone();
    for _ in 0..ROUNDS {
        let mut g = grid.clone();
        g.limits = Limits::Arcs {
            alpha_max,
            arcs: arcs.clone(),
        };
        let alpha0 = Vector2::new(g.start[0], g.start[1]);
        let start = Point::new(&g, g.limits.snap(&point.u, alpha0, g.h()), point.nu)
            .map_err(|_| PolishError::Failed)?;
        let r =
            direct::newton_pulsed(&g, start, settings, pulse).map_err(|_| PolishError::Failed)?;
        if !r.converged() {
            return Err(PolishError::NotConverged(Box::new(r)));
        }
        // States beyond the limit off the arcs, and arc states with η < 0.
        let states = &r.point.states;
        let n = states.len() - 1;
        let eta = |k: u32, a: &Arc| f64::from(a.sign) * r.jumps[k as usize][a.index()];
        let scale = arcs
            .iter()
            .flat_map(|a| (a.first..=a.last).map(move |k| (k, a)))
            .fold(0.0f64, |m, (k, a)| m.max(eta(k, a).abs()));
        let violated: Vec<Arc> = arcs_of(states, alpha_max, -PAST_LIMIT * alpha_max)
            .into_iter()
            .filter(|v| {
                !arcs.iter().any(|a| {
                    a.joint == v.joint && a.sign == v.sign && a.first <= v.first && v.last <= a.last
                })
            })
            .collect();
        let mut released = Vec::new();
        for a in &arcs {
            // Keep the stretches of the arc where η ≥ 0 (to rounding).
            let mut k = a.first;
            while k <= a.last {
                if eta(k, a) >= -ETA_ROUNDING * scale {
                    let first = k;
                    while k < a.last && eta(k + 1, a) >= -ETA_ROUNDING * scale {
                        k += 1;
                    }
                    released.push(Arc {
                        first,
                        last: k,
                        ..*a
                    });
                }
                k += 1;
            }
        }
        let inside = arcs.iter().all(|a| a.check(n as u32).is_ok());
        let settled = violated.is_empty() && released == arcs && inside;
        if settled {
            return Ok((g, r));
        }
        released.extend(violated);
        arcs = merged(released);
        point = r.point;
    }
    Err(PolishError::Unsettled)
}

/// The steps of a refinement's barrier path on one grid ([`patient_barrier_path`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Steps {
    /// Primal steps, each stopped at the fraction to the boundary.
    Primal,
    /// Primal–dual steps ([`Settings::primal_dual`]).
    PrimalDual,
    /// Primal steps for [`QUICK_PATIENCE`] iterations per weight, then, where those do not
    /// converge, primal–dual ones with the second patience.
    PrimalThenDual,
}

/// The refinement's barrier path on one grid: [`walk`] through `taus` with
/// [`Settings::barrier`] (every step stopped at the fraction to the boundary: from a
/// prolonged coarse solution, unguarded steps pin states to the limit and Newton stalls
/// there), the first of [`PATIENCE`] iterations per weight, then a second patience if that
/// does not converge. The second path's runs up to the weight where the first stalled are the
/// first's (they converged within fewer iterations), so it goes on from there: that weight's
/// run resumed ([`direct::resume`], the same iterates as a run started with the second
/// patience), then the smaller weights. `steps`: which steps ([`Steps`]; with
/// [`Steps::PrimalThenDual`] the first patience is [`QUICK_PATIENCE`] and the resumed run
/// takes primal–dual steps), and the second patience (usually `PATIENCE[1]`).
pub fn patient_barrier_path(
    grid: &Grid,
    (alpha_max, taus): (f64, &[f64]),
    start: Point,
    (steps, patience): (Steps, usize),
    pulse: &dyn Fn(),
) -> Result<Walk, Error> {
    let settings =
        |patience, primal_dual| Settings::barrier(patience).with_primal_dual(primal_dual);
    let first_patience = if steps == Steps::PrimalThenDual {
        QUICK_PATIENCE
    } else {
        PATIENCE[0]
    };
    let first_settings = settings(first_patience, steps == Steps::PrimalDual);
    let first = walk(grid, alpha_max, taus, start, &first_settings, pulse)?;
    if first.run.converged() {
        return Ok(first);
    }
    let patient = settings(patience, steps != Steps::Primal);
    let stalled = first.reached.as_ref().map_or(0, |(i, _)| i + 1);
    let g = barrier_grid(grid, alpha_max, taus[stalled]);
    let at = patient.at_weight(taus[stalled], stalled + 1 == taus.len());
    let run = direct::resume(&g, first.run, &at, pulse)?;
    if !run.converged() {
        return Ok(Walk {
            run,
            reached: first.reached,
            cut: false,
        });
    }
    let point = run.point.clone();
    let path = (alpha_max, taus);
    let from = (point, Some((stalled, run)));
    walk_on(grid, path, from, &patient, pulse, &mut |_, _| false)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::{Problem, Spec};
    use crate::solver::settings::{BARRIER_KAPPA, TOL_DEFECT};
    use crate::solver::stage::Rule;
    use nalgebra::Vector5;

    /// A weight of a path but the last is solved only to `κ·τ`: from a circle shrunk into
    /// `α_max = 1.5`, the point at `τ = 1e-2` still misses the target by more than the
    /// tolerance of the last weight, which the path's end meets.
    #[test]
    fn only_the_last_weight_of_a_path_is_solved_to_the_runs_tolerances() {
        let settings = Settings::search(PATIENCE[1], true);
        let mid = settings.at_weight(1e-2, false);
        assert_eq!(
            (mid.tol_defect, mid.tol_kkt),
            (BARRIER_KAPPA * 1e-2, BARRIER_KAPPA * 1e-2)
        );
        assert_eq!(settings.at_weight(1e-2, true), settings);
        let p = Problem::new(&Spec {
            alpha_max: Some(1.5),
            ..Spec::default()
        })
        .unwrap();
        let grid = Grid::new(&p, 64, Rule::LEFT_POINT).unwrap();
        let u: Vec<Vector2<f64>> = (0..64)
            .map(|k| {
                let phi = core::f64::consts::TAU * k as f64 / 64.0;
                Vector2::new(-phi.sin(), phi.cos()) * 0.3
            })
            .collect();
        let u = shrink_into(u, &Vector2::zeros(), 1.5, grid.h());
        let start = Point::new(&grid, u, Vector5::zeros()).unwrap();
        let mut defects = Vec::new();
        let mut watch = |_: usize, q: &Point| {
            defects.push(grid.terminal.defect(&q.states).amax());
            false
        };
        let taus = [1e-2, 1e-6];
        let w = walk_watched(&grid, 1.5, &taus, start, &settings, &|| (), &mut watch).unwrap();
        assert!(w.run.converged(), "{:?}", w.run.status);
        assert_eq!(defects.len(), 2);
        assert!(
            defects[0] > TOL_DEFECT && defects[0] <= BARRIER_KAPPA * 1e-2,
            "{defects:?}"
        );
        assert!(defects[1] <= TOL_DEFECT, "{defects:?}");
    }

    #[test]
    fn clipping_keeps_the_path_inside_and_the_loop_closed() {
        let h = 0.5;
        let alpha0 = Vector2::new(0.2, -0.1);
        let u: Vec<Vector2<f64>> = (0..40)
            .map(|k| {
                let t = core::f64::consts::TAU * k as f64 / 40.0;
                Vector2::new(t.cos(), (2.0 * t).cos()) * 0.4
            })
            .collect();
        let clipped = clip_into(&u, &alpha0, 1.0, h);
        let (mut a, mut b) = (alpha0, alpha0);
        let mut touched = false;
        for (k, (v, w)) in u.iter().zip(&clipped).enumerate() {
            a += v * h;
            b += w * h;
            if k + 1 < u.len() {
                assert!(b.amax() <= 1.0 + 1e-15, "{k}: {b}");
                touched |= a.amax() > 1.0;
                if a.amax() <= 1.0 {
                    assert!((a - b).amax() <= 1e-14, "{k}: inside, unchanged");
                }
            }
        }
        assert!(touched, "the test path must cross the bound");
        assert!((a - b).amax() <= 1e-14, "the loop closes where it did");
    }
}
