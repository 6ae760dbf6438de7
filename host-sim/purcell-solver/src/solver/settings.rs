//! The solver's settings and tolerances, each named once with its meaning.
//!
//! - [`Settings`]: the stopping and step rules of one Newton–SQP run, with a preset per use:
//!   the global search's starts ([`Settings::search`]), the refinement's intermediate and
//!   fine grids ([`Settings::INTERMEDIATE`], [`Settings::fine`]) and its barrier path
//!   ([`Settings::barrier`]), a warm start's walk ([`Settings::warm`]) and a sweep's
//!   neighbour passes ([`Settings::NEIGHBOURS`]).
//! - Convergence thresholds ([`TOL_DEFECT`] …), the joint limit's interior-point path
//!   ([`COARSE_PATHS`] …), the line search and inertia correction ([`MIN_STEP`] …), the
//!   Riccati step's pivots ([`PIVOT`] …), the global search ([`TRUST_RADIUS`] …), the
//!   refinement's margins ([`PRUNE`] …), the warm start ([`MIN_WALK_STEP`] …) and the
//!   certificates' bounds ([`TERMINAL_TOL`] …).
//!
//! When a state counts as on the joint limit, from the loosest: within [`NEAR`] (the end of
//! a barrier path, where arcs are found); past it by more than [`PAST_LIMIT`] (a violation
//! in the active-set rounds); at it to [`ON_LIMIT`] (the KKT certificate); and admissible
//! to [`crate::problem::LIMIT_ROUNDING`] (the problem's own definition).

use crate::problem::Problem;
use nalgebra::Vector2;

/// The settings of a solve: the global search's budget and grid, and how many candidates
/// are refined.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveOptions {
    /// Most start loops of the global search, its budget (without a joint limit it stops
    /// earlier once its stopping rule is met, [`super::search`]); `None`: the problem's default
    /// ([`SolveOptions::budget`]).
    pub starts: Option<usize>,
    /// Fewest start loops of the global search before its stopping rule may end it (unless
    /// `starts` is smaller); `None`: the problem's default ([`SolveOptions::starts`]).
    pub min_starts: Option<usize>,
    /// Orders the start loops after the first `min_starts` (seed 0's for every seed; under a
    /// joint limit every seed runs seed 0's order).
    pub seed: u64,
    /// Steps of the coarse grid of the global search.
    pub coarse_steps: usize,
    /// Most candidates carried to the fine grid (those Newton cannot carry do not count).
    pub refine: usize,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            starts: None,
            min_starts: None,
            seed: 0,
            coarse_steps: 64,
            refine: 6,
        }
    }
}

impl SolveOptions {
    /// The search's budget for `problem`: `starts` if given, else [`FREE_STARTS`] without a
    /// joint limit and [`LIMITED_STARTS`] with one.
    pub fn budget(&self, problem: &Problem) -> usize {
        self.starts.unwrap_or(match problem.alpha_max {
            None => FREE_STARTS,
            Some(_) => LIMITED_STARTS,
        })
    }

    /// The search's fewest to most starts for `problem`: `min_starts` if given, else
    /// [`FREE_MIN_STARTS`] without a joint limit and [`LIMITED_MIN_STARTS`] with one, to
    /// [`SolveOptions::budget`].
    pub fn starts(&self, problem: &Problem) -> core::ops::RangeInclusive<usize> {
        let fewest = self.min_starts.unwrap_or(match problem.alpha_max {
            None => FREE_MIN_STARTS,
            Some(_) => LIMITED_MIN_STARTS,
        });
        fewest..=self.budget(problem)
    }
}

