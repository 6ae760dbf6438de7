//! The solver: the cheapest admissible extremal of the discrete problem (MODEL.md §4).
//!
//! Pipeline of [`solve`]:
//! 1. [`starts`]: closed shape loops through `ᾱ`, sized from the problem's geometry;
//! 2. [`search`]: each start through the direct method ([`direct`]: Newton–SQP with the exact
//!    Hessian and a Riccati step, [`riccati`], on the stage model [`stage`]) on a coarse grid
//!    whose rule mimics the fine one; distinct local minima, cheapest first;
//! 3. [`refine`]: the cheapest candidates carried to the problem's own grid through finer
//!    grids, Newton converging in a few steps at each (a candidate dearer than the settled
//!    cheapest by [`PRUNE`] on an intermediate grid stops there); second-order check by the
//!    inertia of the last factorisation. With a joint limit ([`limits`]), the search and the
//!    refinement run an interior-point path and the refinement ends with the limit imposed
//!    exactly on the arcs where it is active;
//! 4. [`costate`]: `(μ, ξ^{−1})` and the costate path from the multipliers;
//! 5. [`certificate`]: independent checks (the core's law reproduces the controls, the
//!    controls reach the target through the core's kinematics, KKT by reverse mode).
//!
//! [`continuation`] solves from a stored extremal (`--from`) and over a grid of targets
//! (`sweep`).

pub mod certificate;
pub mod constraints;
pub mod continuation;
pub mod cost;
pub mod costate;
pub mod direct;
pub mod filter;
pub mod grid;
pub mod limits;
pub mod linearisation;
pub mod riccati;
pub mod search;
pub mod settings;
pub mod stage;
pub mod starts;
pub mod symmetry;

use crate::problem::{OVERLAP, Problem};
use constraints::joint_limit::Limits;
use direct::Run;
use grid::{Grid, Point};
use nalgebra::{Vector2, Vector3, Vector5};
use purcell_core::{Arc, State};
use settings::{
    COARSE_ALPHA_ERROR, COARSE_COST_ERROR, COARSE_TAU, KKT_TOL, LAW_TOL, PRUNE, Settings,
    TERMINAL_TOL,
};
use stage::Rule;

/// Solver settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveOptions {
    /// Most start loops of the global search, its budget (it stops earlier once its stopping
    /// rule is met, [`search`]).
    pub starts: usize,
    /// Fewest start loops of the global search (unless `starts` is smaller).
    pub min_starts: usize,
    /// Orders the start loops.
    pub seed: u64,
    /// Steps of the coarse grid of the global search.
    pub coarse_steps: usize,
    /// Most candidates carried to the fine grid.
    pub refine: usize,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            starts: 512,
            min_starts: 128,
            seed: 0,
            coarse_steps: 64,
            refine: 6,
        }
    }
}

/// A trajectory on the grid: `k = 0..N` states, `k < N` controls, costates `ξ^{k−1}`.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Trajectory {
    /// `(α_k, g_k)`, `k = 0..=N`.
    pub states: Vec<State<f64>>,
    /// `u_k`, `k < N`.
    pub controls: Vec<Vector2<f64>>,
    /// `ξ^{k−1}`, `k = 0..=N` (the first is `ξ^{−1}`).
    pub xis: Vec<Vector2<f64>>,
}

/// One extremal of the fine problem, with its certificates.
#[derive(Clone, Debug, PartialEq)]
pub struct Extremal {
    /// `J = Σ h/2 |u_k|²`.
    pub cost: f64,
    /// Spatial momentum `μ`.
    pub mu: Vector3<f64>,
    /// `ξ^{−1}`.
    pub xi0: Vector2<f64>,
    /// Largest `|α_i|` along the path.
    pub max_abs_alpha: f64,
    /// Whether the path is admissible ([`Problem::admits`]).
    pub admissible: bool,
    /// Terminal defect of the direct method's trajectory (largest component, m / rad).
    pub residual: f64,
    /// The same after re-integrating the controls through the core's kinematics
    /// ([`certificate::terminal_residual`]); `None` if the path is not admissible.
    pub terminal_residual: Option<f64>,
    /// Independent KKT residual ([`certificate::kkt`], rad/s, with the joint limit's
    /// multipliers); `None` if the path is not admissible (the core refuses shapes past the
    /// overlap limit).
    pub kkt_residual: Option<f64>,
    /// The joint limit's arcs: maximal runs of states `k = first..=last` on `σ α_{k,i} = α_max`
    /// (empty without a limit or where it is inactive), sorted by `(first, joint)` as a gait's
    /// arc table is ([`purcell_core::arc`]).
    pub arcs: Vec<Arc>,
    /// Smallest multiplier `η_k ≥ 0` of the joint limit over the arcs' states, from
    /// [`certificate::kkt`]; `None` without arcs.
    pub min_eta: Option<f64>,
    /// The direct method's own stationarity residual (rad/s).
    pub stationarity: f64,
    /// Relative deviation of the core's law from the controls ([`certificate::law_residual`]);
    /// `None` if the path is not admissible.
    pub law_residual: Option<f64>,
    /// Second-order sufficient condition: a strict local minimum.
    pub local_min: bool,
    /// Newton iterations on the fine grid.
    pub iterations: usize,
    /// Index of the start loop that first reached it in the global search (0: zero loop).
    pub start: usize,
    /// How many starts of the global search reached it.
    pub hits: usize,
    /// For a problem that a symmetry of the swimmer maps to itself ([`symmetry`]): the
    /// index in [`Solution::extremals`] of this extremal's image (same cost, another loop),
    /// when found too.
    pub twin_of: Option<usize>,
    /// The trajectory with its costates.
    pub trajectory: Trajectory,
}

