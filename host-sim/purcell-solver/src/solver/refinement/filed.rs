//! What a solve's refinement has filed ([`super::refine_candidates`]): the extremals found,
//! each with the starts that reached it, the paths of the intermediate grids that lead to each,
//! and the candidates carried, each with the extremal it led to.

use super::{Controls, Stop, Trail, extremal};
use crate::problem::Problem;
use crate::solver::direct::Run;
use crate::solver::grid::{self, Grid};
use crate::solver::search;
use crate::solver::solution::Extremal;
use crate::solver::symmetry;

/// An extremal's cost on each intermediate grid of its refinement: (steps, cost).
pub(super) type OnGrids = Vec<(usize, f64)>;

/// What a solve's refinement has filed (see the module docs).
#[derive(Default)]
pub(super) struct Filed<'a> {
    /// The extremals found, each with its first candidate's coarse cost.
    pub(super) extremals: Vec<(Extremal, f64)>,
    /// The paths of the intermediate grids of the refinements that reached an extremal (and
    /// their twins' images), which a later refinement that meets one stops at
    /// ([`Stop::Repeat`]).
    pub(super) paths: Vec<Controls>,
    /// The index in `extremals` of the extremal each of `paths` leads to.
    owners: Vec<usize>,
    /// The candidates tried whose refinement did not stall, for their twins
    /// ([`Filed::twin_of`]), each with the index in `extremals` of the extremal it leads to
    /// (`None`: dearer than the bound).
    carried: Vec<(&'a search::Candidate, Option<usize>)>,
}

impl<'a> Filed<'a> {
    /// Files candidate `c`'s refinement, `refined` on `problem` (the settled cost `settled`):
    /// an extremal with its twins ([`Filed::refined`]), a prune, or a repeat, whose starts
    /// are the extremal's it met. Whether a new extremal was found, and, for one admissible
    /// and cheaper than `settled`, its cost on each intermediate grid; a stall as it is.
    pub(super) fn outcome(
        &mut self,
        problem: &Problem,
        c: &'a search::Candidate,
        refined: Result<(Grid, Run, Trail), Stop>,
        settled: f64,
    ) -> Result<(bool, Option<OnGrids>), Stop> {
        let leads = match refined {
            Ok(refined) => {
                let (leads, new, on) = self.refined(problem, c, refined, settled);
                self.carried.push((c, Some(leads)));
                return Ok((new, on));
            }
            Err(Stop::Dearer) => None,
            Err(Stop::Repeat(i)) => self.owners.get(i).copied(),
            Err(stop) => return Err(stop),
        };
        self.reached(leads, c);
        self.carried.push((c, leads));
        Ok((false, None))
    }

    /// Counts candidate `c`'s starts as starts that reached the extremal `leads` (its index in
    /// `extremals`; `None`: none), the first of them as its first start if earlier.
    pub(super) fn reached(&mut self, leads: Option<usize>, c: &search::Candidate) {
        if let Some((x, _)) = leads.and_then(|i| self.extremals.get_mut(i)) {
            x.hits += c.hits;
            x.start = x.start.min(c.start);
        }
    }

    /// Files the extremal that candidate `c` was refined to, `(grid, run)` with the paths and
    /// costs of its refinement's intermediate grids `trail` (its twins too, [`twins`]),
    /// `c`'s starts counted as its: its index in `extremals`, whether it was new, and if it
    /// is admissible and cheaper than `settled`, its cost on each intermediate grid.
    fn refined(
        &mut self,
        problem: &Problem,
        c: &search::Candidate,
        (grid, run, trail): (Grid, Run, Trail),
        settled: f64,
    ) -> (usize, bool, Option<OnGrids>) {
        let x = extremal(problem, &grid, &run);
        let on = (x.admissible && x.cost < settled)
            .then(|| trail.iter().map(|(u, cost)| (u.len(), *cost)).collect());
        let paths: Vec<Controls> = trail.into_iter().map(|(u, _)| u).collect();
        let twins = twins(problem, (&grid, &run), &x, &paths);
        let (i, new) = self.file(x, c, problem.h);
        self.reached(Some(i), c);
        self.lead(paths, i);
        for (twin, paths) in twins {
            let (j, _) = self.file(twin, c, problem.h);
            self.lead(paths, j);
        }
        (i, new, on)
    }

