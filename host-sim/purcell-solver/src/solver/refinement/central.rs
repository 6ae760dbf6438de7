//! Controls walked back up the central path under a joint limit and down again, and refined
//! from where the walk ends ([`walked`]): the recentring of a limited solve's gaits
//! ([`crate::solver::recentre`], whose docs have the measurements) and the last retry of a
//! coarse minimum whose refinement stalled ([`super::refine_candidates`]).

use super::{extremal, refine};
use crate::problem::Problem;
use crate::solver::grid::{self, Grid, Point};
use crate::solver::homotopy;
use crate::solver::settings::{
    CENTRAL_PATHS, FINE_PRUNE, FINE_TAUS, PATIENCE, RECENTRE_STEPS, Settings,
};
use crate::solver::solution::Extremal;
use nalgebra::{Vector2, Vector5};

/// The admissible extremal cheaper than `bound` that the controls `u` (of an extremal, or of a
/// coarse minimum whose refinement stalled, on any grid) reach walked back up the central
/// path under the limit `alpha_max` and down again, and refined where the walk ends farther
/// than `apart` from their own path and costs less than `bound` (see
/// [`crate::solver::recentre`]'s docs).
pub fn walked(
    problem: &Problem,
    u: &[Vector2<f64>],
    (apart, bound): (f64, f64),
    alpha_max: f64,
    pulse: &dyn Fn(),
) -> Option<Extremal> {
    let grid = Grid::mimic(problem, RECENTRE_STEPS.min(problem.steps as usize)).ok()?;
    let sampled = grid::prolong(u, grid.steps);
    // Strictly inside the limit, as the barrier path needs it.
    let inside = (1.0 - FINE_TAUS[0]) * alpha_max;
    let inside = homotopy::clip_into(&sampled, &problem.alpha0, inside, grid.h());
    let start = Point::new(&grid, inside, Vector5::zeros()).ok()?;
    let settings = Settings::barrier(PATIENCE[1]);
    let walk = homotopy::walk(&grid, alpha_max, CENTRAL_PATHS[1], start, &settings, pulse).ok()?;
    let end = &walk.run.point;
    let elsewhere = grid::path_distance(&end.u, &sampled, grid.h()) > apart;
    if !walk.run.converged() || !elsewhere || grid.cost(&end.u, &end.states) >= bound {
        return None;
    }
    // The bound holds from the first finer grid, GRADUAL_STEPS steps: like with like there.
    let (fine, run) = refine(problem, &end.u, &end.nu, bound * (1.0 + FINE_PRUNE), pulse).ok()?;
    let y = extremal(problem, &fine, &run);
    // Cheaper than the settled answer, the cheapest admissible extremal: none of those found
    // (reached from no start: `extremal` leaves its start and hits 0).
    (y.admissible && y.cost < bound).then_some(y)
}
