//! The global search: many start loops through the direct method on a coarse grid.
//!
//! Each start ([`super::starts`]) runs [`super::direct::newton`] on a grid of `M ≪ N` steps
//! whose rule mimics the fine problem's discretisation ([`super::stage::Rule::matching`]), so
//! its local minima and their costs match the fine problem's to about 1e-3 and cost a
//! hundredth of a fine solve. Without a joint limit each start runs with a trust radius
//! ([`super::settings::TRUST_RADIUS`]), so that it reaches a minimum near its own loop. Starts run in batches (in parallel); converged points are grouped
//! into distinct extremals (same shape path, [`grid::same_path`]). A converged point whose motion the
//! coarse grid does not resolve ([`Grid::resolves`]) is dropped.
//!
//! **Pulls.** Without a joint limit many starts converge past the links' overlap, and the
//! cheapest admissible minimum may lie in a basin that a single loop of the whole family
//! reaches (at drag ratio 1.9 on the paper's target: one loop of 1 128, so a seed found it
//! or not by where it put that loop). It lies next to minima past the overlap, which many
//! starts reach: each distinct one that matters to the stopping rule (no dearer than the
//! cheapest admissible minimum so far) is pulled inside (`pull`), its shape path shrunk into
//! [`super::settings::PULL`]`·π` and carried along both barrier paths there
//! ([`COARSE_PATHS`]: each found minima the other missed), then released to Newton with the trust radius; an admissible
//! minimum it reaches counts as a hit, and so does every later hit of the minimum it was
//! pulled from (those starts reach it too).
//!
//! **Under a joint limit.** The cheapest minimum may be reached by one or two of the 936
//! (loop, barrier path) pairs (the paper's target at `α_max = 2.2`: three seeds of four
//! returned the interior extremal 0.8183904, 2 % dearer than 0.8021628 on two arcs). Each
//! loop runs its own barrier path ([`StartLoop::path`]), so the pairs are the same for every
//! seed, and what a start reaches does not depend on its place. The search is made
//! seed-independent by construction: every seed runs the loops in one order (seed 0's; with
//! the default budget, for a loop problem, the 96 rim loops and the first 64 loops of the
//! family, [`super::settings::LIMITED_STARTS`]; `--starts 1032` runs them all), so what the
//! starts file after each batch, and where the stopping rule ends the search, is the same for
//! every seed. (With an order of its own per seed, either rule let seeds stop at different
//! minima, issue 33: at `α_max = 1.2`, target (0, 0, −0.5), the cheapest gait 2.8620559 came
//! from start 357; seed 7 gave up after 96 starts without a candidate; at `α_max = 1.0`,
//! seed 4 found 2.9734287, the others 3.1658241.) The stopping rule may end it from
//! [`super::settings::LIMITED_MIN_STARTS`] starts (the rims of 1–4 turns); the hopeless rule
//! does not (the family's loops come after the rims). Each start but the rim loops has
//! the second of [`PATIENCE`] (300) Newton iterations per barrier weight (a rim loop the
//! first, 100: with 300 the rims of 4–6 turns took 16 of the 24 CPU-s of `α_max = 1.1`,
//! target (0, 0, 0.3), for the same answers on nine limited problems; with 50, 0.9 and
//! 1.2 / (0, 0, −0.5) came out dearer): the starts under a limit converge
//! slowly (their defect falls from about 0.5 to 0.03 of the target over 200–300 iterations
//! before Newton's fast phase; over the whole family of `α_max = 1.2`, target (0, 0, −0.5),
//! 14 starts converge with 100, 219 with 300, and with 100 or 200 the solve returned
//! 3.0872855 instead of 2.8620559). Each loop runs a second path too, its own path from the
//! central path's far end, `τ = 0.1` ([`super::settings::CENTRAL_PATHS`], IPOPT's first
//! weight): from there other basins are reached (`α_max = 1.2`, target (0, 0, −0.5):
//! 2.7226544 from loop 469, where the own paths' cheapest is 2.8620559 and IPOPT's
//! 2.7437297), and the union keeps every basin the own paths reach (from `τ = 0.1` alone,
//! `α_max = 1.0` returned 2.9911419 instead of 2.9734287), at about twice the starts' cost.
//! After the starts, the distinct minima of the same problem without the limit (its own
//! search, `free`) are carried into it (`inward`): each clipped to
//! [`super::settings::SHRINK`]`·α_max`, along the first coarse path ([`COARSE_PATHS`],
//! from `τ = 1e-3`); what they reach is filed as candidates. (Along both, as the pulls go, the
//! 53 limited problems of docs/MEASUREMENTS.md cost the same, seeds 0–3, and the carried
//! minima a tenth of a limited solve more: `α_max = 1.5` 2.4 → 2.1 CPU-s. Each also scaled
//! about `ᾱ` into the limit, as they were before: the same 53 costs, at twice the carrying's
//! time; scaled only, `--ratio 3 --alpha-max 2 --target 0.1,-0.1,0` 0.4451337 against
//! 0.4368711.)
//!
//! **Repeats.** Most starts under a limit meet another's barrier path: at `α_max = 1.5` the
//! 512 starts reach 86 distinct minima. After each weight a start's point is compared with
//! the points the starts of earlier batches reached at that weight on a path with the same
//! weights from there on (a central path meets the own paths from `τ = 1e-2` or `1e-3`); once
//! one is the same ([`grid::same_path`]), the walk stops there and the start is filed as
//! the earlier start's run ([`Search::repeats`]), saving its path's later weights (a quarter
//! of the search's Newton iterations at 1.5). The earlier batches only, so that what is a
//! repeat does not depend on the threads.
//!
//! **Stopping rule.** After each batch, with `n` starts run and `b` the cheapest admissible
//! extremal so far, the minima that matter are those no dearer than `b` (`b` and cheaper
//! inadmissible ones). By the Good–Turing estimate, the chance that the next start reaches a
//! minimum not seen yet is about the share of starts that reached a minimum no other start
//! reached; restricted to the minima that matter, `f₁/n` with `f₁` the number of them
//! reached by exactly one start ([`Search::unseen`]). The search stops once at least
//! `min_starts` starts have run, `f₁/n ≤` [`UNSEEN`] (below 200 starts: no such minimum;
//! from 200: one; from 400: two) and `b` has been reached from [`CONFIRMATIONS`] starts (its
//! basin is not a lucky hit); without a joint limit `b` must be clear of the overlap by the
//! coarse grid's error in `|α|` ([`COARSE_ALPHA_ERROR`]), since one closer may cross it on
//! the problem's grid (drag ratio 1.5, target (0.3, 0, 0.5): seed 7 stopped on 1.7238 at
//! 3.135, which did, and returned 1.8085956 where seed 0 found 1.6620245). It also stops when
//! the zero loop solves the problem (`J = 0`), without a joint limit when
//! [`HOPELESS_BATCHES`] batches found nothing, and when `max_starts` (the budget) have run
//! ([`Search::satisfied`] is then false). Under a limit the rule is met at most looser limits
//! (on the paper's target at `α_max` = 1.2–3.1 but 2.1, after 64–128 starts) and not at the
//! tight ones (0.9–1.1), which run the budget. Boender and Rinnooy Kan's Bayesian estimate of the
//! number of minima, `w(n−1)/(n−w−2)` for `w` distinct minima, is reported beside it
//! ([`Search::expected_minima`]).
//!
//! **The seed.** The starts the rule runs at least, `min_starts`, are seed 0's for every seed
//! (under a joint limit all of them, above); the seed orders only the starts after them
//! ([`starts::of_grid`]). A basin seed 0 reaches there every seed reaches, and `b` found there
//! is every seed's answer unless a seed's later starts find a cheaper one (links 1, 0.7, 1.3,
//! target (0.25, 0.2, 0): the cheapest gait's basin, reached by 0.4 % of the loops, from seed
//! 0's 124th start; seeds 1, 3, 5 and 7, each in its own order from the first start, met the
//! rule without reaching it). Under a joint limit the search without it whose minima are
//! carried in is seed 0's too ([`super::search_coarse`]), so that a limited solve does not
//! depend on the seed at all: every seed returns seed 0's gait, bit for bit.

