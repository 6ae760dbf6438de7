//! The refinement: the search's candidates carried from the coarse grid to the problem's
//! own, through grids at most 16 times finer each (under a joint limit 4 times up to 1 024
//! steps), Newton converging in a few steps at each
//! (with a joint limit, the barrier path and then the active set, [`homotopy`]); the
//! fine extremals with their certificates, cheapest first. Which candidates, in which order,
//! and the answer: [`refine_candidates`].

mod candidates;
mod central;
mod filed;
pub use candidates::refine_candidates;
pub use central::walked;

use super::constraints::joint_limit::Limits;
use super::cost::{Costs, StageCost};
use super::direct::{self, Run};
use super::grid::{self, Grid, Point};
use super::homotopy::{self, PolishError, Steps};
use super::settings::{
    COARSE_COST_ERROR, FINE_TAUS, GRADUAL_STEPS, PATIENCE, QUICK_PATIENCE, RESCUE_TAUS, Settings,
};
use super::solution::Extremal;
use super::{certificate, costate};
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
    /// solve carried on to an extremal ([`refine_candidates`]): its index among the known
    /// paths.
    Repeat(usize),
}

impl Stop {
    /// The terminal defect where it stopped (0 for [`Stop::Dearer`] and [`Stop::Repeat`],
    /// which converged).
    pub fn defect(self) -> f64 {
        match self {
            Stop::Defect(d) | Stop::Stationarity { defect: d, .. } => d,
            Stop::Dearer | Stop::Repeat(_) => 0.0,
        }
    }
}

/// Carries controls `u` (on any grid over the same horizon) with multiplier `nu` to the
/// problem's grid, through grids at most 16 times finer each ([`finer_grid`]; under a joint
/// limit first through grids 4 times finer up to [`GRADUAL_STEPS`], and again 16 times finer
/// if that stalls), Newton
/// converging at each. With a joint limit, the first finer grid runs the barrier path
/// [`FINE_TAUS`] and the others only its last weight ([`homotopy::patient_barrier_path`]; if a
/// smaller weight stalls, the path goes on from the last weight reached; if the first stalls
/// near the start, the path runs again from larger weights, on the intermediate grids after
/// the first at once), and on the problem's grid the
/// active-set rounds impose the limit on its arcs ([`homotopy::polish`]); if that stalls on
/// some grid, the whole way once more with primal–dual barrier steps
/// ([`Settings::primal_dual`]; the first stop is returned if that stalls too). Gives up with
/// [`Stop::Dearer`] once an intermediate grid's cost exceeds `bound` (`f64::INFINITY`: never).
/// `pulse` is called on each grid and before each Newton iteration.
pub fn refine(
    problem: &Problem,
    u: &[Vector2<f64>],
    nu: &Vector5<f64>,
    bound: f64,
    pulse: &dyn Fn(),
) -> Result<(Grid, Run), Stop> {
    let bound = |_| bound;
    either(problem, (u, nu), (&bound, &[]), PATIENCE[1], pulse).map(|(grid, run, _)| (grid, run))
}

/// [`refine`] without a bound, the barrier paths given `patience` iterations per weight where
/// [`PATIENCE`]`[0]` do not converge (instead of [`PATIENCE`]`[1]`): for a start far from the
/// barrier's path on the problem's grid ([`super::periodic`]).
pub fn refine_patiently(
    problem: &Problem,
    u: &[Vector2<f64>],
    nu: &Vector5<f64>,
    patience: usize,
    pulse: &dyn Fn(),
) -> Result<(Grid, Run), Stop> {
    let none = |_| f64::INFINITY;
    either(problem, (u, nu), (&none, &[]), patience, pulse).map(|(grid, run, _)| (grid, run))
}

/// [`carry`]'s first route of a search's candidate ([`refine_candidates`]): primal barrier
/// steps, on the problem's grid primal–dual ones after [`super::settings::QUICK_PATIENCE`]
/// ([`Steps::PrimalThenDual`]), [`PATIENCE`]`[1]`.
const PRIMAL: (Steps, usize) = (Steps::PrimalThenDual, PATIENCE[1]);

