//! Warm starts: a known extremal (`solve --from`) carried to a new problem by Newton and
//! natural-parameter continuation in the target (`through_medium`); under a joint limit,
//! where that fails, by the refinement straight from the gait (`straight_in`).

use crate::problem::Problem;
use crate::solver::constraints::joint_limit::Limits;
use crate::solver::costate;
use crate::solver::direct;
use crate::solver::grid::{self, Grid, Point};
use crate::solver::homotopy;
use crate::solver::progress::Progress;
use crate::solver::refinement::{extremal, refine};
use crate::solver::settings::{
    self, FINE_TAUS, MIN_WALK_STEP, Settings, SolveOptions, WARM_INSIDE,
};
use crate::solver::solution::{Extremal, Solution, SolveError, Trajectory};
use crate::solver::stage::{Rule, StageState};
use nalgebra::{Vector2, Vector3, Vector5};

/// A known extremal as a start: its controls on its own grid, its horizon and terminal
/// multiplier.
#[derive(Clone, Debug)]
pub struct Warm {
    /// Controls `u_0 … u_{N−1}`.
    pub u: Vec<Vector2<f64>>,
    /// Its horizon `T`.
    pub horizon: f64,
    /// `ν` (coordinates `(α, x, y, θ)`).
    pub nu: Vector5<f64>,
    /// Its target `ḡ`.
    pub target: Vector3<f64>,
}

impl Warm {
    /// From a trajectory with its costates (e.g. a replayed costate file) and `μ`.
    pub fn from_trajectory(t: &Trajectory, mu: &Vector3<f64>, horizon: f64) -> Option<Self> {
        let (end, xi) = (t.states.last()?, t.xis.last()?);
        let s = StageState::new(
            end.alpha.x,
            end.alpha.y,
            end.g.x(),
            end.g.y(),
            end.g.theta(),
        );
        Some(Warm {
            u: t.controls.clone(),
            horizon,
            nu: costate::multiplier(mu, xi, &s),
            target: Vector3::new(s[2], s[3], s[4]),
        })
    }

    /// The start on `grid` (a grid of `problem` over horizon `horizon`).
    fn point(&self, grid: &Grid, horizon: f64) -> Result<Point, purcell_core::Error> {
        let scale = self.horizon / horizon;
        let u = grid::prolong(&self.u, grid.steps)
            .into_iter()
            .map(|v| v * scale)
            .collect();
        Point::new(grid, u, self.nu * scale)
    }
}

/// Why a warm start reached nothing: Newton's smallest terminal defect.
fn unreachable(best_residual: f64) -> SolveError {
    SolveError::Unreachable { best_residual }
}

/// The extremal of `problem` reached from `warm` (see the module docs).
pub fn continue_to(problem: &Problem, warm: &Warm) -> Result<Extremal, SolveError> {
    continue_to_pulsed(problem, warm, &|| ())
}

/// [`continue_to`], calling `pulse` before each Newton iteration (where the work may be
/// cancelled).
fn continue_to_pulsed(
    problem: &Problem,
    warm: &Warm,
    pulse: &dyn Fn(),
) -> Result<Extremal, SolveError> {
    let horizon = problem.horizon();
    // Directly on the problem's own grid (without a joint limit).
    let fine = Grid::new(problem, problem.steps as usize, Rule::LEFT_POINT)
        .map_err(|_| unreachable(f64::INFINITY))?;
    if problem.alpha_max.is_none()
        && let Ok(p) = warm.point(&fine, horizon)
    {
        let settings = Settings::fine(problem, &p.u);
        if let Ok(run) = direct::newton_pulsed(&fine, p, &settings, pulse)
            && run.converged()
            && problem.admits(grid::max_abs_alpha(&run.point.states))
        {
            return Ok(extremal(problem, &fine, &run));
        }
    }
    let medium = through_medium(problem, warm, pulse);
    match (problem.alpha_max, medium) {
        (Some(alpha_max), Err(e)) => straight_in(problem, warm, alpha_max, pulse).map_err(|_| e),
        (_, reached) => reached,
    }
}

