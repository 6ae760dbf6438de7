//! The global search: many start loops through the direct method on a coarse grid.
//!
//! Each start ([`super::starts`]) runs [`direct::newton`] on a grid of `M ≪ N` steps whose
//! rule mimics the fine problem's discretisation ([`super::stage::Rule::matching`]), so its
//! local minima and their costs match the fine problem's to about 1e-3 and cost a hundredth
//! of a fine solve. Without a
//! joint limit each start runs with a trust radius ([`settings::TRUST_RADIUS`]), so that it reaches a
//! minimum near its own loop. Starts run in batches (in parallel); converged points are grouped
//! into distinct extremals (same shape path to [`SAME_PATH`]). A converged point whose motion the
//! coarse grid does not resolve ([`Grid::resolves`]) is dropped.
//!
//! **Stopping rule.** After each batch, with `n` starts run and `b` the cheapest admissible
//! extremal so far, the minima that matter are those no dearer than `b` (`b` and cheaper
//! inadmissible ones). By the Good–Turing estimate, the chance that the next start reaches a
//! minimum not seen yet is about the share of starts that reached a minimum no other start
//! reached; restricted to the minima that matter, `f₁/n` with `f₁` the number of them
//! reached by exactly one start ([`Search::unseen`]). The search stops once at least
//! `min_starts` starts have run, `f₁/n ≤` [`UNSEEN`] (below 200 starts: no such minimum; from
//! 200: one; from 400: two) and `b` has been reached from [`CONFIRMATIONS`] starts (its basin
//! is not a lucky hit); it also stops when the zero loop solves the problem (`J = 0`), when
//! [`HOPELESS_BATCHES`] batches found nothing, or when `max_starts` (the budget) have run
//! ([`Search::satisfied`] is then false). Boender and Rinnooy Kan's Bayesian estimate of the
//! number of minima, `w(n−1)/(n−w−2)` for `w` distinct minima, is reported beside it
//! ([`Search::expected_minima`]).

use super::direct::{self, Run};
use super::grid::{self, Grid, Point};
use super::limits;
use super::settings::{
    self, BATCH, CONFIRMATIONS, HOPELESS_BATCHES, NEAR_TARGET, PATIENCE, SAME_PATH, Settings,
    UNSEEN,
};
use super::starts::{self, StartLoop};
use nalgebra::{Vector2, Vector5};
use purcell_core::Error;
use rayon::prelude::*;

/// A distinct local minimum of the coarse problem.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// Its controls on the coarse grid.
    pub u: Vec<Vector2<f64>>,
    /// Its terminal multiplier.
    pub nu: Vector5<f64>,
    /// `J` on the coarse grid.
    pub cost: f64,
    /// Largest `|α_i|` along it.
    pub max_abs_alpha: f64,
    /// Index of the first start that reached it (0: the zero loop).
    pub start: usize,
    /// How many starts reached it.
    pub hits: usize,
    /// The start loop of `start` (`None` for the zero loop).
    pub start_loop: Option<StartLoop>,
}

/// Outcome of [`search`].
#[derive(Clone, Debug, Default)]
pub struct Search {
    /// Distinct converged extremals, cheapest first.
    pub candidates: Vec<Candidate>,
    /// Start loops run (the zero loop, tried first, not counted).
    pub starts: usize,
    /// Smallest terminal defect among the starts that did not converge.
    pub best_residual: f64,
    /// Converged starts dropped because their motion was not resolved by the coarse grid
    /// ([`Grid::resolves`]).
    pub unresolved: usize,
    /// The stopping rule's estimate `f₁/n` when the search stopped (see the module docs).
    pub unseen: f64,
    /// Whether the stopping rule was met (otherwise the budget ran out first, or nothing was
    /// found).
    pub satisfied: bool,
}