/// Stopping and step rules of one run of Newton–SQP ([`super::direct::newton`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Iteration limit.
    pub max_iterations: usize,
    /// Largest terminal defect accepted (m, rad).
    pub tol_defect: f64,
    /// Largest stationarity residual accepted (rad/s).
    pub tol_kkt: f64,
    /// With a barrier: start each line search at the fraction to the boundary
    /// ([`FRACTION_TO_BOUNDARY`]) rather than at the full step, so that no state comes
    /// closer to the limit than 1 % of its distance in one step (IPOPT's rule).
    pub fraction_to_boundary: bool,
    /// With a barrier, IPOPT's primal–dual step: the bound multipliers `z` carried as iterates
    /// and the barrier's Hessian `Σ = z/d` in place of the primal `τ/d²`
    /// ([`Limits::dual_step`]); the refinement's second try of a candidate whose primal path
    /// stalled ([`super::refinement`]).
    ///
    /// [`Limits::dual_step`]: super::constraints::joint_limit::Limits::dual_step
    pub primal_dual: bool,
    /// Largest change of any shape `α_{k,i}` in one iteration, radians (`f64::INFINITY`:
    /// none); see [`super::direct`].
    pub trust_radius: f64,
    /// Whether a run whose terminal defect is met also ends converged when Newton has
    /// stalled at rounding: its last step was Newton's own (no regularisation, `δ = 0`) and
    /// moved no control by more than [`ROUNDING_STEP`] of the largest, while stationarity
    /// stays within [`ROUNDING_KKT`] times `tol_kkt` (the barrier's gradient `τ/d` near the
    /// limit puts a rounding floor under the stationarity residual on fine grids). Only the
    /// refinement's barrier path ([`Settings::barrier`]), whose end the active-set rounds
    /// converge and certify themselves.
    pub rounding_stall: bool,
    /// Whether a converged run checks the second-order sufficient condition (one more
    /// factorisation, [`super::direct::Status::LocalMin`]); without, it ends
    /// [`super::direct::Status::Stationary`]. Off where only convergence counts: the
    /// search's starts and the refinement's intermediate grids and barrier paths.
    pub second_order: bool,
}

impl Settings {
    /// `max_iterations` Newton iterations to [`TOL_DEFECT`] and [`TOL_KKT`], plain line
    /// search, no trust radius: the coarse and intermediate grids' settings, which the other
    /// presets adjust field by field.
    pub const fn plain(max_iterations: usize) -> Self {
        Settings {
            max_iterations,
            tol_defect: TOL_DEFECT,
            tol_kkt: TOL_KKT,
            fraction_to_boundary: false,
            primal_dual: false,
            trust_radius: f64::INFINITY,
            second_order: true,
            rounding_stall: false,
        }
    }

    /// [`Settings::plain`] without the second-order check (see [`Settings::second_order`]).
    const fn first_order(max_iterations: usize) -> Self {
        Settings {
            second_order: false,
            ..Settings::plain(max_iterations)
        }
    }

    /// A start of the global search: `patience` iterations (per barrier weight with a joint
    /// limit, [`PATIENCE`]); without a joint limit (`limited = false`) the [`TRUST_RADIUS`].
    pub fn search(patience: usize, limited: bool) -> Self {
        Settings {
            trust_radius: if limited { f64::INFINITY } else { TRUST_RADIUS },
            ..Settings::first_order(patience)
        }
    }

    /// The intermediate grids of a refinement without a joint limit.
    pub const INTERMEDIATE: Settings = Settings::first_order(30);

    /// The problem's own grid, relative to the problem's scale: the terminal defect to
    /// [`FINE_DEFECT`] of the displacement asked for (within [`FINE_DEFECT_MIN`] …
    /// [`FINE_DEFECT_MAX`]), stationarity to [`FINE_KKT`] of the largest of `controls` (at
    /// least [`FINE_KKT_MIN`] rad/s); 30 iterations.
    pub fn fine(problem: &Problem, controls: &[Vector2<f64>]) -> Self {
        let t = problem.target;
        let scale = (t.x * t.x + t.y * t.y).sqrt().max(t.z.abs());
        let umax = controls.iter().map(|u| u.amax()).fold(0.0, f64::max);
        Settings {
            tol_defect: (FINE_DEFECT * scale).clamp(FINE_DEFECT_MIN, FINE_DEFECT_MAX),
            tol_kkt: (FINE_KKT * umax).max(FINE_KKT_MIN),
            ..Settings::plain(30)
        }
    }

    /// The barrier path of a refinement with a joint limit: `patience` iterations per weight,
    /// stationarity to [`BARRIER_TOL_KKT`] (or stalled at rounding near it,
    /// [`Settings::rounding_stall`]), every step stopped at the fraction to the boundary.
    pub fn barrier(patience: usize) -> Self {
        Settings {
            tol_kkt: BARRIER_TOL_KKT,
            fraction_to_boundary: true,
            rounding_stall: true,
            ..Settings::first_order(patience)
        }
    }