/// Natural-parameter continuation in the target on a medium grid (with a joint limit, from
/// the warm gait pulled within it, [`within_limit`]), then the refinement to the problem's
/// grid.
fn through_medium(
    problem: &Problem,
    warm: &Warm,
    pulse: &dyn Fn(),
) -> Result<Extremal, SolveError> {
    let horizon = problem.horizon();
    let steps = (problem.steps as usize).min(1024);
    let mut medium = Grid::mimic(problem, steps).map_err(|_| unreachable(f64::INFINITY))?;
    let mut point = warm
        .point(&medium, horizon)
        .map_err(|_| unreachable(f64::INFINITY))?;
    let settings = Settings::warm(problem.alpha_max.is_some());
    if let Some(a) = problem.alpha_max {
        point = within_limit(problem, warm, &medium, point, a, &settings, pulse)?;
        medium.limits = Limits::Barrier {
            alpha_max: a,
            tau: settings::COARSE_TAU,
        };
    }
    let point = walk(problem, warm.target, &medium, point, &settings, pulse)?;
    let (fine, run) = refine(problem, &point.u, &point.nu, f64::INFINITY, pulse)
        .map_err(|stop| unreachable(stop.defect()))?;
    Ok(extremal(problem, &fine, &run))
}

/// With a joint limit `alpha_max`, where [`through_medium`] fails: the warm gait's own
/// controls clipped to within the share `τ₀ =` [`FINE_TAUS`]`[0]` of the limit and carried by
/// the refinement straight to the problem's grid, its barrier path from `τ₀` and active set
/// there ([`refine`]). Another time step or horizon changes a gait on many arcs of a tight
/// limit more than the medium grid's barrier at its last weight follows: `--alpha-max 1
/// --links 1,0.93,0.93 --target 0.144,0.023,-0.44` from its gait of `--step 0.1` (7.8450051,
/// 16 arcs) to `--step 0.05`: the medium route stalls, this one reaches 8.6260113 in 12
/// Newton iterations at the last weight (the global search there returns 14.7280354). The
/// barrier's minimiser at `τ` rests about `τ/η` from the limit on an arc: clipped to within
/// 1e-4 … 1e-7 of it, the path converges; to within [`WARM_INSIDE`] (1e-3) its first
/// weight stalls (300 iterations, stationarity 4e-4), the on-arc states too far out.
fn straight_in(
    problem: &Problem,
    warm: &Warm,
    alpha_max: f64,
    pulse: &dyn Fn(),
) -> Result<Extremal, SolveError> {
    let horizon = problem.horizon();
    let scale = warm.horizon / horizon;
    let u: Vec<Vector2<f64>> = warm.u.iter().map(|v| v * scale).collect();
    let h = horizon / u.len() as f64;
    let bound = (1.0 - FINE_TAUS[0]) * alpha_max;
    let u = homotopy::clip_into(&u, &problem.alpha0, bound, h);
    let (fine, run) = refine(problem, &u, &(warm.nu * scale), f64::INFINITY, pulse)
        .map_err(|stop| unreachable(stop.defect()))?;
    Ok(extremal(problem, &fine, &run))
}

