//! Sweeps of targets: every target of a lattice solved at least as well as `solve`, with
//! neighbours passing their coarse extremals on.

use crate::problem::{Problem, Spec};
use crate::solver::coarse_grid;
use crate::solver::direct;
use crate::solver::grid::{self, Grid, Point};
use crate::solver::progress::{Progress, Within};
use crate::solver::refinement::refine_candidates;
use crate::solver::search::Candidate;
use crate::solver::settings::{SAME_TARGET, Settings, SolveOptions};
use crate::solver::solution::{Extremal, SolveError};
use crate::solver::symmetry::{self, Symmetry};
use nalgebra::Vector3;
use rayon::prelude::*;

/// A lattice of targets: every combination of the values on the three axes `x`, `y`, `θ`.
#[derive(Clone, Debug, PartialEq)]
pub struct Lattice {
    /// Values of `x`, `y`, `θ`.
    pub axes: [Vec<f64>; 3],
}

impl Lattice {
    /// `count` evenly spaced values from `from` to `to` (`from` alone for one), symmetric in
    /// the two, so that a symmetric range gives exact negatives.
    pub fn spaced(from: f64, to: f64, count: usize) -> Vec<f64> {
        (0..count)
            .map(|i| {
                if count == 1 {
                    from
                } else {
                    (from * (count - 1 - i) as f64 + to * i as f64) / (count - 1) as f64
                }
            })
            .collect()
    }

