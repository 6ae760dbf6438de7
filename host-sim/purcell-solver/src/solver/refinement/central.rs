//! Controls walked back up the central path under a joint limit and down again, and refined
//! from where the walk ends: the recentring of a limited solve's gaits ([`walked`],
//! [`crate::solver::recentre`], whose docs have the measurements) and the last try of a
//! coarse minimum whose refinement stalled or that the coarse grid does not resolve
//! ([`carry_walked`], [`super::refine_candidates`]).

use super::{Controls, Stop, Trail, either, extremal, refine};
use crate::problem::Problem;
use crate::solver::direct::Run;
use crate::solver::grid::{self, Grid, Point};
use crate::solver::homotopy;
use crate::solver::settings::{
    CENTRAL_PATHS, FINE_PRUNE, FINE_TAUS, PATIENCE, RECENTRE_STEPS, Settings,
};
use crate::solver::solution::Extremal;
use nalgebra::{Vector2, Vector5};

/// The controls `u` (on any grid) sampled on [`RECENTRE_STEPS`] steps, clipped just inside
/// the limit `alpha_max` and walked along the barrier path from `τ = 0.1`
/// ([`CENTRAL_PATHS`]`[1]`): the grid, the sampled controls and the converged end; why not
/// (the walk's defect where it stopped; ∞ if it could not start).
fn walk_down(
    problem: &Problem,
    u: &[Vector2<f64>],
    alpha_max: f64,
    pulse: &dyn Fn(),
) -> Result<(Grid, Controls, Point), Stop> {
    let failed = |_| Stop::Defect(f64::INFINITY);
    let grid = Grid::mimic(problem, RECENTRE_STEPS.min(problem.steps as usize)).map_err(failed)?;
    let sampled = grid::prolong(u, grid.steps);
    // Strictly inside the limit, as the barrier path needs it.
    let inside = (1.0 - FINE_TAUS[0]) * alpha_max;
    let inside = homotopy::clip_into(&sampled, &problem.alpha0, inside, grid.h());
    let start = Point::new(&grid, inside, Vector5::zeros()).map_err(failed)?;
    let settings = Settings::barrier(PATIENCE[1]);
    let walk = homotopy::walk(&grid, alpha_max, CENTRAL_PATHS[1], start, &settings, pulse)
        .map_err(failed)?;
    if !walk.run.converged() {
        return Err(Stop::Defect(walk.run.defect));
    }
    Ok((grid, sampled, walk.run.point))
}

/// The admissible extremal cheaper than `bound` that the controls `u` (of an extremal, on any
/// grid) reach walked back up the central path under the limit `alpha_max` and down again
/// (sampled on [`RECENTRE_STEPS`] steps, from `τ = 0.1`), and refined where the walk ends
/// farther than `apart` from their own path and costs less than `bound` (see
/// [`crate::solver::recentre`]'s docs).
pub fn walked(
    problem: &Problem,
    u: &[Vector2<f64>],
    (apart, bound): (f64, f64),
    alpha_max: f64,
    pulse: &dyn Fn(),
) -> Option<Extremal> {
    let (grid, sampled, end) = walk_down(problem, u, alpha_max, pulse).ok()?;
    let elsewhere = grid::path_distance(&end.u, &sampled, grid.h()) > apart;
    if !elsewhere || grid.cost(&end.u, &end.states) >= bound {
        return None;
    }
    // The bound holds from the first finer grid, GRADUAL_STEPS steps: like with like there.
    let (fine, run) = refine(problem, &end.u, &end.nu, bound * (1.0 + FINE_PRUNE), pulse).ok()?;
    let y = extremal(problem, &fine, &run);
    // Cheaper than the settled answer, the cheapest admissible extremal: none of those found
    // (reached from no start: `extremal` leaves its start and hits 0).
    (y.admissible && y.cost < bound).then_some(y)
}

/// A coarse minimum's controls `u` walked back up the central path under the limit
/// `alpha_max` and down again ([`walk_down`]) and carried from the walk's end to the
/// problem's grid as a candidate is ([`carry`], primal steps, primal–dual ones if that
/// stalls), its trail beginning with the walk's end: [`Stop::Dearer`] where the end costs
/// more than `bound` on its grid (`bound(steps)`, as on every grid after it), and
/// [`Stop::Repeat`] where it is one of the `known` paths, as on every grid after it.
pub(super) fn carry_walked(
    problem: &Problem,
    u: &[Vector2<f64>],
    alpha_max: f64,
    (bound, known): (&dyn Fn(usize) -> f64, &[Controls]),
    pulse: &dyn Fn(),
) -> Result<(Grid, Run, Trail), Stop> {
    let (grid, _, end) = walk_down(problem, u, alpha_max, pulse)?;
    let cost = grid.cost(&end.u, &end.states);
    if cost > bound(grid.steps) {
        return Err(Stop::Dearer);
    }
    if let Some(i) = (known.iter()).position(|k| grid::same_path(k, &end.u, grid.h())) {
        return Err(Stop::Repeat(i));
    }
    let carried = either(
        problem,
        (&end.u, &end.nu),
        (bound, known),
        PATIENCE[1],
        pulse,
    );
    carried.map(|(fine, run, mut trail)| {
        trail.insert(0, (end.u, cost));
        (fine, run, trail)
    })
}