/// [`carry`] of `(u, nu)` against `(bound, known)` with primal barrier steps, and under a
/// joint limit, if that stalls on some grid, with primal–dual ones (the first stop is
/// returned if that stalls too); the barrier paths' second patience `patience`.
fn either(
    problem: &Problem,
    (u, nu): (&[Vector2<f64>], &Vector5<f64>),
    (bound, known): (&dyn Fn(usize) -> f64, &[Controls]),
    patience: usize,
    pulse: &dyn Fn(),
) -> Result<(Grid, Run, Trail), Stop> {
    let carry = |steps| carry(problem, (u, nu), bound, known, (steps, patience), pulse);
    let primal = carry(Steps::Primal);
    match primal {
        Err(Stop::Defect(_) | Stop::Stationarity { .. }) if problem.alpha_max.is_some() => {
            carry(Steps::PrimalDual).or(primal)
        }
        _ => primal,
    }
}

/// [`refine`], which also gives up with [`Stop::Repeat`] once an intermediate grid's path is
/// one of `known` (to [`grid::same_path`]): a path there that an earlier refinement carried
/// on to the problem's grid leads to the extremal it reached. Also gives the paths of its own
/// intermediate grids, each with its cost there; `bound` is the bound on a grid of that many
/// steps. Under a joint limit many coarse minima meet on the intermediate grids
/// (`α_max = 1.1`, target (0, 0, 0.3): ten coarse minima at 1.604–1.641 all reach 1.5450974
/// on 1 024 steps and 1.5448608 on 10 000), and the problem's grid costs about three times
/// the intermediate one. There the grids are at most 4 times finer each up to
/// [`GRADUAL_STEPS`] (64, 256, 1 024 steps, then the problem's): Newton from a prolonged
/// path converges in fewer iterations, most of them on the cheaper grids (at that target
/// 14.8 → 8.6 CPU-s); a candidate that stalls on one of them is carried again through grids
/// 16 times finer, as without a limit (at `α_max = 0.9` the cheapest, 4.1403062, stalls on
/// 1 024 steps from 256 and is carried from 64), one that stalls on the problem's grid is
/// not (at `α_max = 0.95`, target (0, 0, 0.2), six stalled in the active-set rounds there;
/// carried again, they took 10 of the solve's 33 CPU-s).
///
/// The primal barrier's Hessian `τ/d²` is right only on the central path: where a state
/// rests far from its barrier minimiser's distance to the limit, as a prolonged coarse path's
/// do on a finer grid, Newton's steps overshoot and each is cut at the fraction to the
/// boundary. The primal–dual step carries the limit's multipliers `z` and takes `z/d`
/// (MODEL.md §9): `steps`, which barrier steps ([`Steps`]), with the barrier paths' second
/// patience ([`homotopy::patient_barrier_path`]). Tried first, it found the
/// same costs on 52 of 53 limited problems (3.5 % less time, every one's bits changed) and
/// took longer at `α_max = 1.2`, target (0, 0, −0.5) (24 CPU-s against 14); as the second
/// try of a candidate whose primal route stalls (after the others, [`refine_candidates`];
/// [`refine`]), it leaves every solve whose candidates all refined as it was, and there
/// carries the coarse minimum whose primal route stalls to 2.7023994 (2.7226544 without).
/// On the problem's grid the first route ([`PRIMAL`]) takes primal–dual steps once
/// [`super::settings::QUICK_PATIENCE`] primal ones have not converged: there the path
/// prolonged from 1 024 steps creeps at `τ = 1e-9` (`α_max = 1.1`, target (0, 0, 0.3): 104
/// primal iterations, 1.2 s of the 5.4 s solve; 20 + 41 this way, 0.7 s); every grid that
/// converges within 20 is as it was (42 of the 53 limited problems bit for bit, the other 11
/// the same cost). Not for a flown gait ([`refine_patiently`], a far start): with primal–dual
/// steps on every route's problem's grid, the flown links 1, 1.5, 0.6 within 1.6 rad came
/// out dearer (7.3977557 against 7.1386952); nor for a gait continued ([`refine`],
/// [`super::continuation`]), which is to follow its family: from the gait of links 1, 0.93,
/// 0.93 to (0.144, 0.023, −0.44) within 1 rad at `--step 0.1` to `--step 0.05` this way
/// reached 8.6030324, primal steps 8.6260113.
fn carry(
    problem: &Problem,
    (u, nu): (&[Vector2<f64>], &Vector5<f64>),
    bound: &dyn Fn(usize) -> f64,
    known: &[Controls],
    (steps, patience): (Steps, usize),
    pulse: &dyn Fn(),
) -> Result<(Grid, Run, Trail), Stop> {
    let route = Route {
        gradual: problem.alpha_max.is_some() && 4 * u.len() <= GRADUAL_STEPS,
        steps,
        patience,
    };
    carry_through(problem, (u, nu), bound, known, route, pulse)
}