/// With a joint limit `alpha_max`: the warm start `point` on `medium` pulled just inside it
/// (a gait on arcs of the limit rests on it) and to the barrier's minimum at its own target
/// and the search's last weight; the walk then keeps that weight, its steps stopping short
/// of the limit. `pulse` before each Newton iteration.
fn within_limit(
    problem: &Problem,
    warm: &Warm,
    medium: &Grid,
    point: Point,
    alpha_max: f64,
    settings: &Settings,
    pulse: &dyn Fn(),
) -> Result<Point, SolveError> {
    let own = medium.aiming_at(&warm.target);
    // A warm gait within the limit (on arcs of it or inside) is nearly the barrier's
    // minimum: its last weight only. One beyond it is shrunk into it and walks the path.
    let within = problem.admits(grid::max_abs_alpha(&point.states));
    let (inside, path): (_, &[f64]) = if within {
        let bound = (1.0 - WARM_INSIDE) * alpha_max;
        let u = homotopy::clip_into(&point.u, &problem.alpha0, bound, medium.h());
        (u, &[settings::COARSE_TAU])
    } else {
        let u = homotopy::shrink_into(point.u, &problem.alpha0, alpha_max, medium.h());
        (u, settings::coarse_path(0))
    };
    let start = Point::new(&own, inside, point.nu).map_err(|_| unreachable(f64::INFINITY))?;
    let run = homotopy::walk(&own, alpha_max, path, start, settings, pulse)
        .map(|w| w.run)
        .map_err(|_| unreachable(f64::INFINITY))?;
    if run.converged() {
        Ok(run.point)
    } else {
        Err(unreachable(run.defect))
    }
}

/// Natural-parameter continuation on `medium` from `point` (an extremal at the target
/// `from`) to the problem's target: steps of the way that grow by half on success and halve
/// on failure, every accepted point admissible; the point at the problem's target, or why
/// the walk stopped (its step below [`MIN_WALK_STEP`]). `pulse` before each Newton iteration.
fn walk(
    problem: &Problem,
    from: Vector3<f64>,
    medium: &Grid,
    mut point: Point,
    settings: &Settings,
    pulse: &dyn Fn(),
) -> Result<Point, SolveError> {
    let to = problem.target;
    let (mut s, mut ds) = (0.0f64, 0.25f64);
    let mut best_residual = f64::INFINITY;
    // The smallest largest |α_i| of the converged steps refused for leaving the admissible
    // shapes: why the walk stopped, if it did there.
    let mut left = f64::INFINITY;
    while s < 1.0 {
        if ds < MIN_WALK_STEP {
            return Err(if left.is_finite() {
                SolveError::NoneAdmissible {
                    found: 1,
                    best_alpha: left,
                }
            } else {
                unreachable(best_residual)
            });
        }
        let next = (s + ds).min(1.0);
        let grid = medium.aiming_at(&(from + (to - from) * next));
        let start =
            Point::new(&grid, point.u.clone(), point.nu).map_err(|_| unreachable(best_residual))?;
        match direct::newton_pulsed(&grid, start, settings, pulse) {
            Ok(run)
                if run.converged() && problem.admits(grid::max_abs_alpha(&run.point.states)) =>
            {
                point = run.point;
                s = next;
                ds *= 1.5;
            }
            Ok(run) => {
                if run.converged() {
                    left = left.min(grid::max_abs_alpha(&run.point.states));
                } else {
                    best_residual = best_residual.min(run.defect);
                }
                ds *= 0.5;
            }
            Err(_) => ds *= 0.5,
        }
    }
    Ok(point)
}

/// `solve --from`: the extremal reached from a stored one, as a solution of one extremal;
/// or, if none is reached within the admissible shapes, the global search's solution
/// ([`crate::solver::solve`], with `options` and `progress`) and why the warm start failed. The
/// continuation is `progress`'s phase `continuation`, one tick, pulsing within.
pub fn solve_from(
    problem: &Problem,
    warm: &Warm,
    options: &SolveOptions,
    progress: &dyn Progress,
) -> (Result<Solution, SolveError>, Option<SolveError>) {
    progress.phase("continuation", 1, "extremal");
    let reached = continue_to_pulsed(problem, warm, &|| progress.pulse()).and_then(|x| {
        if x.admissible {
            Ok(x)
        } else {
            Err(SolveError::NoneAdmissible {
                found: 1,
                best_alpha: x.max_abs_alpha,
            })
        }
    });
    progress.tick();
    match reached {
        Ok(x) => (
            Ok(Solution {
                best: 0,
                extremals: vec![x],
                search: None,
                flown: None,
                recentred: false,
            }),
            None,
        ),
        Err(e) => (crate::solver::solve(problem, options, progress), Some(e)),
    }
}
