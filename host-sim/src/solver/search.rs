//! The global search: many start loops through the direct method on a coarse grid.
//!
//! Each start ([`super::starts`]) runs [`direct::newton`] on a grid of `M ≪ N` steps whose rule
//! mimics the fine problem's discretisation ([`super::stage::Rule::matching`]), so its local minima and their
//! costs match the fine problem's to about 1e-3 and cost a hundredth of a fine solve. Starts run
//! in batches (in parallel); converged points are grouped into distinct extremals (same shape
//! path to 1e-6 rad); the search stops when the cheapest admissible extremal has been reached
//! from [`CONFIRMATIONS`] starts (its basin is not a lucky hit) and at least a given number of
//! starts have run, when three batches found
//! nothing, or when the starts are used up. A converged point whose motion the coarse grid
//! does not resolve ([`Grid::resolves`]) is dropped.

use super::direct::{self, Grid, Point, Settings};
use super::limits;
use super::starts::{self, StartLoop};
use nalgebra::{Vector2, Vector5};
use rayon::prelude::*;

/// Starts per batch.
pub const BATCH: usize = 32;
/// How many starts must reach the cheapest admissible extremal before the search stops.
pub const CONFIRMATIONS: usize = 3;

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
    /// Starts run (including the zero loop).
    pub starts: usize,
    /// Smallest terminal defect among the starts that did not converge.
    pub best_residual: f64,
    /// Converged starts dropped because their motion was not resolved by the coarse grid
    /// ([`Grid::resolves`]).
    pub unresolved: usize,
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
    let family = starts::family(size, seed, max_starts);
    // The zero loop first: the solution when the target is the start (J = 0); for any other
    // target its Newton step is singular and it stops at once.
    let all: Vec<(usize, Option<StartLoop>)> = core::iter::once((0, None))
        .chain(family.iter().enumerate().map(|(i, s)| (i + 1, Some(*s))))
        .collect();
    // Newton iterations per start (per barrier weight with a limit): the first of
    // [`limits::PATIENCE`]; the second for a search with a limit whose first pass found
    // nothing though a start came within 1e-3 of the target.
    let run = |patience: usize, best_residual: f64| {
        let settings = Settings {
            max_iterations: patience,
            tol_defect: 1e-10,
            tol_kkt: 1e-8,
            fraction_to_boundary: false,
        };
        let mut out = Search {
            best_residual,
            ..Search::default()
        };
        for batch in all.chunks(BATCH) {
            let results: Vec<_> = batch
                .par_iter()
                .map(|&(index, start_loop)| {
                    let u = start_loop
                        .map_or_else(|| vec![Vector2::zeros(); grid.steps], |s| s.controls(grid));
                    let alpha0 = Vector2::new(grid.start[0], grid.start[1]);
                    let r = match limit {
                        None => Point::new(grid, u, Vector5::zeros())
                            .and_then(|p| direct::newton(grid, p, &settings)),
                        Some(a) => {
                            let u = limits::shrink_into(u, &alpha0, a, grid.h());
                            Point::new(grid, u, Vector5::zeros()).and_then(|p| {
                                limits::barrier_path(
                                    grid,
                                    a,
                                    limits::coarse_path(index),
                                    p,
                                    &settings,
                                )
                            })
                        }
                    };
                    progress();
                    (index, start_loop, r)
                })
                .collect();
            let before = cheapest_admissible(&out.candidates, admissible).map(|c| c.cost);
            for (index, start_loop, r) in results {
                out.starts += 1;
                let Ok(run) = r else { continue };
                if !run.converged {
                    out.best_residual = out.best_residual.min(run.defect);
                    continue;
                }
                if let Some(c) = out
                    .candidates
                    .iter_mut()
                    .find(|c| same_path(&c.u, &run.point.u, grid.h()))
                {
                    c.hits += 1;
                    if index < c.start {
                        c.start = index;
                        c.start_loop = start_loop;
                    }
                    continue;
                }
                // Checked once per distinct extremal (a rollout 16 times finer).
                if !grid.resolves(&run.point.u) {
                    out.unresolved += 1;
                    continue;
                }
                let cost = grid.cost(&run.point.u);
                let max_abs_alpha = direct::max_abs_alpha(&run.point.states);
                out.candidates.push(Candidate {
                    u: run.point.u,
                    nu: run.point.nu,
                    cost,
                    max_abs_alpha,
                    start: index,
                    hits: 1,
                    start_loop,
                });
            }
            out.candidates.sort_by(|a, b| a.cost.total_cmp(&b.cost));
            let after = cheapest_admissible(&out.candidates, admissible);
            let confirmed = after
                .is_some_and(|c| c.hits >= CONFIRMATIONS && before.is_some_and(|b| b <= c.cost));
            // The zero target is solved by the zero loop; nothing can be cheaper.
            let trivial = after.is_some_and(|c| c.cost == 0.0);
            // Nothing at all after three batches: the target is out of reach (or needs more
            // starts than the default; `--starts` bounds the search, not this rule).
            let hopeless = out.candidates.is_empty() && out.starts >= 3 * BATCH;
            if (confirmed && out.starts >= min_starts) || trivial || hopeless {
                break;
            }
        }
        out
    };
    let out = run(limits::PATIENCE[0], f64::INFINITY);
    // Nothing found, but a start ended near the target: the starts ran out of iterations, not
    // of room (with a tight limit the barrier paths spend long pinned to it).
    let near = out.best_residual <= 1e-3 * (grid.target - grid.start).amax();
    if out.candidates.is_empty() && limit.is_some() && near {
        run(limits::PATIENCE[1], out.best_residual)
    } else {
        out
    }
}

fn cheapest_admissible<'a>(
    candidates: &'a [Candidate],
    admissible: &(dyn Fn(f64) -> bool + Sync),
) -> Option<&'a Candidate> {
    candidates.iter().find(|c| admissible(c.max_abs_alpha))
}

/// Whether two control sequences run the same shape path (to 1e-6 rad at every node).
pub fn same_path(a: &[Vector2<f64>], b: &[Vector2<f64>], h: f64) -> bool {
    let mut d = Vector2::zeros();
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            d += (x - y) * h;
            d.amax() <= 1e-6
        })
}