    /// These settings with the primal–dual step ([`Settings::primal_dual`]) or without.
    pub fn with_primal_dual(self, primal_dual: bool) -> Self {
        Settings {
            primal_dual,
            ..self
        }
    }

    /// These settings at the barrier weight `tau` of a path: as they are at its last weight
    /// (`last`), otherwise the tolerances relaxed to [`BARRIER_KAPPA`]`·tau`.
    pub fn at_weight(&self, tau: f64, last: bool) -> Self {
        if last {
            return *self;
        }
        Settings {
            tol_defect: self.tol_defect.max(BARRIER_KAPPA * tau),
            tol_kkt: self.tol_kkt.max(BARRIER_KAPPA * tau),
            ..*self
        }
    }

    /// The walk of a warm start in its target ([`super::continuation`]): 30 iterations per
    /// point; with a joint limit (`limited`), the first of [`PATIENCE`] and the fraction to
    /// the boundary.
    pub fn warm(limited: bool) -> Self {
        let plain = Settings::plain(30);
        if limited {
            Settings {
                max_iterations: PATIENCE[0],
                fraction_to_boundary: true,
                ..plain
            }
        } else {
            plain
        }
    }

    /// A sweep's neighbour passes on the coarse grid ([`super::continuation::sweep`]).
    pub const NEIGHBOURS: Settings = Settings::plain(40);
}

// Convergence.

/// Terminal defect of the coarse and intermediate grids (m, rad).
pub const TOL_DEFECT: f64 = 1e-10;
/// Stationarity of the coarse and intermediate grids (rad/s).
pub const TOL_KKT: f64 = 1e-8;
/// The problem's grid: terminal defect relative to the displacement asked for.
pub const FINE_DEFECT: f64 = 1e-11;
/// Smallest terminal defect asked for on the problem's grid (m, rad).
pub const FINE_DEFECT_MIN: f64 = 1e-15;
/// Largest terminal defect accepted on the problem's grid (m, rad).
pub const FINE_DEFECT_MAX: f64 = 1e-12;
/// The problem's grid: stationarity relative to the largest control.
pub const FINE_KKT: f64 = 1e-10;
/// Smallest stationarity asked for on the problem's grid (rad/s).
pub const FINE_KKT_MIN: f64 = 1e-13;
/// Stationarity of the refinement's barrier path (rad/s): the barrier's Hessian grows like
/// `τ/d²` near the limit, so it is asked only this much at the small weights; the path is
/// there to find the arcs, the active-set rounds converge the constrained problem itself.
pub const BARRIER_TOL_KKT: f64 = 1e-6;
/// A Newton step that moves no control by more than this share of the largest is at
/// rounding ([`Settings::rounding_stall`]): on the 10 000-step grid of `α_max = 1.1`, target
/// (0, 0, 0.3), the barrier path's last weight took steps of 1e-12 (against 1e-1 controls)
/// for 13 iterations with stationarity 1.3–2.9e-6.
pub const ROUNDING_STEP: f64 = 1e-9;
/// Stationarity a run stalled at rounding may keep, as a multiple of its tolerance
/// ([`Settings::rounding_stall`]).
pub const ROUNDING_KKT: f64 = 10.0;

// The joint limit (MODEL.md §9, [`super::homotopy`]).

