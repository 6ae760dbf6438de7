//! The refinement: the search's candidates carried from the coarse grid to the problem's
//! own, through grids at most 16 times finer each, Newton converging in a few steps at each
//! (with a joint limit, the barrier path and then the active set, [`homotopy`]); the
//! fine extremals with their certificates, cheapest first.

use super::constraints::joint_limit::Limits;
use super::cost::{Costs, StageCost};
use super::direct::{self, Run};
use super::grid::{self, Grid, Point};
use super::homotopy::{self, PolishError};
use super::progress::Progress;
use super::search;
use super::settings::{
    COARSE_ALPHA_ERROR, COARSE_COST_ERROR, FINE_TAUS, LIMITED_COARSE_COST_ERROR, PATIENCE, PRUNE,
    RESCUE_TAUS, Settings, SolveOptions, UNRESOLVED,
};
use super::solution::{Extremal, Minimum, SolveError, Unrefined};
use super::{certificate, costate, symmetry};
use crate::problem::{Cost, OVERLAP, Problem};
use nalgebra::{Vector2, Vector5};

/// Controls on a grid.
type Controls = Vec<Vector2<f64>>;

/// Why a refinement stopped short of the problem's grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stop {
    /// Newton did not converge on a grid: the terminal defect where it stopped.
    Defect(f64),
    /// Newton met the terminal defect on a grid but not stationarity: the defect and the
    /// stationarity residual where it stopped (seen on tiny targets, whose coarse minima lie
    /// in one flat valley).
    Stationarity {
        /// The terminal defect, within its tolerance.
        defect: f64,
        /// The stationarity residual, above its tolerance.
        stationarity: f64,
    },
    /// On an intermediate grid the extremal already cost more than the bound.
    Dearer,
    /// On an intermediate grid the path was one that an earlier refinement of the same
    /// solve carried on to an extremal ([`refine_candidates`]).
    Repeat,
}

impl Stop {
    /// The terminal defect where it stopped (0 for [`Stop::Dearer`] and [`Stop::Repeat`],
    /// which converged).
    pub fn defect(self) -> f64 {
        match self {
            Stop::Defect(d) | Stop::Stationarity { defect: d, .. } => d,
            Stop::Dearer | Stop::Repeat => 0.0,
        }
    }
}

/// Carries controls `u` (on any grid over the same horizon) with multiplier `nu` to the
/// problem's grid, through grids at most 16 times finer each ([`finer_grid`]), Newton
/// converging at each. With a joint limit, the first finer grid runs the barrier path
/// [`FINE_TAUS`] and the others only its last weight ([`homotopy::patient_barrier_path`]; if a
/// smaller weight stalls, the path goes on from the last weight reached; if the first stalls
/// near the start, the path runs again from larger weights), and on the problem's grid the
/// active-set rounds impose the limit on its arcs ([`homotopy::polish`]). Gives up with
/// [`Stop::Dearer`] once an intermediate grid's cost exceeds `bound` (`f64::INFINITY`: never).
/// `pulse` is called on each grid and before each Newton iteration.
pub fn refine(
    problem: &Problem,
    u: &[Vector2<f64>],
    nu: &Vector5<f64>,
    bound: f64,
    pulse: &dyn Fn(),
) -> Result<(Grid, Run), Stop> {
    carry(problem, u, nu, bound, &[], pulse).map(|(grid, run, _)| (grid, run))
}