impl Extremal {
    /// Why its certificates do not vouch for it, if they do not: it must be admissible and a
    /// strict local minimum, land on the target through the core's kinematics within
    /// [`TERMINAL_TOL`], satisfy KKT within [`KKT_TOL`] and be reproduced by the core's law
    /// within [`LAW_TOL`] (relative); the bounds the tests hold every returned extremal to.
    pub fn uncertified(&self) -> Option<&'static str> {
        if !self.admissible {
            return Some("not admissible");
        }
        if !self.local_min {
            return Some("not a strict local minimum");
        }
        let residuals = [self.terminal_residual, self.kkt_residual, self.law_residual];
        residuals
            .into_iter()
            .zip(CERTIFICATES)
            .find(|(r, (bound, _))| !r.is_some_and(|r| r <= *bound))
            .map(|(_, (_, why))| why)
    }
}

/// The certificates' bounds, in the order [`Extremal::uncertified`] checks them, with how it
/// names a residual above each (sweep.csv's `status`).
const CERTIFICATES: [(f64, &str); 3] = [
    (TERMINAL_TOL, "terminal residual above 1e-10"),
    (KKT_TOL, "KKT residual above 1e-8"),
    (LAW_TOL, "law residual above 1e-9"),
];

/// Outcome of a solve.
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    /// Index into `extremals` of the returned one (the cheapest admissible).
    pub best: usize,
    /// Every distinct extremal carried to the fine grid, cheapest first.
    pub extremals: Vec<Extremal>,
    /// What the global search saw (`None` for a solve from a warm start).
    pub search: Option<Evidence>,
}

/// The global search's evidence for its answer ([`search`]'s stopping rule).
#[derive(Clone, Debug, PartialEq)]
pub struct Evidence {
    /// Start loops run.
    pub starts: usize,
    /// The budget ([`SolveOptions::starts`]).
    pub budget: usize,
    /// The distinct minima of the coarse problem, cheapest first.
    pub minima: Vec<Minimum>,
    /// Estimated chance that a further start reaches an unseen minimum no dearer than the
    /// cheapest admissible one ([`search::Search::unseen`]).
    pub unseen: f64,
    /// Boender and Rinnooy Kan's estimate of the number of minima
    /// ([`search::Search::expected_minima`]).
    pub expected_minima: f64,
    /// Whether the stopping rule was met within the budget.
    pub satisfied: bool,
}

/// One distinct minimum of the coarse problem.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Minimum {
    /// `J` on the coarse grid.
    pub cost: f64,
    /// Largest `|α_i|` along it.
    pub max_abs_alpha: f64,
    /// How many starts reached it.
    pub hits: usize,
}

impl Evidence {
    fn of(found: &search::Search, budget: usize) -> Self {
        Evidence {
            starts: found.starts,
            budget,
            minima: found
                .candidates
                .iter()
                .map(|c| Minimum {
                    cost: c.cost,
                    max_abs_alpha: c.max_abs_alpha,
                    hits: c.hits,
                })
                .collect(),
            unseen: found.unseen,
            expected_minima: found.expected_minima(),
            satisfied: found.satisfied,
        }
    }
}