/// Barrier weights of the coarse grid's paths: a start's path begins at `1e-3` or, for about
/// half of the start loops ([`super::starts::StartLoop::path`]), at `1e-2` (a stronger push
/// off the limit at first leads to other basins).
pub const COARSE_PATHS: [&[f64]; 2] = [&[1e-3, 1e-4, 1e-5, 1e-6], &[1e-2, 1e-3, 1e-4, 1e-5, 1e-6]];
/// Each weight `τ` of a barrier path but the last is solved only to `κ·τ`, this `κ`, in
/// the terminal defect and in stationarity (IPOPT's barrier subproblem tolerance
/// `ε_μ = κ_ε·μ`, `κ_ε = 10`): the path has only to follow the barrier's minimisers to its
/// last weight, which is solved to the run's own tolerances ([`Settings::at_weight`]).
pub const BARRIER_KAPPA: f64 = 10.0;
/// The coarse grid's barrier path number `i` ([`COARSE_PATHS`], `i` taken modulo 2).
pub fn coarse_path(i: usize) -> &'static [f64] {
    COARSE_PATHS[i % 2]
}
/// [`COARSE_PATHS`] from the far end of the central path first, `τ = 1e-1` (IPOPT's first
/// barrier weight `μ₀`), solved to [`BARRIER_KAPPA`]`·τ` = 1 like every weight but the last: a
/// start loop's second path under a joint limit ([`super::search`]).
pub const CENTRAL_PATHS: [&[f64]; 2] = [
    &[1e-1, 1e-3, 1e-4, 1e-5, 1e-6],
    &[1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6],
];
/// The last weight of the coarse paths: the coarse problem's barrier.
pub const COARSE_TAU: f64 = 1e-6;
/// Barrier weights of the fine grid before the active set is fixed.
pub const FINE_TAUS: [f64; 4] = [1e-6, 1e-7, 1e-8, 1e-9];
/// Larger barrier weights before [`FINE_TAUS`] for a refinement's grid whose path stalled at
/// its first weight ([`super::refinement`]).
pub const RESCUE_TAUS: [f64; 2] = [1e-4, 1e-5];
/// Newton iterations per barrier weight; the second for a path that ran out of the first (as
/// one pinned to a tight limit can). In the search, the first for a start without a joint
/// limit and for a rim loop, the second for every other start under one ([`super::search`]: on the coarse grid of
/// `α_max = 1.2`, target (0, 0, −0.5), the starts that converge take up to 299 iterations at
/// their first weight; 14 of 936 converge within 100, 136 within 200, 219 within 300).
pub const PATIENCE: [usize; 2] = [100, 300];
/// Iterations per barrier weight on a refinement's intermediate grids after the first
/// before the path is taken from [`RESCUE_TAUS`] instead ([`super::refinement`]); on the
/// problem's grid, primal ones before a candidate's path goes on with primal–dual ones
/// ([`super::homotopy::Steps::PrimalThenDual`]).
pub const QUICK_PATIENCE: usize = 20;
/// The periods `m` of the gaits flown `m` times that a limited solve tries where its search
/// finds no gait ([`super::periodic`]), those that divide the problem's steps.
pub const PERIODS: [usize; 4] = [2, 3, 4, 5];
/// Iterations per barrier weight, where [`PATIENCE`]`[0]` do not converge, of the refinement
/// of a gait flown `m` times ([`super::periodic`]): from the tiled loops the problem's grid
/// walks far (at `α_max = 1`, links 1, 0.93, 0.93, target (0.144, 0.023, −0.44), `m = 2`: J
/// 6.37 → 6.10, with the inertia corrected at most steps), and 300 iterations stall.
pub const PERIODIC_PATIENCE: usize = 3000;
/// Steps of the grid on which a flown gait is sampled for its refinement's second start
/// ([`super::periodic`]): the first of the gradual grids ([`GRADUAL_STEPS`] / 4).
pub const FLOWN_SAMPLE: usize = GRADUAL_STEPS / 4;
/// Steps of the grid on which a limited solve's gaits are walked back up the central path
/// and down again ([`super::recentre`]): the first of the gradual grids, as [`FLOWN_SAMPLE`].
pub const RECENTRE_STEPS: usize = GRADUAL_STEPS / 4;
/// A recentred walk ([`super::recentre`]) that ends within this distance (radians, largest
/// at any node, [`super::grid::path_distance`]) of its gait's own path sampled on its grid
/// is in that gait's basin and is not refined. On 27 limited problems (issue 33, twenty-second
/// session) the walks back into the answer's basin ended 0.002–0.15 rad from it; the one that
/// reached IPOPT's cheaper gait (`--alpha-max 1.5 --target -0.053,-0.226,0.53`) 1.72 rad.
pub const RECENTRE_SAME: f64 = 0.25;
/// Most active-set rounds (from a barrier solution on the same grid, two suffice: arcs
/// found, then confirmed).
pub const ROUNDS: usize = 6;
/// A start's shape path is shrunk about `ᾱ` to within this share of the limit.
pub const SHRINK: f64 = 0.95;
/// A warm gait within the limit is clipped to `(1 − WARM_INSIDE)·α_max`: just inside it.
pub const WARM_INSIDE: f64 = 1e-3;
/// A state this close to the limit (radians) at the end of the barrier path is on an arc.
pub const NEAR: f64 = 1e-6;
/// Where the active-set rounds from the states within [`NEAR`] fail, they run once more from
/// those within this share of `α_max` ([`super::homotopy::polish`]).
pub const LOOSE_NEAR: f64 = 1e-5;
/// In the active-set rounds, a state off the arcs beyond the limit by more than this share
/// of `α_max` violates it (less is rounding).
pub const PAST_LIMIT: f64 = 1e-12;
/// In the active-set rounds, an arc state's multiplier `η_k ≥ −ETA_ROUNDING·max|η|` counts as
/// `η_k ≥ 0` (rounding).
pub const ETA_ROUNDING: f64 = 1e-9;
/// The KKT certificate takes a state with `|α_i| ≥ α_max (1 − ON_LIMIT)` as on the limit.
pub const ON_LIMIT: f64 = 1e-12;
/// IPOPT's fraction to the boundary: a step keeps this share of each state's distance from
/// the limit ([`Settings::fraction_to_boundary`]); also the share of the bound multipliers
/// a primal–dual step keeps ([`Settings::primal_dual`]).
pub const FRACTION_TO_BOUNDARY: f64 = 0.99;
/// IPOPT's `κ_Σ`: after each primal–dual step the bound multipliers are kept within
/// `[τ/(κ_Σ d), κ_Σ τ/d]` ([`Settings::primal_dual`]), so that `Σ = z/d` stays within a
/// factor `κ_Σ` of the primal `τ/d²`.
pub const KAPPA_SIGMA: f64 = 1e10;
/// A line-search trial that takes a state past the limit by more than this (radians, more
/// than rounding) is skipped without a rollout.
pub const WALL_SLACK: f64 = 1e-12;