/// [`refine`], which also gives up with [`Stop::Repeat`] once an intermediate grid's path is
/// one of `known` (to [`grid::same_path`]): a path there that an earlier refinement carried
/// on to the problem's grid leads to the extremal it reached. Also gives the paths of its own
/// intermediate grids. Under a joint limit many coarse minima meet on the first finer grid
/// (`α_max = 1.1`, target (0, 0, 0.3): ten coarse minima at 1.604–1.641 all reach 1.5450974
/// on 1 024 steps and 1.5448608 on 10 000), and the problem's grid costs about three times
/// the intermediate one.
fn carry(
    problem: &Problem,
    u: &[Vector2<f64>],
    nu: &Vector5<f64>,
    bound: f64,
    known: &[Controls],
    pulse: &dyn Fn(),
) -> Result<(Grid, Run, Vec<Controls>), Stop> {
    let mut trail = Vec::new();
    let mut u = u.to_vec();
    let mut nu = *nu;
    // The index in FINE_TAUS of the weight at which the next grid's barrier path starts.
    let mut from = 0;
    // The zero control keeps every state at `ᾱ`, inside the limit: no arc to find, and the
    // barrier would push it off the zero target's exact minimum (`J = 0`).
    let barrier = problem
        .alpha_max
        .filter(|_| u.iter().any(|v| *v != Vector2::zeros()));
    loop {
        pulse();
        let inf = |_| Stop::Defect(f64::INFINITY);
        let (grid, last) = finer_grid(problem, u.len()).map_err(inf)?;
        let start = Point::new(&grid, grid::prolong(&u, grid.steps), nu).map_err(inf)?;
        let (run, tol_defect) = match barrier {
            None => {
                let settings = if last {
                    Settings::fine(problem, &start.u)
                } else {
                    Settings::INTERMEDIATE
                };
                let run = direct::newton_pulsed(&grid, start, &settings, pulse).map_err(inf)?;
                (run, settings.tol_defect)
            }
            Some(alpha_max) => {
                let (reached, run) = barrier_stage(&grid, alpha_max, from, start, pulse)?;
                from = reached;
                (run, Settings::barrier(PATIENCE[0]).tol_defect)
            }
        };
        if !run.converged() {
            return Err(stalled(&run, tol_defect));
        }
        if last {
            let Some(alpha_max) = problem.alpha_max else {
                return Ok((grid, run, trail));
            };
            let fine = Settings::fine(problem, &run.point.u);
            let polished = homotopy::polish(&grid, alpha_max, &run.point, &fine, pulse);
            return match polished {
                Ok((grid, run)) => Ok((grid, run, trail)),
                Err(PolishError::NotConverged(run)) => Err(stalled(&run, fine.tol_defect)),
                Err(PolishError::Failed | PolishError::Unsettled) => {
                    Err(Stop::Defect(f64::INFINITY))
                }
            };
        }
        if grid.cost(&run.point.u, &run.point.states) > bound {
            return Err(Stop::Dearer);
        }
        if known
            .iter()
            .any(|k| grid::same_path(k, &run.point.u, grid.h()))
        {
            return Err(Stop::Repeat);
        }
        trail.push(run.point.u.clone());
        u = run.point.u;
        nu = run.point.nu;
    }
}

/// Why the run `run`, not converged, stopped: stationarity if it met the terminal defect
/// `tol_defect`, otherwise the defect.
fn stalled(run: &Run, tol_defect: f64) -> Stop {
    if run.defect <= tol_defect {
        Stop::Stationarity {
            defect: run.defect,
            stationarity: run.kkt,
        }
    } else {
        Stop::Defect(run.defect)
    }
}