    /// Files `x`, refined from candidate `c` by a later route ([`super::candidates`]'s
    /// retries of stalled candidates), `c`'s starts counted as its.
    pub(super) fn retried(&mut self, x: Extremal, c: &search::Candidate, h: f64) {
        let (i, _) = self.file(x, c, h);
        self.reached(Some(i), c);
    }

    /// The `paths` of a refinement that lead to extremal `owner`.
    fn lead(&mut self, paths: Vec<Controls>, owner: usize) {
        self.owners.extend(core::iter::repeat_n(owner, paths.len()));
        self.paths.extend(paths);
    }

    /// Files `x`, refined from candidate `c` (its first start `c`'s, no start counted yet),
    /// unless `extremals` hold its path (controls at step `h`) already: its index there, and
    /// whether it was new.
    fn file(&mut self, x: Extremal, c: &search::Candidate, h: f64) -> (usize, bool) {
        let same = |(o, _): &(Extremal, f64)| {
            grid::same_path(&o.trajectory.controls, &x.trajectory.controls, h)
        };
        if let Some(i) = self.extremals.iter().position(same) {
            return (i, false);
        }
        let start = c.start;
        let x = Extremal {
            start,
            hits: 0,
            ..x
        };
        self.extremals.push((x, c.cost));
        (self.extremals.len() - 1, true)
    }

    /// Under a joint limit, whether candidate `c` runs the image of the coarse path of one of
    /// the candidates carried under a symmetry of `problem` ([`symmetry::of_problem`]): its
    /// refinement would follow the image of that one's, to the twin of its extremal, filed
    /// with it ([`Filed::refined`]), or stop where that one stopped (the images of every
    /// refinement's intermediate paths are known), so it is not carried. On a symmetric target
    /// the coarse minima come in such pairs (`α_max = 1.1`, target (0, 0, 0.3): 9 of the 27
    /// candidates tried are the second of a pair; not carrying them takes 0.7 CPU-s off the
    /// solve's 5.5). `Some` of the index of the extremal it leads to (the twin; `None` where
    /// that one was dearer).
    pub(super) fn twin_of(
        &self,
        problem: &Problem,
        c: &search::Candidate,
    ) -> Option<Option<usize>> {
        problem.alpha_max?;
        let h = problem.horizon() / c.u.len() as f64;
        symmetry::of_problem(problem).iter().find_map(|sym| {
            let image = sym.controls(&c.u);
            let same = |(d, _): &&(&search::Candidate, _)| grid::same_path(&d.u, &image, h);
            let (_, leads) = self.carried.iter().find(same)?;
            Some(leads.map(|i| {
                let twin = sym.controls(&self.extremals[i].0.trajectory.controls);
                let same = |(o, _): &(Extremal, f64)| {
                    grid::same_path(&o.trajectory.controls, &twin, problem.h)
                };
                self.extremals.iter().position(same).unwrap_or(i)
            }))
        })
    }
}

/// Under a joint limit, the twins of extremal `x`, refined as `(grid, run)`: its images under
/// the symmetries of `problem` ([`symmetry::of_problem`]) that run another path, each with the
/// images of the paths `trail` of its refinement's intermediate grids. A candidate of a twin's
/// basin then stops as a repeat on an intermediate grid instead of being carried to the
/// problem's grid beside it (`α_max = 1.1`, target (0, 0, 0.3): the front–rear twin of
/// 1.5448608 cost a second refinement, 1 of the solve's 6.6 CPU-s). The image is exact and
/// certified as every extremal; without a joint limit the search's twins are refined as they
/// come (the refinement is a small share of those solves).
fn twins(
    problem: &Problem,
    (grid, run): (&Grid, &Run),
    x: &Extremal,
    trail: &[Controls],
) -> Vec<(Extremal, Vec<Controls>)> {
    if problem.alpha_max.is_none() {
        return Vec::new();
    }
    let controls = &x.trajectory.controls;
    (symmetry::of_problem(problem).iter())
        .filter(|sym| !grid::same_path(&sym.controls(controls), controls, problem.h))
        .map(|sym| {
            let (grid, run) = sym.run(grid, run);
            let paths = trail.iter().map(|u| sym.controls(u)).collect();
            (extremal(problem, &grid, &run), paths)
        })
        .collect()
}