/// Why no extremal was returned.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// No start converged.
    #[error("no start reached the target: best residual {best_residual:.3e}")]
    Unreachable {
        /// Smallest terminal defect reached by any start.
        best_residual: f64,
    },
    /// The search found extremals on its coarse grid, but none could be carried to the
    /// problem's grid.
    #[error(
        "{found} extremal(s) of the coarse search, none carried to the problem's grid: smallest terminal defect {best_residual:.3e}"
    )]
    NotRefined {
        /// How many were tried.
        found: usize,
        /// Smallest terminal defect where a refinement stopped.
        best_residual: f64,
    },
    /// Extremals were found but none is admissible.
    #[error(
        "{found} extremal(s) found, none admissible: the smallest largest |alpha_i| is {best_alpha:.4} rad, at or past the joint limit (or the links' overlap at pi)"
    )]
    NoneAdmissible {
        /// How many.
        found: usize,
        /// Smallest of their largest `|α_i|`.
        best_alpha: f64,
    },
}

/// Why a refinement stopped short of the problem's grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stop {
    /// Newton did not converge on a grid: the terminal defect where it stopped.
    Defect(f64),
    /// On an intermediate grid the extremal already cost more than the bound.
    Dearer,
}

impl Stop {
    /// The terminal defect where it stopped (0 for [`Stop::Dearer`], which converged).
    pub fn defect(self) -> f64 {
        match self {
            Stop::Defect(d) => d,
            Stop::Dearer => 0.0,
        }
    }
}

/// Carries controls `u` (on any grid over the same horizon) with multiplier `nu` to the
/// problem's grid: [`refine_free`], or [`limits::refine`] with a joint limit. Gives up with
/// [`Stop::Dearer`] once an intermediate grid's cost exceeds `bound` (`f64::INFINITY`: never).
pub fn refine(
    problem: &Problem,
    u: &[Vector2<f64>],
    nu: &Vector5<f64>,
    bound: f64,
) -> Result<(Grid, Run), Stop> {
    match problem.alpha_max {
        None => refine_free(problem, u, nu, bound),
        Some(a) => limits::refine(problem, a, u, nu, bound),
    }
}

/// Without a joint limit: through grids at most 16 times finer each ([`Rule::matching`] on
/// the intermediate ones), Newton converging at each.
pub fn refine_free(
    problem: &Problem,
    u: &[Vector2<f64>],
    nu: &Vector5<f64>,
    bound: f64,
) -> Result<(Grid, Run), Stop> {
    let mut u = u.to_vec();
    let mut nu = *nu;
    loop {
        let inf = |_| Stop::Defect(f64::INFINITY);
        let (grid, last) = finer_grid(problem, u.len()).map_err(inf)?;
        let next = grid.steps;
        let start = Point::new(&grid, grid::prolong(&u, next), nu).map_err(inf)?;
        let settings = if last {
            Settings::fine(problem, &start.u)
        } else {
            Settings::INTERMEDIATE
        };
        let run = direct::newton(&grid, start, &settings).map_err(inf)?;
        if !run.converged {
            return Err(Stop::Defect(run.defect));
        }
        if last {
            return Ok((grid, run));
        }
        if grid.cost(&run.point.u) > bound {
            return Err(Stop::Dearer);
        }
        u = run.point.u;
        nu = run.point.nu;
    }
}

/// The next grid of a refinement from `n` steps: at most 16 times finer, with the rule that
/// mimics the problem's discretisation ([`Rule::matching`]), or the problem's own grid
/// (`true`) once that is near enough.
pub fn finer_grid(problem: &Problem, n: usize) -> Result<(Grid, bool), purcell_core::Error> {
    let n_fine = problem.steps as usize;
    let next = if n_fine <= 16 * n { n_fine } else { 16 * n };
    let last = next == n_fine;
    let rule = if last {
        Rule::LEFT_POINT
    } else {
        Rule::matching(problem.horizon() / next as f64, problem.h)
    };
    Ok((Grid::new(problem, next, rule)?, last))
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
    let cost = grid.cost(&p.u);
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
        local_min: run.local_min || cost == 0.0,
        iterations: run.iterations,
        start: 0,
        hits: 0,
        twin_of: None,
        trajectory,
    }
}

/// The coarse grid of the global search: `options.coarse_steps` steps (at most the problem's)
/// with the rule that mimics the problem's discretisation; with a joint limit, its barrier
/// at the last weight of the search's path ([`COARSE_TAU`]).
pub fn coarse_grid(problem: &Problem, options: &SolveOptions) -> Option<Grid> {
    let n = options.coarse_steps.min(problem.steps as usize).max(1);
    let rule = if n == problem.steps as usize {
        Rule::LEFT_POINT
    } else {
        Rule::matching(problem.horizon() / n as f64, problem.h)
    };
    let mut grid = Grid::new(problem, n, rule).ok()?;
    if let Some(alpha_max) = problem.alpha_max {
        grid.limits = Limits::Barrier {
            alpha_max,
            tau: COARSE_TAU,
        };
    }
    Some(grid)
}

