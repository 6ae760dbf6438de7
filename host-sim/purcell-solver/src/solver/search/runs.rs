//! The runs of the search: a start loop along its barrier paths under a joint limit (a repeat
//! once it meets an earlier start's path), the zero loop, the free minima carried into the
//! limit, and the pulls of minima past the links' overlap (see [`super`]'s docs).

use super::{Candidate, Controls};
use crate::problem::OVERLAP;
use crate::solver::constraints::joint_limit::Limits;
use crate::solver::direct::{self, Run};
use crate::solver::grid::{self, Grid, Point};
use crate::solver::homotopy;
use crate::solver::settings::{self, PULL, SHRINK, Settings};
use crate::solver::starts::{self, StartLoop};
use nalgebra::{Vector2, Vector5};
use purcell_core::Error;

/// A start's barrier path under a joint limit: its weights, the point each converged to, in
/// turn, and its run at the last weight tried.
#[derive(Clone, Debug)]
pub(super) struct Trail {
    taus: &'static [f64],
    points: Vec<Controls>,
    pub(super) end: Result<Run, Error>,
}

/// What a start came to: its own run (and under a joint limit its barrier path), or, under a
/// limit, the end of an earlier start's path (its index in
/// [`Search::trails`](super::Search::trails)) that its own path met.
pub(super) enum Outcome {
    Ran(Box<(Result<Run, Error>, Option<Trail>)>),
    Repeat(usize),
}

/// Which barrier path of its loop a start runs under a joint limit (see [`super`]'s docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Paths {
    /// [`settings::COARSE_PATHS`].
    Own,
    /// [`settings::CENTRAL_PATHS`].
    Central,
}

/// The start loop `start_loop` (`None`: the zero loop, [`zero_loop`], or a transition's
/// straight path) through Newton on `grid`; with a joint limit `limit`, shrunk into it and
/// along its barrier path of `paths` ([`StartLoop::path`]), a repeat once a point of it is
/// one of the same weight on a path of `known` (see [`super`]'s docs).
pub(super) fn run_start(
    grid: &Grid,
    limit: Option<f64>,
    settings: &Settings,
    start_loop: Option<StartLoop>,
    known: &[Trail],
    pulse: &dyn Fn(),
    paths: Paths,
) -> Outcome {
    // The zero loop (no start loop, a loop problem) runs without the joint limit's barrier
    // (`zero_loop`); a transition's first start is the straight path to its end shape.
    let u = match start_loop {
        Some(s) => s.controls(grid),
        None if starts::drift(grid).is_none() => {
            return Outcome::Ran(Box::new((zero_loop(grid, settings, pulse), None)));
        }
        None => starts::straight(grid),
    };
    let Some(a) = limit else {
        let r = Point::new(grid, u, Vector5::zeros())
            .and_then(|p| direct::newton_pulsed(grid, p, settings, pulse));
        return Outcome::Ran(Box::new((r, None)));
    };
    // A rim loop is within the limit as it is built ([`starts::rims`]).
    let alpha0 = Vector2::new(grid.start[0], grid.start[1]);
    let u = if start_loop.is_some_and(|s| s.is_rim()) {
        u
    } else {
        homotopy::shrink_into(u, &alpha0, a, grid.h())
    };
    let i = start_loop.map_or(0, |s| s.path());
    let taus = match paths {
        Paths::Own => settings::coarse_path(i),
        Paths::Central => settings::CENTRAL_PATHS[i % 2],
    };
    let (mut points, mut repeat) = (Vec::new(), None);
    let mut watch = |i: usize, p: &Point| {
        // A path of `known` whose weights from `τ_i` on are this path's: its point there.
        let rest = &taus[i..];
        repeat = (known.iter()).position(|t| {
            let j = t.taus.len().checked_sub(rest.len());
            j.filter(|&j| t.taus[j..] == *rest)
                .and_then(|j| t.points.get(j))
                .is_some_and(|q| grid::same_path(q, &p.u, grid.h()))
        });
        points.push(p.u.clone());
        repeat.is_some()
    };
    let end = Point::new(grid, u, Vector5::zeros()).and_then(|p| {
        homotopy::walk_watched(grid, a, taus, p, settings, pulse, &mut watch).map(|w| w.run)
    });
    match repeat {
        Some(j) => Outcome::Repeat(j),
        None => Outcome::Ran(Box::new((end.clone(), Some(Trail { taus, points, end })))),
    }
}

/// Start loop `start_loop` along its own path ([`run_start`]), and under a joint limit along
/// its central path too (see [`super`]'s docs).
pub(super) fn run_loop(
    grid: &Grid,
    limit: Option<f64>,
    settings: &Settings,
    start_loop: Option<StartLoop>,
    known: &[Trail],
    pulse: &dyn Fn(),
) -> (Outcome, Option<Outcome>) {
    let run = |paths| run_start(grid, limit, settings, start_loop, known, pulse, paths);
    let central = (limit.is_some() && start_loop.is_some()).then(|| run(Paths::Central));
    (run(Paths::Own), central)
}

/// The zero loop through Newton on `grid` without the joint limit's barrier: its states stay
/// at `ᾱ`, inside any limit, and when the target is the start it is the exact global minimum
/// (`J = 0`), which the barrier's gradient at a bent `ᾱ` would push it off; for any other
/// target its Newton step is singular and it stops at once.
fn zero_loop(grid: &Grid, settings: &Settings, pulse: &dyn Fn()) -> Result<Run, Error> {
    let free = Grid {
        limits: Limits::None,
        ..grid.clone()
    };
    let p = Point::new(&free, vec![Vector2::zeros(); free.steps], Vector5::zeros())?;
    direct::newton_pulsed(&free, p, settings, pulse)
}

/// A minimum `c` of the problem without the joint limit carried into the limit `alpha_max`
/// (see [`super`]'s docs): its shape path clipped to [`SHRINK`]` · α_max`
/// ([`homotopy::clip_into`]), then the barrier path `taus` by `settings`.
pub(super) fn inward(
    grid: &Grid,
    alpha_max: f64,
    c: &Candidate,
    taus: &[f64],
    settings: &Settings,
    pulse: &dyn Fn(),
) -> Result<Run, Error> {
    let alpha0 = Vector2::new(grid.start[0], grid.start[1]);
    let u = homotopy::clip_into(&c.u, &alpha0, SHRINK * alpha_max, grid.h());
    let p = Point::new(grid, u, c.nu)?;
    homotopy::walk(grid, alpha_max, taus, p, settings, pulse).map(|w| w.run)
}

/// A coarse minimum `from` past the links' overlap pulled inside (see [`super`]'s docs): its
/// shape path shrunk into `PULL·π`, the barrier path `taus` there, then
/// Newton without the barrier by `settings` (the starts', with the trust radius); the
/// converged run, if any.
pub(super) fn pull(
    grid: &Grid,
    from: &Point,
    taus: &[f64],
    settings: &Settings,
    pulse: &dyn Fn(),
) -> Option<Run> {
    let wall = PULL * OVERLAP;
    let alpha0 = Vector2::new(grid.start[0], grid.start[1]);
    let u = homotopy::shrink_into(from.u.clone(), &alpha0, wall, grid.h());
    let barrier = Settings::search(settings.max_iterations, true);
    let start = Point::new(grid, u, from.nu).ok()?;
    let held = homotopy::walk(grid, wall, taus, start, &barrier, pulse)
        .ok()?
        .run;
    if !held.converged() {
        return None;
    }
    let free = direct::newton_pulsed(grid, held.point, settings, pulse).ok()?;
    free.converged().then_some(free)
}
