//! The direct method: Newton–SQP on the controls of the exact discrete problem, with the exact
//! Hessian of the Lagrangian and a Riccati-structured step.
//!
//! Unknowns: the controls `u_0 … u_{N−1}` on a [`Grid`]; the states follow by the exact
//! kinematics ([`super::stage::step`]), so every iterate is a trajectory of the swimmer and
//! only the terminal constraint `c(u) = s_N − s̄ = 0` (five equations: `α_N = ᾱ`,
//! `(x, y, θ)_N = ḡ`, [`super::constraints::terminal`]) can be violated. With `L = J + νᵀc`,
//! the costates `λ_N = ν`, `λ_k = A_kᵀλ_{k+1}` give `∇_{u_k}L = h·u_k + B_kᵀλ_{k+1}`
//! ([`Linearisation`]), and the Newton step is the LQ problem of [`super::riccati`] with the
//! stage Hessians of `λ_{k+1}ᵀf`. Per iteration: one rollout, one backward sweep
//! (derivatives, costates, Riccati), one forward sweep — `O(N)`.
//!
//! Globalisation: a filter line search ([`super::filter`]); when the QP is not convex on the
//! constraint's null space (wrong inertia), `δ·I` is added to the control Hessian until it is
//! (as IPOPT corrects inertia). Near a local minimum no correction is needed and the
//! iteration is Newton's method on the KKT system: quadratic convergence.
//!
//! An optional trust radius bounds how far one iteration moves the shape path
//! ([`Settings::trust_radius`]): the line search then starts at the step that moves no
//! `α_k` by more than the radius. Far from a solution a full Newton step can jump across the
//! shape plane, so the minimum a start reaches has little to do with the start; with the
//! radius the iterates deform the start loop, and a start placed in a region of the shape
//! plane reaches a minimum there (the global search relies on this, [`super::search`]).
//! Near a minimum the steps are short and the iteration is Newton's.
//!
//! The angles wrap at `±π` ([`super::stage::wrap`]): an iterate may swing a joint past the
//! links' overlap; whether an extremal is admissible is decided afterwards.
//!
//! **Tracing.** Each iteration is logged through the [`log`] crate at `debug` level (cost,
//! defect, stationarity, `δ`, inertia, step length), the linearised step's residual at
//! `trace`. The library installs no logger and `purcell-sim` none either: a program that
//! wants the lines installs one, e.g. `env_logger::init()` run with
//! `RUST_LOG=purcell_solver::solver::direct=debug`.

use super::constraints::joint_limit::ControlMap;
use super::filter::{Filter, Search, Step};
use super::grid::{Grid, Point};
use super::linearisation::Linearisation;
use super::riccati::Factor;
use super::settings::{
    DELTA_DECAY, DELTA_GROWTH, DELTA_MAX, DELTA_MIN, FRACTION_TO_BOUNDARY, ROUNDING_KKT,
    ROUNDING_STEP, Settings,
};
use super::stage::StageState;
use nalgebra::{Vector2, Vector5};
use purcell_core::Error;

/// Outcome of [`newton`].
#[derive(Clone, Debug)]
pub struct Run {
    /// The last iterate.
    pub point: Point,
    /// Its costates `λ_0 … λ_N` (with the jumps of the limit's multipliers).
    pub lambda: Vec<StageState>,
    /// The jumps of `λ^α_k` at states on arcs ([`Linearisation::jumps`]).
    pub jumps: Vec<Vector2<f64>>,
    /// `|c|_∞` there.
    pub defect: f64,
    /// Stationarity residual there.
    pub kkt: f64,
    /// Iterations used.
    pub iterations: usize,
    /// How it ended.
    pub status: Status,
    /// Newton's own state where it ran out of iterations, to go on from ([`resume`]);
    /// `None` if it ended otherwise.
    more: Option<Box<Resume>>,
}

/// What Newton carries from one iteration to the next besides the iterate: the last
/// regularisation, the filter, and whether the last step was at rounding
/// ([`Settings::rounding_stall`]).
#[derive(Clone, Debug)]
struct Resume {
    delta_last: f64,
    filter: Filter,
    at_rounding: bool,
}