impl Search {
    /// Boender and Rinnooy Kan's posterior estimate of the number of distinct minima,
    /// `w(n−1)/(n−w−2)` (`∞` while `n ≤ w + 2`).
    pub fn expected_minima(&self) -> f64 {
        let (w, n) = (self.candidates.len() as f64, self.starts as f64);
        if n > w + 2.0 {
            w * (n - 1.0) / (n - w - 2.0)
        } else {
            f64::INFINITY
        }
    }

    /// The stopping rule's estimate `f₁/n` after `self.starts` starts, and whether the
    /// cheapest admissible candidate `b` is confirmed (see the module docs).
    fn rule(&self, admissible: &(dyn Fn(f64) -> bool + Sync)) -> (f64, bool) {
        let b = cheapest_admissible(&self.candidates, admissible);
        let bound = b.map_or(f64::INFINITY, |b| b.cost);
        let once = self
            .candidates
            .iter()
            .filter(|c| c.cost <= bound && c.hits == 1)
            .count();
        let confirmed = b.is_some_and(|b| b.hits >= CONFIRMATIONS);
        (once as f64 / self.starts.max(1) as f64, confirmed)
    }
}

/// Runs at least `min_starts` (at most `max_starts`) start loops and the zero loop on `grid`;
/// `admissible` decides from the largest `|α_i|` whether an extremal counts for the stopping
/// rule; `progress` is called once per finished start. With a joint limit `limit`, the starts
/// are shrunk into it and run through the barrier path ([`super::limits`]): the candidates
/// are then minima of the barrier problem at its last weight.
pub fn search(
    grid: &Grid,
    min_starts: usize,
    max_starts: usize,
    seed: u64,
    limit: Option<f64>,
    admissible: &(dyn Fn(f64) -> bool + Sync),
    progress: &(dyn Fn() + Sync),
) -> Search {
    let size = starts::reference_size(grid);
    let alpha0 = Vector2::new(grid.start[0], grid.start[1]);
    let family = starts::family(size, &alpha0, seed, max_starts, limit.is_none());
    // The zero loop first: the solution when the target is the start (J = 0); for any other
    // target its Newton step is singular and it stops at once.
    let all: Vec<(usize, Option<StartLoop>)> = core::iter::once((0, None))
        .chain(family.iter().enumerate().map(|(i, s)| (i + 1, Some(*s))))
        .collect();
    // Newton iterations per start (per barrier weight with a limit): the first of
    // [`PATIENCE`]; the second for a search with a limit whose first pass found nothing
    // though a start came near the target ([`NEAR_TARGET`]).
    let run = |patience: usize, best_residual: f64| {
        let settings = Settings::search(patience, limit.is_some());
        let mut out = Search {
            best_residual,
            ..Search::default()
        };
        // The zero loop rides with the first batch of start loops.
        let (first, rest) = all.split_at((1 + BATCH).min(all.len()));
        for batch in core::iter::once(first).chain(rest.chunks(BATCH)) {
            let results: Vec<_> = batch
                .par_iter()
                .map(|&(index, start_loop)| {
                    let r = run_start(grid, limit, &settings, index, start_loop);
                    progress();
                    (index, start_loop, r)
                })
                .collect();
            for (index, start_loop, r) in results {
                out.absorb(grid, index, start_loop, r);
            }
            if out.after_batch(min_starts, admissible) {
                break;
            }
        }
        out
    };
    let out = run(PATIENCE[0], f64::INFINITY);
    // Nothing found, but a start ended near the target: the starts ran out of iterations, not
    // of room (with a tight limit the barrier paths spend long pinned to it).
    let near = out.best_residual <= NEAR_TARGET * (grid.terminal.target - grid.start).amax();
    if out.candidates.is_empty() && limit.is_some() && near {
        run(PATIENCE[1], out.best_residual)
    } else {
        out
    }
}