// The line search (a filter, Wächter & Biegler, with IPOPT's constants) and the inertia
// correction ([`super::direct`]).

/// The shortest step tried.
pub const MIN_STEP: f64 = 1e-12;
/// Each rejected trial halves the step.
pub const BACKTRACK: f64 = 0.5;
/// The filter's `γ_θ`: a trial must lower `θ = |c|₁` by this share of `θ`…
pub const FILTER_GAMMA_THETA: f64 = 1e-5;
/// …or the cost by `γ_φ·θ`.
pub const FILTER_GAMMA_PHI: f64 = 1e-5;
/// The filter's Armijo constant `η_φ`.
pub const FILTER_ETA: f64 = 1e-4;
/// The switching condition's exponent `s_θ`.
pub const FILTER_S_THETA: f64 = 1.1;
/// The switching condition's exponent `s_φ`.
pub const FILTER_S_PHI: f64 = 2.3;
/// No trial with `θ` above this multiple of `max(θ_0, 1)` is accepted.
pub const FILTER_THETA_MAX: f64 = 1e4;
/// Below this multiple of `max(θ_0, 1)` an iterate is nearly feasible (the Armijo rule
/// applies).
pub const FILTER_THETA_MIN: f64 = 1e-4;
/// The first regularisation `δ` tried, relative to `h`.
pub const DELTA_MIN: f64 = 1e-6;
/// The largest `δ`, relative to `h`: beyond it the iteration stops.
pub const DELTA_MAX: f64 = 1e10;
/// `δ` grows by this factor until the QP is convex on the constraint's null space.
pub const DELTA_GROWTH: f64 = 10.0;
/// The next iteration's first `δ` is the last one divided by this.
pub const DELTA_DECAY: f64 = 3.0;

// The Riccati step ([`super::riccati`]).

/// A pivot `Q̂_uu` is singular when `|det| ≤ PIVOT·(largest entry)²`.
pub const PIVOT: f64 = 1e-14;
/// `M` is singular when an eigenvalue is within this share of the largest.
pub const SINGULAR: f64 = 1e-13;
/// The refinement of `ν` stops once the open-loop end misses `e` by this share of `e`…
pub const REFINE_MISS: f64 = 1e-13;
/// …or after this many passes…
pub const REFINE_PASSES: usize = 3;
/// …or when a pass shrinks the miss by less than this factor.
pub const REFINE_GAIN: f64 = 0.5;

// The global search ([`super::search`]).