    /// Number of targets.
    pub fn len(&self) -> usize {
        self.axes.iter().map(Vec::len).product()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn index(&self, i: [usize; 3]) -> usize {
        (i[0] * self.axes[1].len() + i[1]) * self.axes[2].len() + i[2]
    }

    fn coordinates(&self, mut n: usize) -> [usize; 3] {
        let l = self.axes[2].len();
        let c2 = n % l;
        n /= l;
        let m = self.axes[1].len();
        [n / m, n % m, c2]
    }

    /// The targets, `x` slowest, `θ` fastest.
    pub fn targets(&self) -> Vec<Vector3<f64>> {
        (0..self.len())
            .map(|n| {
                let c = self.coordinates(n);
                Vector3::new(self.axes[0][c[0]], self.axes[1][c[1]], self.axes[2][c[2]])
            })
            .collect()
    }

    /// The targets one lattice step away from target `n` along each axis.
    pub fn neighbours(&self, n: usize) -> Vec<usize> {
        let c = self.coordinates(n);
        let mut out = Vec::new();
        for axis in 0..3 {
            for delta in [-1i64, 1] {
                let v = c[axis] as i64 + delta;
                if v >= 0 && (v as usize) < self.axes[axis].len() {
                    let mut d = c;
                    d[axis] = v as usize;
                    out.push(self.index(d));
                }
            }
        }
        out
    }
}

/// The outcome of a sweep at one target.
#[derive(Clone, Debug)]
pub struct SweepPoint {
    /// The target.
    pub target: Vector3<f64>,
    /// The cheapest admissible extremal found, or why there is none.
    pub result: Result<Extremal, SolveError>,
}

/// Coarse extremals each target passes on to its neighbours in a sweep ([`sweep`]): its
/// cheapest admissible ones, distinct.
pub const KEEP: usize = 3;

/// Solves every target of `lattice` (the other inputs from `spec`), each at least as well as
/// [`crate::solver::solve`] would:
/// 1. every target's own global search ([`search_target`], with `options`), run once per
///    orbit of the swimmer's symmetries ([`symmetry`]) and mapped onto the other targets of
///    the orbit;
/// 2. passes in which every target runs Newton on the coarse grid from its neighbours'
///    [`KEEP`] cheapest admissible extremals (and takes over the images of those of the
///    targets a symmetry maps onto it), until no target's kept extremals change: a cheap
///    basin one target found reaches the whole region where it is a minimum;
/// 3. each target's candidates (its search's and those the passes brought) carried to the
///    fine grid as `solve` carries them ([`refine_target`]).
///
/// Targets are solved in parallel within each phase. `progress` has the phases `search` (a
/// tick per target, searched or mapped), `neighbours` (one tick) and `refinement` (a tick per
/// target). [`Atlas`] runs the phases one by one (phases 1 and 3 elsewhere, e.g. on a
/// cluster), with the same results.
pub fn sweep(
    spec: &Spec,
    lattice: &Lattice,
    options: &SolveOptions,
    progress: &dyn Progress,
) -> Result<Vec<SweepPoint>, crate::problem::InputError> {
    let atlas = Atlas::new(spec, lattice.clone(), options)?;
    let n = atlas.targets.len();
    progress.phase("search", n, "targets");
    let searched = atlas
        .searched()
        .into_par_iter()
        .map(|i| {
            let within = Within(progress);
            let (list, residual) = search_target(&atlas.problems[i], options, &within);
            progress.tick();
            (i, list, residual)
        })
        .collect();
    let (own, residual) = atlas.spread(searched, &|| progress.tick());
    progress.phase("neighbours", 1, "passes");
    let brought = atlas.neighbour_passes(&own, &|| progress.pulse());
    progress.tick();
    progress.phase("refinement", n, "targets");
    Ok((0..n)
        .into_par_iter()
        .map(|i| {
            let (p, target) = (&atlas.problems[i], atlas.targets[i]);
            let within = Within(progress);
            let result = refine_target(p, &own[i], &brought[i], residual[i], options, &within);
            progress.tick();
            SweepPoint { target, result }
        })
        .collect())
}

/// 1. A target's candidates from its global search and the search's smallest defect (none
///    and infinity if it failed); `progress` ticks per start and pulses every Newton
///    iteration.
pub fn search_target(
    problem: &Problem,
    options: &SolveOptions,
    progress: &dyn Progress,
) -> (Vec<Candidate>, f64) {
    match crate::solver::search_coarse(problem, options, progress) {
        Ok(s) => (s.candidates, s.best_residual),
        Err(_) => (Vec::new(), f64::INFINITY),
    }
}

/// 3. A target's `own` candidates and those the passes `brought` carried to the fine grid as
///    `solve` carries them (`residual`: its search's smallest defect); its cheapest
///    admissible extremal, or why there is none.
pub fn refine_target(
    problem: &Problem,
    own: &[Candidate],
    brought: &[Candidate],
    residual: f64,
    options: &SolveOptions,
    progress: &dyn Progress,
) -> Result<Extremal, SolveError> {
    let mut candidates = [own, brought].concat();
    candidates.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    refine_candidates(problem, &candidates, options, residual, progress)
        .map(|(best, mut extremals, _)| extremals.swap_remove(best))
}

/// A sweep's targets with their problems, coarse grids and symmetric images: [`sweep`]'s
/// phases one by one.
pub struct Atlas {
    lattice: Lattice,
    /// The targets, as [`Lattice::targets`].
    pub targets: Vec<Vector3<f64>>,
    /// Their problems.
    pub problems: Vec<Problem>,
    grids: Vec<Option<Grid>>,
    /// For each target, the targets a symmetry maps onto it, with that symmetry.
    images: Vec<Vec<(usize, Symmetry)>>,
}

impl Atlas {
    /// The targets of `lattice` with the other inputs from `spec`.
    pub fn new(
        spec: &Spec,
        lattice: Lattice,
        options: &SolveOptions,
    ) -> Result<Self, crate::problem::InputError> {
        let targets = lattice.targets();
        let problems: Vec<Problem> = targets
            .iter()
            .map(|t| {
                Problem::new(&Spec {
                    target: [t.x, t.y, t.z],
                    ..spec.clone()
                })
            })
            .collect::<Result<_, _>>()?;
        let grids = problems.iter().map(|p| coarse_grid(p, options)).collect();
        let lookup = |t: &Vector3<f64>| {
            targets
                .iter()
                .position(|u| (u - t).amax() <= SAME_TARGET * (1.0 + t.amax()))
        };
        let images = problems
            .iter()
            .enumerate()
            .map(|(i, p)| {
                symmetry::of_swimmer(p)
                    .into_iter()
                    .filter_map(|sym| Some((lookup(&sym.target(&targets[i]))?, sym)))
                    .filter(|(j, _)| *j != i)
                    .collect()
            })
            .collect();
        Ok(Atlas {
            lattice,
            targets,
            problems,
            grids,
            images,
        })
    }

    /// The targets whose global search phase 1 runs: one per orbit of the symmetries.
    pub fn searched(&self) -> Vec<usize> {
        (0..self.targets.len())
            .filter(|&i| self.images[i].iter().all(|(j, _)| *j > i))
            .collect()
    }

    /// 1. Every target's candidates and smallest defect from the `searched` ones' (target,
    ///    [`search_target`]'s outcome): a target whose images include an earlier target takes
    ///    that target's candidates, mapped (`progress` called for each).
    pub fn spread(
        &self,
        searched: Vec<(usize, Vec<Candidate>, f64)>,
        progress: &(dyn Fn() + Sync),
    ) -> (Vec<Vec<Candidate>>, Vec<f64>) {
        let n = self.targets.len();
        let mut own: Vec<Vec<Candidate>> = vec![Vec::new(); n];
        let mut residual = vec![f64::INFINITY; n];
        for (i, list, r) in searched {
            own[i] = list;
            residual[i] = r;
        }
        for i in 0..n {
            if let Some((j, sym)) = self.images[i]
                .iter()
                .filter(|(j, _)| *j < i)
                .min_by_key(|(j, _)| *j)
            {
                own[i] = own[*j].iter().map(|c| image(c, sym)).collect();
                residual[i] = residual[*j];
                progress();
            }
        }
        (own, residual)
    }