/// How a Newton run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    /// Out of iterations before both tolerances were met.
    Stalled,
    /// Both tolerances met, the second-order sufficient condition not (a saddle, or a
    /// minimum that is not strict) or not checked ([`Settings::second_order`]).
    Stationary,
    /// Both tolerances met and the second-order sufficient condition holds (the exact
    /// Hessian's QP is strictly convex on the constraint's null space): a strict local minimum.
    LocalMin,
}

impl Run {
    /// Whether both tolerances were met.
    pub fn converged(&self) -> bool {
        self.status != Status::Stalled
    }

    /// Whether it is a strict local minimum ([`Status::LocalMin`]).
    pub fn local_min(&self) -> bool {
        self.status == Status::LocalMin
    }

    /// Its image under a linear map of the coordinates, `state` on states, the terminal
    /// multiplier and the costates, `control` on controls and on the costates' jumps (a
    /// signed permutation, [`super::symmetry`], is its own inverse transpose, so both kinds
    /// map alike), without the bound multipliers of primal–dual steps and with nothing to
    /// resume: an extremal's image, not a point to go on from.
    pub fn image(
        &self,
        state: impl Fn(&Vector5<f64>) -> Vector5<f64>,
        control: impl Fn(&Vector2<f64>) -> Vector2<f64>,
    ) -> Run {
        Run {
            point: Point {
                u: self.point.u.iter().map(&control).collect(),
                states: self.point.states.iter().map(&state).collect(),
                nu: state(&self.point.nu),
                z: Vec::new(),
            },
            lambda: self.lambda.iter().map(&state).collect(),
            jumps: self.jumps.iter().map(&control).collect(),
            more: None,
            ..*self
        }
    }
}

/// Newton–SQP from `start` (see the module docs).
pub fn newton(grid: &Grid, start: Point, settings: &Settings) -> Result<Run, Error> {
    newton_pulsed(grid, start, settings, &|| ())
}

/// [`newton`], calling `pulse` before each iteration and between its stages (the
/// linearisation, the factorisation, the line search: each a pass over the grid, tenths of a
/// second on 10⁵ steps), where the work may be cancelled.
pub fn newton_pulsed(
    grid: &Grid,
    start: Point,
    settings: &Settings,
    pulse: &dyn Fn(),
) -> Result<Run, Error> {
    let filter = Filter::new(grid.terminal.defect(&start.states).lp_norm(1));
    let state = Resume {
        delta_last: 0.0,
        filter,
        at_rounding: false,
    };
    iterate(grid, start, 0, state, settings, pulse)
}

/// `run` gone on to `settings.max_iterations` iterations in all, as if it had been started
/// with them: the same iterates, bit for bit (a run that ended other than at its iteration
/// limit is returned as it is, since more iterations would end it there too).
pub fn resume(grid: &Grid, run: Run, settings: &Settings, pulse: &dyn Fn()) -> Result<Run, Error> {
    match run.more {
        Some(state) => iterate(grid, run.point, run.iterations, *state, settings, pulse),
        None => Ok(run),
    }
}