/// Trust radius of the starts without a joint limit, radians ([`Settings::trust_radius`]).
pub const TRUST_RADIUS: f64 = 0.3;
/// The default budget of a search without a joint limit ([`SolveOptions::budget`]). Its
/// stopping rule is usually met long before (160–400 starts) and then the count changes
/// nothing (the family's order does not depend on it, [`super::starts::family`]); where it is
/// not, 512 left seed 6 of `--ratio 2.5 --target 0,-0.15,0.2` at a dearer minimum (0.8175969
/// against 0.8043649) and 1024 make seeds 0–7 agree (issue 33).
pub const FREE_STARTS: usize = 1024;
/// The default budget of a search under a joint limit (every seed runs seed 0's order,
/// [`super::search`]): the 96 rim loops of a loop problem ([`super::starts::rims`]) and 64 of
/// the family. On 33 limited problems (`α_max` 0.9–3.1 on the paper's target, turning,
/// lateral and short targets, a bent start, drag ratio 2.1) every cost is that of the 512
/// loops of the family without rims, at 0.48 of the CPU time (issue 33, fourteenth session).
pub const LIMITED_STARTS: usize = 160;
/// The fewest starts of a search without a joint limit before its stopping rule may end it
/// ([`SolveOptions::starts`]).
pub const FREE_MIN_STARTS: usize = 128;
/// The fewest starts of a search under a joint limit before its stopping rule may end it
/// ([`SolveOptions::starts`]): the rim loops of 1–4 turns. On 41 limited problems every cost
/// is that of the whole budget's (so with 32), and where the rule is met (the looser limits)
/// the solve takes 0.6–0.7 of the time (issue 33, fifteenth session).
pub const LIMITED_MIN_STARTS: usize = 64;
/// Most turns of the rim loops under a joint limit ([`super::starts::rims`]): the paper's
/// target at `α_max = 0.9` (16 arcs) is reached only from rims of 6 turns; `0.95`, `1.0`
/// and `1.05` from 4–6.
pub const RIM_TURNS: u32 = 6;
/// Starts per batch.
pub const BATCH: usize = 32;
/// How many starts must reach the cheapest admissible extremal before the search stops.
pub const CONFIRMATIONS: usize = 3;
/// Largest estimated chance that a further start reaches a minimum not seen yet that is no
/// dearer than the cheapest admissible one, for the search to stop.
pub const UNSEEN: f64 = 0.005;
/// Batches without any extremal after which a search without a joint limit gives up (one
/// under a limit then runs its whole budget: the family's loops come after the 96 rims,
/// [`super::search`]).
pub const HOPELESS_BATCHES: usize = 3;
/// Two control sequences run the same shape path when their shapes agree to this (radians)
/// at every node.
pub const SAME_PATH: f64 = 1e-6;
/// Without a joint limit, a minimum past the links' overlap is pulled inside the barrier at
/// this share of `π` ([`super::search`]): far enough inside that the barrier's minimum near
/// an admissible extremal (largest `|α_i|` about 3.03 in the cases that needed it) is that
/// extremal, which Newton then reaches without the barrier.
pub const PULL: f64 = 0.97;
/// Without a joint limit, when every extremal found crosses the links' overlap, `solve`
/// returns the cheapest gait within `|α_i| ≤ π − OVERLAP_MARGIN` (radians), with a warning:
/// on the far and turning targets whose extremals all cross it ((0.3, −0.25, 1), (0.15, 0.25,
/// −0.6), (0, 0.4, 0), (0, 0, 2.8)), that limit's search finds a gait for each.
pub const OVERLAP_MARGIN: f64 = 0.1;

// The refinement ([`super::refine_candidates`]).