/// Solves from many starts (see the module docs); `progress` is called once per start.
pub fn solve(
    problem: &Problem,
    options: &SolveOptions,
    progress: &(dyn Fn() + Sync),
) -> Result<Solution, SolveError> {
    let found = search_coarse(problem, options, progress)?;
    let (best, extremals) =
        refine_candidates(problem, &found.candidates, options, found.best_residual)?;
    Ok(Solution {
        best,
        extremals,
        search: Some(Evidence::of(&found, options.starts)),
    })
}

/// The global search of `problem` on its coarse grid ([`coarse_grid`], [`search::search`]).
pub fn search_coarse(
    problem: &Problem,
    options: &SolveOptions,
    progress: &(dyn Fn() + Sync),
) -> Result<search::Search, SolveError> {
    let grid = coarse_grid(problem, options).ok_or(SolveError::Unreachable {
        best_residual: f64::INFINITY,
    })?;
    Ok(search::search(
        &grid,
        options.min_starts,
        options.starts,
        options.seed,
        problem.alpha_max,
        &|a| problem.admits(a),
        progress,
    ))
}

/// Carries coarse `candidates` (cheapest first) to the fine grid: the index of the cheapest
/// admissible fine extremal and every distinct one refined, cheapest first (see the comments
/// for which). `best_residual` is the search's smallest defect, for the error when no
/// candidate was tried.
pub fn refine_candidates(
    problem: &Problem,
    candidates: &[search::Candidate],
    options: &SolveOptions,
    best_residual: f64,
) -> Result<(usize, Vec<Extremal>), SolveError> {
    let alpha_max = problem.shape_bound();
    // Carry candidates to the fine grid, cheapest first: admissible ones (with a margin for
    // the coarse grid's error in `|α|`) until the cheapest admissible fine extremal is settled
    // (every remaining candidate costs more, with a margin for the coarse grid's error in
    // `J`), then the inadmissible ones cheaper than it, for the report. A candidate that
    // costs more than the settled one on an intermediate grid stops there ([`PRUNE`]).
    let mut extremals: Vec<Extremal> = Vec::new();
    let mut refine_defect = f64::INFINITY;
    let near = |a: f64| a < alpha_max + COARSE_ALPHA_ERROR;
    let (maybe, beyond): (Vec<_>, Vec<_>) = candidates.iter().partition(|c| near(c.max_abs_alpha));
    let mut refined = 0;
    for (pass, list) in [maybe, beyond].into_iter().enumerate() {
        for c in list {
            let settled = extremals
                .iter()
                .filter(|x| x.admissible)
                .map(|x| x.cost)
                .fold(f64::INFINITY, f64::min);
            let margin = if pass == 0 {
                1.0 + COARSE_COST_ERROR
            } else {
                1.0
            };
            if refined >= options.refine || c.cost > settled * margin {
                break;
            }
            refined += 1;
            let (fine, run) = match refine(problem, &c.u, &c.nu, settled * (1.0 + PRUNE)) {
                Ok(r) => r,
                Err(stop) => {
                    if let Stop::Defect(d) = stop {
                        refine_defect = refine_defect.min(d);
                    }
                    continue;
                }
            };
            let mut x = extremal(problem, &fine, &run);
            x.start = c.start;
            x.hits = c.hits;
            if !extremals.iter().any(|o| {
                search::same_path(&o.trajectory.controls, &x.trajectory.controls, problem.h)
            }) {
                extremals.push(x);
            }
        }
    }
    if extremals.is_empty() {
        return Err(if refined == 0 {
            SolveError::Unreachable { best_residual }
        } else {
            SolveError::NotRefined {
                found: refined,
                best_residual: refine_defect,
            }
        });
    }
    extremals.sort_by(|a, b| a.cost.total_cmp(&b.cost));
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
    Ok((best, extremals))
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
                j != i && search::same_path(&extremals[j].trajectory.controls, &image, problem.h)
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::CERTIFICATES;

    #[test]
    fn each_certificate_message_names_its_bound() {
        for (bound, why) in CERTIFICATES {
            assert!(why.ends_with(&format!(" above {bound:e}")), "{why}");
        }
    }
}