/// Newton's iterations from `pt` after `iterations` of them, with the state they carry.
fn iterate(
    grid: &Grid,
    mut pt: Point,
    mut iterations: usize,
    state: Resume,
    settings: &Settings,
    pulse: &dyn Fn(),
) -> Result<Run, Error> {
    let h = grid.h();
    let Resume {
        mut delta_last,
        mut filter,
        mut at_rounding,
    } = state;
    loop {
        pulse();
        let c = grid.terminal.defect(&pt.states);
        if settings.primal_dual && pt.z.len() != pt.states.len() {
            pt.z = grid.limits.duals(&pt.states);
        }
        let lz = Linearisation::new(grid, (&pt.states, &pt.u), &pt.nu, &pt.z)?;
        let maps = grid.limits.control_maps(grid.steps);
        let maps = maps.as_deref();
        let stalled =
            settings.rounding_stall && at_rounding && lz.kkt <= ROUNDING_KKT * settings.tol_kkt;
        let done = c.amax() <= settings.tol_defect && (lz.kkt <= settings.tol_kkt || stalled);
        if done || iterations >= settings.max_iterations {
            let state = Resume {
                delta_last,
                filter,
                at_rounding,
            };
            return Ok(ended(grid, pt, lz, iterations, done, settings, state));
        }
        iterations += 1;
        pulse();
        let Some((factor, delta)) = convex_factor(&lz, h, delta_last, maps) else {
            return Ok(finish(grid, pt, lz, iterations, Status::Stalled));
        };
        delta_last = delta;
        pulse();
        // With the Lagrangian's gradient as the linear term the QP's multiplier is the change
        // of `ν` (the constant `−νᵀGδu = νᵀc` drops out), and near a solution every term of the
        // step is small: no cancellation of O(1) terms in the closed loop.
        let Some((du, dnu)) = factor.solve(&lz.lin, &(-c), true) else {
            return Ok(finish(grid, pt, lz, iterations, Status::Stalled));
        };
        trace_linear_residual(&lz, &du, &c);
        let nu_qp = pt.nu + dnu;
        // The next Hessian's multiplier: the QP's when the step is Newton's (δ = 0: then the
        // iteration is Newton's method on the KKT system), otherwise the least-squares
        // estimate (a regularised QP's multiplier grows with δ and is meaningless).
        let nu = if delta == 0.0 {
            nu_qp
        } else {
            lz.nu_ls.unwrap_or(pt.nu)
        };
        let correction = |e: &Vector5<f64>| factor.solve(&lz.lin, e, false).map(|(corr, _)| corr);
        let step = Step {
            point: &pt,
            du: &du,
            nu,
        };
        let search = filter.search(grid, &step, &c, correction, settings);
        let at = (&lz, &factor, delta);
        trace_iteration(iterations, at, (&c, &nu_qp, &du), &search);
        let Some(mut p) = search.point else {
            return Ok(finish(grid, pt, lz, iterations, Status::Stalled));
        };
        if settings.primal_dual {
            let states = (&pt.states[..], &p.states[..]);
            p.z = (grid.limits).dual_step(h, states, &du, &pt.z, FRACTION_TO_BOUNDARY);
        }
        at_rounding =
            settings.rounding_stall && delta == 0.0 && amax(&du) <= ROUNDING_STEP * amax(&pt.u);
        pt = p;
    }
}

/// The run ending at `pt` with its derivatives `lz`: converged (`done`; the second-order
/// condition checked if `settings` ask for it) or out of iterations (Newton's `state` kept
/// to resume from).
fn ended(
    grid: &Grid,
    pt: Point,
    lz: Linearisation,
    iterations: usize,
    done: bool,
    settings: &Settings,
    state: Resume,
) -> Run {
    let maps = grid.limits.control_maps(grid.steps);
    let convex = || {
        Factor::new(&lz.lin, &lz.grad, grid.h(), 0.0, maps.as_deref()).is_some_and(|f| f.convex())
    };
    let status = if !done {
        Status::Stalled
    } else if settings.second_order && convex() {
        Status::LocalMin
    } else {
        Status::Stationary
    };
    let mut run = finish(grid, pt, lz, iterations, status);
    if !done {
        run.more = Some(Box::new(state));
    }
    run
}

/// Inertia correction (as IPOPT's): the factorisation of the Newton step's LQ problem with
/// the smallest `δ` that makes it convex on the constraint's null space (0, then from the
/// last iteration's `δ` over [`DELTA_DECAY`] and at least [`DELTA_MIN`]`·h`, times
/// [`DELTA_GROWTH`]), with that `δ`; `None` past [`DELTA_MAX`]`·h`.
fn convex_factor(
    lz: &Linearisation,
    h: f64,
    delta_last: f64,
    maps: Option<&[ControlMap]>,
) -> Option<(Factor, f64)> {
    let mut delta = 0.0;
    loop {
        if let Some(f) = Factor::new(&lz.lin, &lz.grad, h, delta, maps)
            && f.convex()
        {
            return Some((f, delta));
        }
        delta = if delta == 0.0 {
            (delta_last / DELTA_DECAY).max(DELTA_MIN * h)
        } else {
            delta * DELTA_GROWTH
        };
        if delta > DELTA_MAX * h {
            return None;
        }
    }
}