/// A refinement's barrier path on `grid` from `start` through the weights
/// `FINE_TAUS[from..]` ([`homotopy::patient_barrier_path`]): the index in [`FINE_TAUS`] of the
/// last weight that converged, with its run. If a smaller weight stalls after it, that run
/// all the same: the path is only there to find the arcs (the active set converges the
/// constrained problem itself), the next grid walks on from that weight, and the problem's
/// grid polishes from it (seen at `α_max = 140°` on the paper's target: the 1 024-step grid
/// stalled at `τ = 1e-9` with stationarity 1.8e-6 against [`super::settings::BARRIER_TOL_KKT`],
/// which dropped the cheapest gait). If the first weight stalls near the start (its cost
/// within [`COARSE_COST_ERROR`] of the start's), the path again from the weights
/// [`RESCUE_TAUS`] down ([`rescue`]); otherwise, or if that stalls too: the first
/// weight's run, not converged.
fn barrier_stage(
    grid: &Grid,
    alpha_max: f64,
    from: usize,
    start: Point,
    pulse: &dyn Fn(),
) -> Result<(usize, Run), Stop> {
    let taus = &FINE_TAUS[from..];
    let walk = homotopy::patient_barrier_path(grid, alpha_max, taus, start.clone(), pulse)
        .map_err(|_| Stop::Defect(f64::INFINITY))?;
    if walk.run.converged() {
        return Ok((FINE_TAUS.len() - 1, walk.run));
    }
    let Some((i, reached)) = walk.reached else {
        let near = grid.cost(&walk.run.point.u, &walk.run.point.states)
            <= grid.cost(&start.u, &start.states) * (1.0 + COARSE_COST_ERROR);
        if near && let Some(rescued) = rescue(grid, alpha_max, start, pulse) {
            return Ok(rescued);
        }
        return Ok((from, walk.run));
    };
    log::debug!(
        "barrier path on {} steps stalled at τ = {:e} (defect {:.1e}, stationarity {:.1e}); \
         going on from τ = {:e}",
        grid.steps,
        FINE_TAUS[from + i + 1],
        walk.run.defect,
        walk.run.kkt,
        FINE_TAUS[from + i]
    );
    Ok((from + i, reached))
}

/// The barrier path on `grid` from `start` through the larger weights [`RESCUE_TAUS`] and
/// then [`FINE_TAUS`], for a grid whose path stalled at its first weight near its start:
/// the larger weights first hold the states off the limit, where Newton converges from the
/// prolonged path, and the smaller ones bring them back (seen at `α_max = 1` on the paper's
/// target: from the coarse extremal, the 1 024-step grid stalled at `τ = 1e-6` with
/// stationarity 0.4 at a cost 0.1 % below the coarse one, and converged from `τ = 1e-4`).
/// The index in [`FINE_TAUS`] of the last weight that converged, with its run; `None` if
/// none of them did.
fn rescue(grid: &Grid, alpha_max: f64, start: Point, pulse: &dyn Fn()) -> Option<(usize, Run)> {
    let taus: Vec<f64> = RESCUE_TAUS.iter().chain(&FINE_TAUS).copied().collect();
    let walk = homotopy::patient_barrier_path(grid, alpha_max, &taus, start, pulse).ok()?;
    if walk.run.converged() {
        return Some((FINE_TAUS.len() - 1, walk.run));
    }
    let (j, reached) = walk.reached?;
    Some((j.checked_sub(RESCUE_TAUS.len())?, reached))
}

/// The next grid of a refinement from `n` steps: at most 16 times finer, with the rule that
/// mimics the problem's discretisation ([`super::stage::Rule::matching`]), or the problem's own grid
/// (`true`) once that is near enough.
pub fn finer_grid(problem: &Problem, n: usize) -> Result<(Grid, bool), purcell_core::Error> {
    let n_fine = problem.steps as usize;
    let next = if n_fine <= 16 * n { n_fine } else { 16 * n };
    Ok((Grid::mimic(problem, next)?, next == n_fine))
}