    /// 2. Neighbour passes on the coarse grid from each target's `own` candidates, until no
    ///    target's kept extremals change; the candidates they brought to each target (not
    ///    among its own). `pulse` is called before each target's pass.
    pub fn neighbour_passes(
        &self,
        own: &[Vec<Candidate>],
        pulse: &(dyn Fn() + Sync),
    ) -> Vec<Vec<Candidate>> {
        let n = self.targets.len();
        let mut kept: Vec<Vec<Candidate>> = vec![Vec::new(); n];
        let mut changed = vec![false; n];
        for i in 0..n {
            changed[i] = merge(
                &mut kept[i],
                own[i].clone(),
                &self.problems[i],
                self.grids[i].as_ref(),
            );
        }
        let mut brought: Vec<Vec<Candidate>> = vec![Vec::new(); n];
        loop {
            let updates: Vec<(usize, Vec<Candidate>)> = (0..n)
                .into_par_iter()
                .filter_map(|i| {
                    pulse();
                    Some((i, self.pass(i, &kept, &changed)?))
                })
                .collect();
            if updates.is_empty() {
                break;
            }
            changed = vec![false; n];
            for (i, list) in updates {
                for c in &list {
                    let h = self.grids[i].as_ref().map_or(0.0, Grid::h);
                    if !own[i]
                        .iter()
                        .chain(&brought[i])
                        .any(|m| grid::same_path(&m.u, &c.u, h))
                    {
                        brought[i].push(c.clone());
                    }
                }
                kept[i] = list;
                changed[i] = true;
            }
        }
        brought
    }

    /// One pass at target `i`: Newton from the `kept` extremals of its neighbours that
    /// `changed` in the last pass, and the images of those of the targets a symmetry maps
    /// onto it; its new kept list if that changed.
    fn pass(&self, i: usize, kept: &[Vec<Candidate>], changed: &[bool]) -> Option<Vec<Candidate>> {
        let grid = self.grids[i].as_ref()?;
        let mut new = Vec::new();
        for j in self.lattice.neighbours(i) {
            if !changed[j] {
                continue;
            }
            for c in &kept[j] {
                if !kept[i]
                    .iter()
                    .any(|m| grid::same_path(&m.u, &c.u, grid.h()))
                {
                    new.extend(newton_from(grid, c, &Settings::NEIGHBOURS));
                }
            }
        }
        for (j, sym) in &self.images[i] {
            if changed[*j] {
                new.extend(kept[*j].iter().map(|c| image(c, sym)));
            }
        }
        let mut list = kept[i].clone();
        merge(&mut list, new, &self.problems[i], Some(grid)).then_some(list)
    }
}

/// The image of a coarse extremal under a symmetry of the swimmer.
fn image(c: &Candidate, sym: &Symmetry) -> Candidate {
    Candidate {
        u: sym.controls(&c.u),
        nu: sym.coordinates(&c.nu),
        ..c.clone()
    }
}

/// Merges `new` coarse extremals into a target's kept list (admissible, distinct, the
/// [`KEEP`] cheapest); whether the list changed.
fn merge(
    kept: &mut Vec<Candidate>,
    new: Vec<Candidate>,
    problem: &Problem,
    grid: Option<&Grid>,
) -> bool {
    let Some(grid) = grid else { return false };
    let before: Vec<f64> = kept.iter().map(|c| c.cost).collect();
    for c in new {
        if problem.admits(c.max_abs_alpha)
            && !kept.iter().any(|m| grid::same_path(&m.u, &c.u, grid.h()))
        {
            kept.push(c);
        }
    }
    kept.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    kept.truncate(KEEP);
    kept.iter().map(|c| c.cost).collect::<Vec<_>>() != before
}

/// Newton at one target from another target's coarse extremal; the extremal it converges to,
/// if its motion is resolved by the grid.
fn newton_from(grid: &Grid, from: &Candidate, settings: &Settings) -> Option<Candidate> {
    let p = Point::new(grid, from.u.clone(), from.nu).ok()?;
    let run = direct::newton(grid, p, settings).ok()?;
    if !run.converged() || !grid.resolves(&run.point.u) {
        return None;
    }
    let max_abs_alpha = grid::max_abs_alpha(&run.point.states);
    Some(Candidate {
        cost: grid.cost(&run.point.u, &run.point.states),
        u: run.point.u,
        nu: run.point.nu,
        max_abs_alpha,
        start: 0,
        hits: 1,
        start_loop: None,
    })
}