/// The largest `|u_{k,i}|` of `u`.
fn amax(u: &[Vector2<f64>]) -> f64 {
    u.iter().map(|v| v.amax()).fold(0.0, f64::max)
}

/// Logs one iteration at `debug` level: the objective, defect and stationarity where it
/// started, `δ` and the inertia of its factorisation, the QP's multiplier, the step length
/// the line search ended at and the step's largest control change.
fn trace_iteration(
    iterations: usize,
    (lz, factor, delta): (&Linearisation, &Factor, f64),
    (c, nu_qp, du): (&Vector5<f64>, &Vector5<f64>, &[Vector2<f64>]),
    search: &Search,
) {
    log::debug!(
        "sqp {iterations}: J {:.6} |c| {:.2e} kkt {:.2e} δ {delta:.1e} inertia {}+{} |ν_qp| {:.2e} t {:.1e} |du| {:.2e}",
        search.phi,
        c.amax(),
        lz.kkt,
        factor.negative_h,
        factor.negative_m,
        nu_qp.amax(),
        search.t,
        amax(du)
    );
}

/// Logs at `trace` level how far the step's linearised end `δs_N` misses `−c`.
fn trace_linear_residual(lz: &Linearisation, du: &[Vector2<f64>], c: &Vector5<f64>) {
    if log::log_enabled!(log::Level::Trace) {
        let mut ds = Vector5::zeros();
        for (l, d) in lz.lin.iter().zip(du) {
            ds = l.a * ds + l.b * d;
        }
        log::trace!(
            "   linear residual {:.2e} (|c| {:.2e})",
            (ds + c).amax(),
            c.amax()
        );
    }
}

/// The run ending at `point` with its derivatives `lz`.
fn finish(grid: &Grid, point: Point, lz: Linearisation, iterations: usize, status: Status) -> Run {
    let defect = grid.terminal.defect(&point.states).amax();
    Run {
        point,
        lambda: lz.lambda,
        jumps: lz.jumps,
        defect,
        kkt: lz.kkt,
        iterations,
        status,
        more: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::{Problem, Spec};
    use crate::solver::grid::shape_reach;
    use crate::solver::stage::Rule;

    /// One iteration from a loop far from any solution: with a trust radius no `α_k` moves
    /// by more than it; without, the same step moves the path further.
    #[test]
    fn the_trust_radius_bounds_each_iteration() {
        let p = Problem::new(&Spec {
            target: [0.3, 0.3, 0.0],
            ..Spec::default()
        })
        .unwrap();
        let grid = Grid::new(&p, 64, Rule::LEFT_POINT).unwrap();
        let u: Vec<Vector2<f64>> = (0..64)
            .map(|k| {
                let phi = 2.0 * core::f64::consts::PI * k as f64 / 64.0;
                Vector2::new(-phi.sin(), phi.cos()) * 0.02
            })
            .collect();
        let moved = |radius: f64| {
            let settings = Settings {
                trust_radius: radius,
                ..Settings::plain(1)
            };
            let start = Point::new(&grid, u.clone(), Vector5::zeros()).unwrap();
            let run = newton(&grid, start, &settings).unwrap();
            assert_eq!(run.iterations, 1);
            let du: Vec<Vector2<f64>> = run.point.u.iter().zip(&u).map(|(a, b)| a - b).collect();
            shape_reach(&du, grid.h())
        };
        let (bounded, free) = (moved(0.1), moved(f64::INFINITY));
        assert!(bounded > 0.0 && bounded <= 0.1 * (1.0 + 1e-12), "{bounded}");
        assert!(free > 0.3, "{free}");
    }
}