/// The extremal of a converged fine run, with its certificates.
pub fn extremal(problem: &Problem, grid: &Grid, run: &Run) -> Extremal {
    let p = &run.point;
    let trajectory = costate::trajectory(&p.states, &p.u, &run.lambda, &run.jumps);
    let n = p.u.len();
    let mu = costate::momentum(&run.lambda[n], &p.states[n]);
    let max_abs_alpha = grid::max_abs_alpha(&p.states);
    let physical = max_abs_alpha < OVERLAP;
    let check = |r: Result<f64, purcell_core::Error>| r.ok().filter(|_| physical);
    let cost = grid.cost(&p.u, &p.states);
    let costs = Cost::ALL.map(|c| Costs::of(c, problem.swimmer).value(grid.h(), &p.states, &p.u));
    let kkt = certificate::kkt(problem, &trajectory, &mu)
        .ok()
        .filter(|_| physical);
    let arcs = match &grid.limits {
        Limits::Arcs { arcs, .. } => {
            let mut arcs = arcs.clone();
            arcs.sort_by_key(|a| (a.first, a.joint));
            arcs
        }
        _ => Vec::new(),
    };
    Extremal {
        cost,
        costs,
        mu,
        xi0: trajectory.xis.first().copied().unwrap_or_default(),
        max_abs_alpha,
        admissible: problem.admits(max_abs_alpha),
        residual: run.defect,
        terminal_residual: check(certificate::terminal_residual(problem, &p.u)),
        kkt_residual: kkt.map(|k| k.residual),
        arcs,
        min_eta: kkt.and_then(|k| k.min_eta),
        stationarity: run.kkt,
        law_residual: check(certificate::law_residual(problem, &trajectory, &mu)),
        // J ≥ 0, so J = 0 is the global minimum (there the terminal constraint is degenerate
        // and the second-order test does not apply).
        local_min: run.local_min() || cost == 0.0,
        iterations: run.iterations,
        start: 0,
        hits: 0,
        twin_of: None,
        trajectory,
    }
}