/// Relative margin by which an extremal on an intermediate grid of a refinement must cost
/// more than the settled cheapest one on the same grid to be dropped there: the 1 024-step
/// grid's cost is within 3.2e-5 of the problem's own (measured over 60 extremals of 14
/// problems, with and without joint limits; the coarse grid's is within 8e-3, hence
/// [`COARSE_COST_ERROR`]); the 256-step grid's of a joint limit's 3e-3 (the same extremal at
/// `α_max = 1.1`, target (0, 0, 0.3)), hence the settled one's own cost there. On grids of
/// at least [`GRADUAL_STEPS`] steps, [`FINE_PRUNE`].
pub const PRUNE: f64 = 1e-3;
/// [`PRUNE`] on an intermediate grid of at least [`GRADUAL_STEPS`] steps: each extremal's
/// cost there is within 3.2e-5 of its cost on the problem's grid, so two of them are in the
/// problem's order once they differ by more than 6.4e-5, a third of this. At `α_max = 1.5`
/// (the paper's target) the second extremal, 1.2116535 (6.6e-4 above 1.2108538 on the
/// problem's grid), was carried there with [`PRUNE`]: 0.2 s of the 1.8 s solve.
pub const FINE_PRUNE: f64 = 2e-4;
/// Relative margin for the coarse grid's error in `J`: an admissible candidate dearer than
/// the settled cheapest by more is not refined.
pub const COARSE_COST_ERROR: f64 = 1e-2;
/// [`COARSE_COST_ERROR`] with a joint limit, whose arcs the coarse grid resolves coarsely:
/// coarse minima were 0.8–7 % off the problem's (`α_max = 1.1`, target (0, 0, 0.3): 1.8477
/// against 1.7266; `α_max = 1.3`, (0, 0.1, 0): 1.5077 against 1.5494).
pub const LIMITED_COARSE_COST_ERROR: f64 = 0.1;
/// With a joint limit, a coarse minimum whose path, prolonged to the next grid, ends farther
/// from the target than this share of the displacement asked for is not resolved by the
/// coarse grid: it is refined only if the resolved ones settle no admissible extremal
/// ([`super::refinement::refine_candidates`]). The coarse minima that refine miss by
/// 0.2–0.6 %; those whose barrier path on the next grid stalls (and which cost about 1 s of
/// Newton each before they give up) by 2–7 %.
pub const UNRESOLVED: f64 = 0.012;
/// With a joint limit, an unresolved coarse minimum ([`UNRESOLVED`]) that misses by more than
/// this share is refined only if no other candidate settles an admissible extremal
/// ([`super::refinement::refine_candidates`]); otherwise, if it costs less on the coarse grid
/// than the settled one, it is walked back up the central path and carried from there. On 40
/// limited problems (MEASUREMENTS, 2026-11-29) every coarse minimum that refined missed by at
/// most 1.8 %, and every one that missed by more than 5 % (8.2–20 %, 44 of them, 0.3–1.2 s of
/// Newton each) stalled on the next grid; walked (0.01–0.4 s each), at `α_max = 0.95` two of
/// them reach gaits 3.5 % cheaper than the settled one.
pub const FAR_MISS: f64 = 0.05;
/// Under a joint limit the refinement's grids are at most 4 times finer each up to this many
/// steps (64, 256, 1 024), then at most 16 times (to the problem's), [`super::refinement`].
pub const GRADUAL_STEPS: usize = 1024;
/// When no minimum of the search refines ([`super::SolveError::NotRefined`]), the search runs
/// again on grids twice as fine, up to this many times the options' coarse steps
/// ([`super::solve`]): 64, 128, 256 by default.
pub const FINER_COARSE: usize = 4;
/// Under a joint limit, a search whose starts all failed but one ended within this share of
/// the displacement asked for came near the target ([`super::SolveError::Unreachable`]): its
/// grid may be too coarse for the limit's arcs, and it runs again on a finer one as above
/// (`α_max = 0.95` on 32 steps, 128 starts: none converged, the best defect 3.0e-4, 2.1e-3 of the
/// displacement, since a path's weights but its last are solved only to [`BARRIER_KAPPA`]`·τ`
/// (3.5e-8 when they were solved to the run's tolerances); 64 steps solve).
pub const NEAR_TARGET: f64 = 1e-2;
/// Margin for the coarse grid's error in `|α|` (radians): a candidate whose largest `|α_i|`
/// is below the bound on the shape plus this may be admissible on the problem's grid.
pub const COARSE_ALPHA_ERROR: f64 = 0.05;

// Warm starts and sweeps ([`super::continuation`]).

/// The walk in the target gives up when its step falls below this share of the way.
pub const MIN_WALK_STEP: f64 = 1e-3;
/// Two targets of a lattice are the same when they agree to `SAME_TARGET·(1 + |t|_∞)`.
pub const SAME_TARGET: f64 = 1e-12;

// Certificates ([`super::Extremal::uncertified`]): what a returned extremal is held to.

/// Largest terminal defect through the core's kinematics (m, rad).
pub const TERMINAL_TOL: f64 = 1e-10;
/// Largest KKT residual (rad/s).
pub const KKT_TOL: f64 = 1e-8;
/// Largest relative deviation of the core's law from the controls.
pub const LAW_TOL: f64 = 1e-9;