/// How [`carry_through`] goes: through grids 4 times finer up to [`GRADUAL_STEPS`]
/// (`gradual`) or 16 times, with the barrier `steps` ([`Steps::PrimalThenDual`]: primal on
/// the intermediate grids), the barrier paths' second patience `patience`
/// ([`homotopy::patient_barrier_path`]).
#[derive(Clone, Copy, Debug)]
struct Route {
    gradual: bool,
    steps: Steps,
    patience: usize,
}

impl Route {
    /// The barrier steps on an intermediate grid, or on the problem's grid (`last`).
    fn steps_on(&self, last: bool) -> Steps {
        match self.steps {
            Steps::PrimalThenDual if !last => Steps::Primal,
            steps => steps,
        }
    }
}

/// The paths of a refinement's intermediate grids, each with its cost there ([`carry`]).
type Trail = Vec<(Controls, f64)>;

/// [`carry`] along `route`: through grids 4 times finer up to [`GRADUAL_STEPS`] (from
/// `origin` again 16 times finer if Newton stalls on one of them), or 16 times.
fn carry_through(
    problem: &Problem,
    origin: (&[Vector2<f64>], &Vector5<f64>),
    bound: &dyn Fn(usize) -> f64,
    known: &[Controls],
    route: Route,
    pulse: &dyn Fn(),
) -> Result<(Grid, Run, Trail), Stop> {
    let mut trail = Vec::new();
    let mut u = origin.0.to_vec();
    let mut nu = *origin.1;
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
        let n = u.len();
        let ratio = if route.gradual && 4 * n <= GRADUAL_STEPS {
            4
        } else {
            16
        };
        let (grid, last) = finer_by(problem, n, ratio).map_err(inf)?;
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
                let path = (alpha_max, from);
                let steps = (route.steps_on(last), route.patience);
                let quick = !trail.is_empty() && !last;
                let (reached, run) = barrier_stage(&grid, path, start, (steps, quick), pulse)?;
                from = reached;
                (run, Settings::barrier(PATIENCE[0]).tol_defect)
            }
        };
        if !run.converged() {
            if route.gradual && !last {
                let route = Route {
                    gradual: false,
                    ..route
                };
                return carry_through(problem, origin, bound, known, route, pulse);
            }
            return Err(stalled(&run, tol_defect));
        }
        if last {
            let Some(alpha_max) = problem.alpha_max else {
                return Ok((grid, run, trail));
            };
            let (grid, run) = polished(problem, &grid, alpha_max, &run, pulse)?;
            return Ok((grid, run, trail));
        }
        let cost = grid.cost(&run.point.u, &run.point.states);
        if cost > bound(grid.steps) {
            return Err(Stop::Dearer);
        }
        if let Some(i) = (known.iter()).position(|k| grid::same_path(k, &run.point.u, grid.h())) {
            return Err(Stop::Repeat(i));
        }
        trail.push((run.point.u.clone(), cost));
        u = run.point.u;
        nu = run.point.nu;
    }
}