/// Carries coarse `candidates` (cheapest first) to the fine grid: the index of the cheapest
/// admissible fine extremal, every distinct one refined, cheapest first, and the candidates
/// whose refinement failed or was skipped ([`Unrefined`], each also logged at `debug`).
/// `best_residual` is the search's smallest defect, for the error when no candidate was
/// tried. `progress` ticks once per candidate carried and pulses within.
///
/// Which: admissible candidates (with a margin for the coarse grid's error in `|α|`) until
/// the cheapest admissible fine extremal is settled (every remaining candidate costs more,
/// with a margin for the coarse grid's error in `J`), then the inadmissible ones cheaper
/// than it, for the report. With a joint limit, a candidate whose path the coarse grid does
/// not resolve (prolonged to the next grid, it misses the target by more than the share
/// [`UNRESOLVED`] of the displacement) comes after the others and, once they have settled an
/// admissible extremal, is skipped (that miss is its defect in the report) unless its coarse
/// cost is below that of the cheapest resolved candidate that settled one; those are tried,
/// cheapest first, until one settles a cheaper extremal (on (0, 0.1, 0) within 1.3 rad, with
/// the seed-ordered search of 5289f99, seed 0's one resolved candidate, coarse 1.5841, settled
/// 1.5707995; its cheapest unresolved one, coarse 1.5077, refined to 1.5494037). A candidate that costs more than the settled one on
/// an intermediate grid stops there ([`PRUNE`]). Each extremal is kept with its candidate's
/// coarse cost. The budget `options.refine` counts the candidates carried to a new extremal,
/// not those that reach one already found (under a joint limit many coarse minima refine to
/// the same extremal; most meet on the first finer grid and stop there, [`Stop::Repeat`]),
/// nor those pruned (a prune costs an intermediate grid, not the
/// problem's; under a joint limit the coarse costs do not order the fine ones: on (0, 0.1, 0)
/// within 1.3 rad, seven coarse minima at 1.5138–1.5203 were pruned, all of the extremal
/// 1.5526896, and used up the budget before the one at 1.5375 that refines to the cheapest,
/// 1.5258579), nor those Newton could not carry: a coarse grid can
/// hold minima of a family that has ended in a fold before the problem's grid (seen with
/// `α_max = 1.5`, `r = 2.1`: ten coarse minima at J ≈ 1.05, ν_y ≈ −46, of the family that
/// costs 0.83 at `r = 2.2` and folds near `r = 2.147` on the problem's grid), and they would
/// use it up before the cheapest that exists there.
pub fn refine_candidates(
    problem: &Problem,
    candidates: &[search::Candidate],
    options: &SolveOptions,
    best_residual: f64,
    progress: &dyn Progress,
) -> Result<(usize, Vec<Extremal>, Vec<Unrefined>), SolveError> {
    let mut extremals: Vec<(Extremal, f64)> = Vec::new();
    let mut unrefined: Vec<Unrefined> = Vec::new();
    // A joint limit's coarse minima are further from the problem's (arcs on 64 steps), and
    // many refine to the same extremal.
    let coarse_error = if problem.alpha_max.is_some() {
        LIMITED_COARSE_COST_ERROR
    } else {
        COARSE_COST_ERROR
    };
    // Candidates tried, and those of them not counted: repeats and prunes (see above).
    let (mut tried, mut uncounted) = (0, 0);
    let mut skipped = Vec::new();
    // The intermediate grids' paths of the refinements that reached an extremal.
    let mut trails = Vec::new();
    // The smallest stationarity of the refinements that stalled in it.
    let mut stalled = None;
    for (pass, list) in passes(problem, candidates).into_iter().enumerate() {
        // Before the unresolved candidates: the settled cost, and the coarse cost of the
        // cheapest resolved candidate that settled an admissible extremal.
        let before = (
            admissible(&extremals, |x, _| x.cost),
            admissible(&extremals, |_, c| c),
        );
        for (c, miss) in list {
            let settled = admissible(&extremals, |x, _| x.cost);
            let margin = if pass < 2 { 1.0 + coarse_error } else { 1.0 };
            if pass == 1 && settled.is_finite() && (settled < before.0 || c.cost >= before.1) {
                if c.cost <= settled * margin {
                    skipped.push(unresolved(problem, c, miss));
                }
                continue;
            }
            if tried - unrefined.len() - uncounted >= options.refine || c.cost > settled * margin {
                break;
            }
            tried += 1;
            let pulse = || progress.pulse();
            let bound = settled * (1.0 + PRUNE);
            let refined = carry(problem, &c.u, &c.nu, bound, &trails, &pulse);
            progress.tick();
            let (fine, run) = match refined {
                Ok((fine, run, trail)) => {
                    trails.extend(trail);
                    (fine, run)
                }
                Err(Stop::Dearer | Stop::Repeat) => {
                    uncounted += 1;
                    continue;
                }
                Err(stop) => {
                    unrefined.push(stopped(c, stop, &mut stalled));
                    continue;
                }
            };
            let x = extremal(problem, &fine, &run);
            uncounted += usize::from(!file(&mut extremals, x, c, problem.h));
        }
    }
    unrefined.extend(skipped);
    settle(
        problem,
        extremals,
        unrefined,
        tried,
        (best_residual, stalled),
    )
}

/// Files `x`, refined from candidate `c`, unless `extremals` hold its path (controls at step
/// `h`) already; whether it was new.
fn file(extremals: &mut Vec<(Extremal, f64)>, x: Extremal, c: &search::Candidate, h: f64) -> bool {
    let same = |o: &Extremal| grid::same_path(&o.trajectory.controls, &x.trajectory.controls, h);
    let new = !extremals.iter().any(|(o, _)| same(o));
    if new {
        let (start, hits) = (c.start, c.hits);
        extremals.push((Extremal { start, hits, ..x }, c.cost));
    }
    new
}

/// The least of `f(extremal, its candidate's coarse cost)` over the admissible `extremals`
/// (∞ if none).
fn admissible(extremals: &[(Extremal, f64)], f: impl Fn(&Extremal, f64) -> f64) -> f64 {
    (extremals.iter())
        .filter(|(x, _)| x.admissible)
        .map(|(x, c)| f(x, *c))
        .fold(f64::INFINITY, f64::min)
}