mod runs;

use super::direct::Run;
use super::grid::{self, Grid};
use super::progress::Progress;
use super::settings::{
    BATCH, COARSE_ALPHA_ERROR, COARSE_PATHS, CONFIRMATIONS, HOPELESS_BATCHES, PATIENCE, Settings,
    UNSEEN,
};
use super::starts::{self, StartLoop};
use nalgebra::{Vector2, Vector5};
use purcell_core::Error;
use rayon::prelude::*;
use runs::{Outcome, Trail};

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
    /// Index of the first start that reached it (0: the zero loop, or a minimum without the
    /// joint limit carried into it).
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
    /// Under a joint limit, starts whose barrier path met an earlier start's and ended there,
    /// filed as that start's run (see the module docs).
    pub repeats: usize,
    /// Whether the stopping rule was met (otherwise the budget ran out first, or nothing was
    /// found).
    pub satisfied: bool,
    /// Distinct minima the start loops (and the zero loop) reached: under a joint limit,
    /// before the free minima are carried in.
    pub from_starts: usize,
    /// Each minimum past the overlap that was pulled inside, with the controls of the
    /// admissible minimum its pull reached (see the module docs).
    pulls: Vec<(Controls, Controls)>,
    /// Under a joint limit, the barrier path of each start of the batches so far that was not
    /// a repeat, and where it ended (see the module docs).
    trails: Vec<Trail>,
}