/// The problem's grid `grid` under the joint limit `alpha_max`: the active-set rounds from
/// the barrier path's end `run` ([`homotopy::polish`]).
fn polished(
    problem: &Problem,
    grid: &Grid,
    alpha_max: f64,
    run: &Run,
    pulse: &dyn Fn(),
) -> Result<(Grid, Run), Stop> {
    let fine = Settings::fine(problem, &run.point.u);
    match homotopy::polish(grid, alpha_max, &run.point, &fine, pulse) {
        Ok(done) => Ok(done),
        Err(PolishError::NotConverged(run)) => Err(stalled(&run, fine.tol_defect)),
        Err(PolishError::Failed | PolishError::Unsettled) => Err(Stop::Defect(f64::INFINITY)),
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
/// weight's run, not converged. `steps` as [`homotopy::patient_barrier_path`]'s; `quick`,
/// whether the grid is an intermediate one after the first ([`quick_stage`] first).
fn barrier_stage(
    grid: &Grid,
    (alpha_max, from): (f64, usize),
    start: Point,
    (steps, quick): ((Steps, usize), bool),
    pulse: &dyn Fn(),
) -> Result<(usize, Run), Stop> {
    let taus = &FINE_TAUS[from..];
    if quick && let Some(done) = quick_stage(grid, (alpha_max, taus), &start, steps, pulse)? {
        return Ok(done);
    }
    let path = (alpha_max, taus);
    let walk = homotopy::patient_barrier_path(grid, path, start.clone(), steps, pulse)
        .map_err(|_| Stop::Defect(f64::INFINITY))?;
    if walk.run.converged() {
        return Ok((FINE_TAUS.len() - 1, walk.run));
    }
    let Some((i, reached)) = walk.reached else {
        let near = grid.cost(&walk.run.point.u, &walk.run.point.states)
            <= grid.cost(&start.u, &start.states) * (1.0 + COARSE_COST_ERROR);
        if near && let Some(rescued) = rescue(grid, alpha_max, start, steps, pulse) {
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

/// [`barrier_stage`] on an intermediate grid after the first: the path `taus` with
/// [`QUICK_PATIENCE`] iterations per weight, and if that stalls, at once the path from
/// [`RESCUE_TAUS`] ([`rescue`]) without first spending the patience on the stalled weight;
/// `None` if neither converged. A path prolonged from the grid before creeps there at its
/// small weights (`α_max = 1.1`, target (0, 0, 0.3): on 1 024 steps from 256, 300
/// iterations at `τ = 1e-9` that do not converge, or at `1e-6`, then the rescue's 90 that
/// do, 0.30 s of each candidate's 0.33 s there; with this stage 0.07 s, the solve 8.7 → 6.6
/// CPU-s, its gait bit for bit). A weight that converges does so in 8–13 iterations there.
fn quick_stage(
    grid: &Grid,
    (alpha_max, taus): (f64, &[f64]),
    start: &Point,
    steps: (Steps, usize),
    pulse: &dyn Fn(),
) -> Result<Option<(usize, Run)>, Stop> {
    let primal_dual = steps.0 == Steps::PrimalDual;
    let settings = Settings::barrier(QUICK_PATIENCE).with_primal_dual(primal_dual);
    let walk = homotopy::walk(grid, alpha_max, taus, start.clone(), &settings, pulse)
        .map_err(|_| Stop::Defect(f64::INFINITY))?;
    if walk.run.converged() {
        return Ok(Some((FINE_TAUS.len() - 1, walk.run)));
    }
    Ok(rescue(grid, alpha_max, start.clone(), steps, pulse).filter(|(_, run)| run.converged()))
}

/// The barrier path on `grid` from `start` through the larger weights [`RESCUE_TAUS`] and
/// then [`FINE_TAUS`], for a grid whose path stalled at its first weight near its start:
/// the larger weights first hold the states off the limit, where Newton converges from the
/// prolonged path, and the smaller ones bring them back (seen at `α_max = 1` on the paper's
/// target: from the coarse extremal, the 1 024-step grid stalled at `τ = 1e-6` with
/// stationarity 0.4 at a cost 0.1 % below the coarse one, and converged from `τ = 1e-4`).
/// The index in [`FINE_TAUS`] of the last weight that converged, with its run; `None` if
/// none of them did. `steps` as [`homotopy::patient_barrier_path`]'s.
fn rescue(
    grid: &Grid,
    alpha_max: f64,
    start: Point,
    steps: (Steps, usize),
    pulse: &dyn Fn(),
) -> Option<(usize, Run)> {
    let taus: Vec<f64> = RESCUE_TAUS.iter().chain(&FINE_TAUS).copied().collect();
    let path = (alpha_max, &taus[..]);
    let walk = homotopy::patient_barrier_path(grid, path, start, steps, pulse).ok()?;
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
    finer_by(problem, n, 16)
}

/// The grid at most `ratio` times finer than `n` steps (16: [`finer_grid`]; 4: the joint
/// limit's first grids, [`carry`]), or the problem's own (`true`).
fn finer_by(
    problem: &Problem,
    n: usize,
    ratio: usize,
) -> Result<(Grid, bool), purcell_core::Error> {
    let n_fine = problem.steps as usize;
    let next = if n_fine <= ratio * n {
        n_fine
    } else {
        ratio * n
    };
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Spec;
    use crate::solver::{SolveOptions, search, search_coarse};

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
            min_starts: Some(32),
            ..SolveOptions::default()
        };
        let found = search_coarse(&problem, &options, &|| ()).unwrap();
        let c = &found.candidates[0];
        let none = |_| f64::INFINITY;
        let steps = (Steps::Primal, PATIENCE[1]);
        let (grid, run, trail) = carry(&problem, (&c.u, &c.nu), &none, &[], steps, &|| ()).unwrap();
        let trail: Vec<Controls> = trail.into_iter().map(|(u, _)| u).collect();
        assert_eq!(grid.steps, 2000);
        assert_eq!(trail.iter().map(Vec::len).collect::<Vec<_>>(), [1024]);
        let again =
            |c: &search::Candidate| carry(&problem, (&c.u, &c.nu), &none, &trail, steps, &|| ());
        assert!(matches!(again(c).err(), Some(Stop::Repeat(_))));
        // The path of another extremal is no repeat of this one.
        let other = (found.candidates.iter()).find(|o| {
            refine(&problem, &o.u, &o.nu, f64::INFINITY, &|| ())
                .is_ok_and(|(_, r)| !grid::same_path(&r.point.u, &run.point.u, grid.h()))
        });
        assert!(again(other.expect("a second extremal")).is_ok());
    }

    /// A candidate whose primal barrier path stalls is carried by primal–dual steps
    /// ([`carry`]): within `|α_i| ≤ 1.2` to (0, 0, −0.5), the coarse minimum of J 2.8817545
    /// stalls on the primal route and reaches 2.7023994 on the primal–dual one, the cheapest
    /// gait of `purcell-sim solve` there (2.7226544 without the second try).
    #[test]
    fn a_candidate_whose_primal_path_stalls_is_carried_by_primal_dual_steps() {
        let problem = Problem::new(&Spec {
            target: [0.0, 0.0, -0.5],
            alpha_max: Some(1.2),
            ..Spec::default()
        })
        .unwrap();
        let found = search_coarse(&problem, &SolveOptions::default(), &|| ()).unwrap();
        let c = (found.candidates.iter())
            .find(|c| (c.cost - 2.8817545).abs() <= 1e-7)
            .expect("the coarse minimum");
        let none = |_| f64::INFINITY;
        let through = |steps| {
            let route = Route {
                gradual: true,
                steps,
                patience: PATIENCE[1],
            };
            carry_through(&problem, (&c.u, &c.nu), &none, &[], route, &|| ())
        };
        let primal = through(Steps::Primal).err();
        assert!(
            matches!(primal, Some(Stop::Defect(_) | Stop::Stationarity { .. })),
            "{primal:?}"
        );
        let (grid, run, _) = through(Steps::PrimalDual).unwrap();
        let cost = grid.cost(&run.point.u, &run.point.states);
        assert!((cost - 2.7023994).abs() <= 1e-7, "{cost}");
        let (grid, run) = refine(&problem, &c.u, &c.nu, f64::INFINITY, &|| ()).unwrap();
        assert_eq!(grid.cost(&run.point.u, &run.point.states), cost);
    }
}