/// Candidate `c`, whose refinement stopped with `stop` short of the problem's grid (not
/// [`Stop::Dearer`]), as unrefined (logged at `debug`); `stalled`, the smallest stationarity
/// of the refinements that stalled in it, updated.
fn stopped(c: &search::Candidate, stop: Stop, stalled: &mut Option<f64>) -> Unrefined {
    log::debug!(
        "candidate of coarse J {:.7} ({} hits, max |α| {:.4}) not refined: {stop:?}",
        c.cost,
        c.hits,
        c.max_abs_alpha
    );
    if let Stop::Stationarity { stationarity, .. } = stop {
        *stalled = Some(stalled.map_or(stationarity, |s: f64| s.min(stationarity)));
    }
    Unrefined {
        minimum: Minimum::of(c),
        defect: stop.defect(),
        cheaper: false,
    }
}

/// The candidates in the order [`refine_candidates`] tries them: those that may be
/// admissible (their largest `|α_i|` within [`COARSE_ALPHA_ERROR`] of the bound) whose path
/// the coarse grid resolves; with a joint limit, those whose path it does not ([`miss`] above
/// [`UNRESOLVED`]); the others. Each with its path's miss, computed once (0 where it is not
/// needed: without a joint limit, and for the others).
fn passes<'a>(
    problem: &Problem,
    candidates: &'a [search::Candidate],
) -> [Vec<(&'a search::Candidate, f64)>; 3] {
    let near = |c: &search::Candidate| c.max_abs_alpha < problem.shape_bound() + COARSE_ALPHA_ERROR;
    let limited = problem.alpha_max.is_some();
    let (maybe, beyond): (Vec<_>, Vec<_>) = (candidates.iter())
        .map(|c| {
            (
                c,
                if limited && near(c) {
                    miss(problem, c)
                } else {
                    0.0
                },
            )
        })
        .partition(|(c, _)| near(c));
    let (maybe, deferred) = maybe.into_iter().partition(|(_, m)| *m <= UNRESOLVED);
    [maybe, deferred, beyond]
}

/// Candidate `c` skipped as a minimum the coarse grid does not resolve: reported with its
/// path's `miss` on the next grid ([`miss`]) as its defect.
fn unresolved(problem: &Problem, c: &search::Candidate, miss: f64) -> Unrefined {
    let defect = miss * problem.displacement();
    log::debug!(
        "candidate of coarse J {:.7} ({} hits) not refined: its path misses the target by \
         {defect:.1e} on the next grid",
        c.cost,
        c.hits
    );
    Unrefined {
        minimum: Minimum::of(c),
        defect,
        cheaper: false,
    }
}

/// How far the path of candidate `c`, prolonged to the next grid of its refinement
/// ([`finer_grid`]), ends from the target, as a share of the displacement asked for
/// ([`Problem::displacement`]; 0 when none is asked for, ∞ when it cannot be rolled out).
/// Where the coarse grid resolves a path this is about its error in `J` (1e-3, [`PRUNE`]):
/// 0.2–0.6 % for the coarse minima that refine on the problems measured (`α_max` 1.1–2.3);
/// 2–7 % for those whose refinement stalls (`α_max = 1.5` at `r = 2` and `2.1`), minima of
/// the coarse grid's error ([`UNRESOLVED`]).
fn miss(problem: &Problem, c: &search::Candidate) -> f64 {
    let asked = problem.displacement();
    if asked == 0.0 {
        return 0.0;
    }
    let Ok((grid, _)) = finer_grid(problem, c.u.len()) else {
        return f64::INFINITY;
    };
    let Ok(states) = grid.rollout(&grid::prolong(&c.u, grid.steps)) else {
        return f64::INFINITY;
    };
    let d = grid.terminal.defect(&states);
    let l = problem.swimmer.lengths()[0];
    (d[2] * d[2] + d[3] * d[3] + (l * d[4]).powi(2)).sqrt() / asked
}

/// [`refine_candidates`]' outcome from the extremals it found (each with its candidate's
/// coarse cost) after `tried` candidates: the extremals cheapest first with the index of the
/// cheapest admissible one, and the candidates not refined (`cheaper` than it on the coarse
/// grid or not); or why there is none (with the search's smallest defect and the smallest
/// stationarity of the refinements that stalled in it, `(best_residual, stalled)`).
fn settle(
    problem: &Problem,
    mut extremals: Vec<(Extremal, f64)>,
    mut unrefined: Vec<Unrefined>,
    tried: usize,
    (best_residual, stalled): (f64, Option<f64>),
) -> Result<(usize, Vec<Extremal>, Vec<Unrefined>), SolveError> {
    if extremals.is_empty() {
        return Err(if tried == 0 {
            SolveError::Unreachable { best_residual }
        } else {
            SolveError::NotRefined {
                found: tried,
                best_residual: unrefined
                    .iter()
                    .map(|u| u.defect)
                    .fold(f64::INFINITY, f64::min),
                stationarity: stalled,
            }
        });
    }
    extremals.sort_by(|a, b| a.0.cost.total_cmp(&b.0.cost));
    let (mut extremals, coarse): (Vec<Extremal>, Vec<f64>) = extremals.into_iter().unzip();
    mark_twins(problem, &mut extremals);
    let Some(best) = extremals.iter().position(|x| x.admissible) else {
        return Err(SolveError::NoneAdmissible {
            found: extremals.len(),
            best_alpha: extremals
                .iter()
                .map(|x| x.max_abs_alpha)
                .fold(f64::INFINITY, f64::min),
        });
    };
    for u in &mut unrefined {
        u.cheaper = u.minimum.cost < coarse[best];
    }
    Ok((best, extremals, unrefined))
}

/// Marks each extremal whose image under a symmetry of the problem is also in the list.
fn mark_twins(problem: &Problem, extremals: &mut [Extremal]) {
    for sym in symmetry::of_problem(problem) {
        for i in 0..extremals.len() {
            if extremals[i].twin_of.is_some() {
                continue;
            }
            let image: Vec<Vector2<f64>> = extremals[i]
                .trajectory
                .controls
                .iter()
                .map(|u| sym.shape(u))
                .collect();
            extremals[i].twin_of = (0..extremals.len()).find(|&j| {
                j != i && grid::same_path(&extremals[j].trajectory.controls, &image, problem.h)
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Spec;
    use crate::solver::search_coarse;

    /// A refinement that meets a path an earlier one carried on stops on the intermediate
    /// grid ([`Stop::Repeat`]); one that meets none reaches the problem's grid as [`refine`]
    /// does. The paper's target over 20 s in 2 000 steps: coarse 64, intermediate 1 024.
    #[test]
    fn a_path_met_on_an_intermediate_grid_is_not_carried_twice() {
        let problem = Problem::new(&Spec {
            horizon: 20.0,
            ..Spec::default()
        })
        .unwrap();
        let options = SolveOptions {
            starts: Some(32),
            min_starts: 32,
            ..SolveOptions::default()
        };
        let found = search_coarse(&problem, &options, &|| ()).unwrap();
        let c = &found.candidates[0];
        let (grid, run, trail) = carry(&problem, &c.u, &c.nu, f64::INFINITY, &[], &|| ()).unwrap();
        assert_eq!(grid.steps, 2000);
        assert_eq!(trail.iter().map(Vec::len).collect::<Vec<_>>(), [1024]);
        let again =
            |c: &search::Candidate| carry(&problem, &c.u, &c.nu, f64::INFINITY, &trail, &|| ());
        assert_eq!(again(c).err(), Some(Stop::Repeat));
        // The path of another extremal is no repeat of this one.
        let other = (found.candidates.iter()).find(|o| {
            refine(&problem, &o.u, &o.nu, f64::INFINITY, &|| ())
                .is_ok_and(|(_, r)| !grid::same_path(&r.point.u, &run.point.u, grid.h()))
        });
        assert!(again(other.expect("a second extremal")).is_ok());
    }
}