/// Start `index` (the loop `start_loop`; `None`: the zero loop) through Newton on `grid`;
/// with a joint limit `limit`, shrunk into it and along its barrier path.
fn run_start(
    grid: &Grid,
    limit: Option<f64>,
    settings: &Settings,
    index: usize,
    start_loop: Option<StartLoop>,
) -> Result<Run, Error> {
    let u = start_loop.map_or_else(|| vec![Vector2::zeros(); grid.steps], |s| s.controls(grid));
    match limit {
        None => {
            Point::new(grid, u, Vector5::zeros()).and_then(|p| direct::newton(grid, p, settings))
        }
        Some(a) => {
            let alpha0 = Vector2::new(grid.start[0], grid.start[1]);
            let u = limits::shrink_into(u, &alpha0, a, grid.h());
            Point::new(grid, u, Vector5::zeros()).and_then(|p| {
                limits::barrier_path(grid, a, settings::coarse_path(index), p, settings)
            })
        }
    }
}

impl Search {
    /// Counts start `index` (loop `start_loop`) and files its run `r`: a converged one as
    /// another hit of a candidate with the same path, or as a new candidate if the grid
    /// resolves its motion; the defect of one that did not converge.
    fn absorb(
        &mut self,
        grid: &Grid,
        index: usize,
        start_loop: Option<StartLoop>,
        r: Result<Run, Error>,
    ) {
        self.starts += usize::from(index > 0);
        let Ok(run) = r else { return };
        if !run.converged {
            self.best_residual = self.best_residual.min(run.defect);
            return;
        }
        if let Some(c) = self
            .candidates
            .iter_mut()
            .find(|c| same_path(&c.u, &run.point.u, grid.h()))
        {
            c.hits += 1;
            if index < c.start {
                c.start = index;
                c.start_loop = start_loop;
            }
            return;
        }
        // Checked once per distinct extremal (a rollout 16 times finer).
        if !grid.resolves(&run.point.u) {
            self.unresolved += 1;
            return;
        }
        let cost = grid.cost(&run.point.u);
        let max_abs_alpha = grid::max_abs_alpha(&run.point.states);
        self.candidates.push(Candidate {
            u: run.point.u,
            nu: run.point.nu,
            cost,
            max_abs_alpha,
            start: index,
            hits: 1,
            start_loop,
        });
    }

    /// After a batch: the candidates sorted, the stopping rule's estimate and verdict
    /// updated; whether the search stops (the rule is met, or it is hopeless).
    fn after_batch(
        &mut self,
        min_starts: usize,
        admissible: &(dyn Fn(f64) -> bool + Sync),
    ) -> bool {
        self.candidates.sort_by(|a, b| a.cost.total_cmp(&b.cost));
        let (unseen, confirmed) = self.rule(admissible);
        self.unseen = unseen;
        self.satisfied = confirmed && unseen <= UNSEEN && self.starts >= min_starts;
        // The zero target is solved by the zero loop; nothing can be cheaper.
        let trivial =
            cheapest_admissible(&self.candidates, admissible).is_some_and(|c| c.cost == 0.0);
        self.satisfied |= trivial;
        // Nothing at all after a few batches: the target is out of reach (or needs more
        // starts than the default; `--starts` bounds the search, not this rule).
        let hopeless = self.candidates.is_empty() && self.starts >= HOPELESS_BATCHES * BATCH;
        self.satisfied || hopeless
    }
}

fn cheapest_admissible<'a>(
    candidates: &'a [Candidate],
    admissible: &(dyn Fn(f64) -> bool + Sync),
) -> Option<&'a Candidate> {
    candidates.iter().find(|c| admissible(c.max_abs_alpha))
}

/// Whether two control sequences run the same shape path (to [`SAME_PATH`] at every node).
pub fn same_path(a: &[Vector2<f64>], b: &[Vector2<f64>], h: f64) -> bool {
    let mut d = Vector2::zeros();
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            d += (x - y) * h;
            d.amax() <= SAME_PATH
        })
}