/// A coarse minimum's controls.
type Controls = Vec<Vector2<f64>>;

/// The Newton settings of start `start_loop` (`None`: the zero loop) under the joint limit
/// `limit`: [`PATIENCE`]'s first number of iterations (per barrier weight under a limit)
/// without a limit and for a rim loop, its second for the other starts under a limit (see
/// the module docs).
fn start_settings(limit: Option<f64>, start_loop: Option<StartLoop>) -> Settings {
    let rim = start_loop.is_some_and(|s| s.is_rim());
    Settings::search(
        PATIENCE[usize::from(limit.is_some() && !rim)],
        limit.is_some(),
    )
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

/// Runs at least `starts.start()` (at most `starts.end()`) start loops and the zero loop on `grid`;
/// `admissible` decides from the largest `|α_i|` whether an extremal counts for the stopping
/// rule; `progress` ticks once per finished start and pulses before each Newton iteration. With a joint limit `limit`, the starts
/// are shrunk into it and run through the barrier path ([`homotopy`](super::homotopy)): the candidates
/// are then minima of the barrier problem at its last weight; `free`, the distinct minima of
/// the same problem without the limit (a search of its own), are carried into it first
/// along the first coarse path (`inward`; ignored without a limit).
pub fn search(
    grid: &Grid,
    starts: core::ops::RangeInclusive<usize>,
    seed: u64,
    limit: Option<f64>,
    admissible: &(dyn Fn(f64) -> bool + Sync),
    free: &[Candidate],
    progress: &dyn Progress,
) -> Search {
    let (min_starts, max_starts) = (*starts.start(), *starts.end());
    let pulse = &|| progress.pulse();
    let size = starts::reference_size(grid);
    // Seed 0's order for the starts the stopping rule cannot do without, under a joint limit
    // for all (see the module docs).
    let common = if limit.is_some() {
        max_starts
    } else {
        min_starts
    };
    let family = starts::of_grid(grid, size, seed, common, max_starts, limit);
    // The zero loop first: the solution when the target is the start (J = 0); for any other
    // target its Newton step is singular and it stops at once. For a transition, the straight
    // shape path in its place ([`starts::straight`]).
    let all: Vec<(usize, Option<StartLoop>)> = core::iter::once((0, None))
        .chain(family.iter().enumerate().map(|(i, s)| (i + 1, Some(*s))))
        .collect();
    let settings = start_settings(limit, None);
    let mut out = Search {
        best_residual: f64::INFINITY,
        ..Search::default()
    };
    // The zero loop rides with the first batch of start loops.
    let (first, rest) = all.split_at((1 + BATCH).min(all.len()));
    for batch in core::iter::once(first).chain(rest.chunks(BATCH)) {
        let results: Vec<_> = batch
            .par_iter()
            .map(|&(index, start_loop)| {
                let settings = start_settings(limit, start_loop);
                let r = runs::run_loop(grid, limit, &settings, start_loop, &out.trails, pulse);
                progress.tick();
                (index, start_loop, r)
            })
            .collect();
        for (index, start_loop, (own, central)) in results {
            out.starts += usize::from(index > 0);
            for outcome in core::iter::once(own).chain(central) {
                let r = out.outcome(outcome);
                let pull = limit.is_none().then_some(&settings);
                out.absorb(grid, (index, start_loop), r, pull, admissible, pulse);
            }
        }
        if out.after_batch(min_starts, limit.is_some(), admissible) {
            break;
        }
    }
    out.from_starts = out.candidates.len();
    // With a limit, the free minima carried into it along the first coarse path, after the
    // starts (see the module docs).
    if let Some(a) = limit {
        out.carry_in(grid, a, free, &settings, admissible, pulse);
    }
    out
}

impl Search {
    /// The run a start's `outcome` stands for: its own (its barrier path kept among the
    /// trails), or the end of the earlier path it repeats.
    fn outcome(&mut self, outcome: Outcome) -> Result<Run, Error> {
        match outcome {
            Outcome::Ran(ran) => {
                let (r, trail) = *ran;
                self.trails.extend(trail);
                r
            }
            Outcome::Repeat(j) => {
                self.repeats += 1;
                self.trails[j].end.clone()
            }
        }
    }

    /// Files the `free` minima carried into the limit `alpha_max`, each clipped to it and
    /// along the first coarse path (see the module docs).
    fn carry_in(
        &mut self,
        grid: &Grid,
        alpha_max: f64,
        free: &[Candidate],
        settings: &Settings,
        admissible: &(dyn Fn(f64) -> bool + Sync),
        pulse: &(dyn Fn() + Sync),
    ) {
        let taus = COARSE_PATHS[0];
        let results: Vec<_> = free
            .par_iter()
            .map(|c| runs::inward(grid, alpha_max, c, taus, settings, pulse))
            .collect();
        for r in results {
            self.absorb(grid, (0, None), r, None, admissible, pulse);
        }
        self.candidates.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    }

    /// Files the run `r` of start `index` (loop `start_loop`; the caller counts the starts)
    /// ([`Search::file`]); the defect of one that did not converge. With `pull` (the starts' settings; no joint
    /// limit), a new candidate that `admissible` refuses and that matters is pulled inside
    /// ([`runs::pull`]) and an admissible minimum it reaches filed as well (see the module docs).
    fn absorb(
        &mut self,
        grid: &Grid,
        (index, start_loop): (usize, Option<StartLoop>),
        r: Result<Run, Error>,
        pull: Option<&Settings>,
        admissible: &(dyn Fn(f64) -> bool + Sync),
        pulse: &dyn Fn(),
    ) {
        let Ok(run) = r else { return };
        if !run.converged() {
            self.best_residual = self.best_residual.min(run.defect);
            return;
        }
        let from = run.point.clone();
        let Some((cost, max_abs_alpha)) = self.file(grid, index, start_loop, run) else {
            return;
        };
        // Only a minimum that matters (no dearer than the cheapest admissible so far).
        let bound = (self.candidates.iter())
            .filter(|c| admissible(c.max_abs_alpha))
            .fold(f64::INFINITY, |b, c| b.min(c.cost));
        let Some(settings) = pull.filter(|_| !admissible(max_abs_alpha) && cost <= bound) else {
            return;
        };
        for path in COARSE_PATHS {
            let Some(inside) = runs::pull(grid, &from, path, settings, pulse) else {
                continue;
            };
            if admissible(grid::max_abs_alpha(&inside.point.states)) {
                self.pulls.push((from.u.clone(), inside.point.u.clone()));
                self.file(grid, index, start_loop, inside);
            }
        }
    }

    /// Files the converged `run` of start `index` (loop `start_loop`): as another hit of a
    /// candidate with the same path (and of the minimum that candidate was pulled to), or as
    /// a new candidate if the grid resolves its motion; the new candidate's largest `|α_i|`.
    fn file(
        &mut self,
        grid: &Grid,
        index: usize,
        start_loop: Option<StartLoop>,
        run: Run,
    ) -> Option<(f64, f64)> {
        let h = grid.h();
        if let Some(c) = self
            .candidates
            .iter_mut()
            .find(|c| grid::same_path(&c.u, &run.point.u, h))
        {
            c.hits += 1;
            if index < c.start {
                c.start = index;
                c.start_loop = start_loop;
            }
            let from = c.u.clone();
            for (_, to) in self
                .pulls
                .iter()
                .filter(|(f, _)| grid::same_path(f, &from, h))
            {
                if let Some(t) = self
                    .candidates
                    .iter_mut()
                    .find(|t| grid::same_path(&t.u, to, h))
                {
                    t.hits += 1;
                }
            }
            return None;
        }
        // Checked once per distinct extremal (a rollout 16 times finer).
        if !grid.resolves(&run.point.u) {
            self.unresolved += 1;
            return None;
        }
        let cost = grid.cost(&run.point.u, &run.point.states);
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
        Some((cost, max_abs_alpha))
    }

    /// After a batch: the candidates sorted, the stopping rule's estimate and verdict
    /// updated; whether the search stops (the rule is met, or it is hopeless).
    fn after_batch(
        &mut self,
        min_starts: usize,
        limited: bool,
        admissible: &(dyn Fn(f64) -> bool + Sync),
    ) -> bool {
        self.candidates.sort_by(|a, b| a.cost.total_cmp(&b.cost));
        // Without a limit, `b` clear of the overlap (see the module docs).
        let margin = if limited { 0.0 } else { COARSE_ALPHA_ERROR };
        let (unseen, confirmed) = self.rule(&|a| admissible(a + margin));
        self.unseen = unseen;
        self.satisfied = confirmed && unseen <= UNSEEN && self.starts >= min_starts;
        // The zero target is solved by the zero loop; nothing can be cheaper.
        let trivial =
            cheapest_admissible(&self.candidates, admissible).is_some_and(|c| c.cost == 0.0);
        self.satisfied |= trivial;
        // Nothing at all after a few batches: the target is out of reach (or needs more
        // starts than the default; `--starts` bounds the search, not this rule).
        let hopeless = self.candidates.is_empty() && self.starts >= HOPELESS_BATCHES * BATCH;
        // Under a joint limit the search does not give up (see the module docs).
        self.satisfied || (hopeless && !limited)
    }
}

fn cheapest_admissible<'a>(
    candidates: &'a [Candidate],
    admissible: &(dyn Fn(f64) -> bool + Sync),
) -> Option<&'a Candidate> {
    candidates.iter().find(|c| admissible(c.max_abs_alpha))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::{Problem, Spec};
    use crate::solver::{SolveOptions, coarse_grid};

    /// Under a joint limit (the public problem `joint-limit-1.5`) a start whose barrier path
    /// meets one of an earlier batch is filed as that start's run: the search files the
    /// candidates (paths, costs, hits, first starts) that walking every start to its path's
    /// end files.
    #[test]
    fn a_repeat_files_what_its_own_walk_would() {
        let problem = Problem::new(&Spec {
            alpha_max: Some(1.5),
            ..Spec::default()
        })
        .unwrap();
        let grid = coarse_grid(&problem, &SolveOptions::default()).unwrap();
        let admits = |a| problem.admits(a);
        let n = 96;
        let found = search(&grid, n..=n, 0, problem.alpha_max, &admits, &[], &|| {});
        assert!(found.repeats >= n / 4, "{}", found.repeats);
        let size = starts::reference_size(&grid);
        let family = starts::of_grid(&grid, size, 0, n, n, problem.alpha_max);
        let mut walked = Search {
            best_residual: f64::INFINITY,
            ..Search::default()
        };
        let all = core::iter::once(None).chain(family.into_iter().map(Some));
        for (index, start_loop) in all.enumerate() {
            walked.starts += usize::from(index > 0);
            let settings = start_settings(problem.alpha_max, start_loop);
            let (own, central) =
                runs::run_loop(&grid, problem.alpha_max, &settings, start_loop, &[], &|| ());
            for outcome in core::iter::once(own).chain(central) {
                let Outcome::Ran(ran) = outcome else {
                    panic!("start {index}: a repeat of no known path")
                };
                walked.absorb(&grid, (index, start_loop), ran.0, None, &admits, &|| ());
            }
        }
        walked.candidates.sort_by(|a, b| a.cost.total_cmp(&b.cost));
        assert_eq!(found.candidates.len(), walked.candidates.len());
        for (a, b) in found.candidates.iter().zip(&walked.candidates) {
            assert!(
                grid::same_path(&a.u, &b.u, grid.h()),
                "{} vs {}",
                a.cost,
                b.cost
            );
            assert_eq!((a.cost, a.hits, a.start), (b.cost, b.hits, b.start));
        }
    }
}
