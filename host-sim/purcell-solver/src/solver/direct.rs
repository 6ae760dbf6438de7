//! The direct method: Newton–SQP on the controls of the exact discrete problem, with the exact
//! Hessian of the Lagrangian and a Riccati-structured step.
//!
//! Unknowns: the controls `u_0 … u_{N−1}`; the states follow by the exact kinematics
//! ([`super::stage::step`]), so every iterate is a trajectory of the swimmer and only the
//! terminal constraint `c(u) = s_N − s̄ = 0` (five equations: `α_N = ᾱ`, `(x, y, θ)_N = ḡ`)
//! can be violated. With `L = J + νᵀc`, the costates `λ_N = ν`, `λ_k = A_kᵀλ_{k+1}` give
//! `∇_{u_k}L = h·u_k + B_kᵀλ_{k+1}`, and the Newton step is the LQ problem of
//! [`super::riccati`] with the stage Hessians of `λ_{k+1}ᵀf`. Per iteration: one rollout, one
//! backward sweep (derivatives, costates, Riccati), one forward sweep — `O(N)`.
//!
//! Globalisation: a filter line search (Wächter–Biegler, as IPOPT's) with one second-order
//! correction of a rejected full step (the terminal constraint is curved: without it the
//! merit rejects good Newton steps, the Maratos effect); when the QP is not convex on the
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

use super::constraints::joint_limit::Limits;
use super::constraints::terminal::Terminal;
use super::cost::{Effort, StageCost};
use super::riccati::Factor;
use super::settings::{
    BACKTRACK, DELTA_DECAY, DELTA_GROWTH, DELTA_MAX, DELTA_MIN, FILTER_ETA, FILTER_GAMMA_PHI,
    FILTER_GAMMA_THETA, FILTER_S_PHI, FILTER_S_THETA, FILTER_THETA_MAX, FILTER_THETA_MIN,
    FRACTION_TO_BOUNDARY, MIN_STEP, Settings, WALL_SLACK,
};
use super::stage::{Linearised, Rule, StageModel, StageState};
use crate::problem::Problem;
use nalgebra::{Vector2, Vector5};
use purcell_core::{Error, Kinematics};

/// One time grid of the problem: `steps` steps over the horizon `T`.
#[derive(Clone, Debug)]
pub struct Grid {
    /// The stage model with `h = T/steps`.
    pub model: StageModel,
    /// Steps `N`.
    pub steps: usize,
    /// `s_0 = (ᾱ, 0, 0, 0)`.
    pub start: StageState,
    /// The terminal constraint `s_N = s̄`.
    pub terminal: Terminal,
    /// How the joint limit `|α_i| ≤ α_max` enters, if at all.
    pub limits: Limits,
}

impl Grid {
    /// The problem on a grid of `steps` steps with the connection evaluated by `rule`
    /// (`steps = problem.steps` with [`Rule::LEFT_POINT`] is the problem itself).
    pub fn new(problem: &Problem, steps: usize, rule: Rule) -> Result<Self, Error> {
        let h = problem.horizon() / steps as f64;
        let kin = Kinematics::new(*problem.kinematics::<f64>()?.swimmer(), h)?;
        let a = problem.alpha0;
        let t = problem.target;
        Ok(Grid {
            model: StageModel::new(kin, rule)?,
            steps,
            start: StageState::new(a.x, a.y, 0.0, 0.0, 0.0),
            terminal: Terminal {
                target: StageState::new(a.x, a.y, t.x, t.y, t.z),
            },
            limits: Limits::None,
        })
    }

    /// Step `h`.
    pub fn h(&self) -> f64 {
        self.model.h()
    }

    /// The same problem on `steps` steps with `rule`.
    pub fn resampled(&self, steps: usize, rule: Rule) -> Result<Self, Error> {
        let h = self.h() * self.steps as f64 / steps as f64;
        let kin = Kinematics::new(*self.model.kin.swimmer(), h)?;
        Ok(Grid {
            model: StageModel::new(kin, rule)?,
            steps,
            start: self.start,
            terminal: self.terminal,
            limits: Limits::None,
        })
    }

    /// Whether the net motion of the controls `u` is resolved by this grid: the end of their
    /// shape path integrated 16 times finer by the midpoint rule (second order) lies within a
    /// fifth of the displacement asked for from the end of `u`'s own rollout. A solution that
    /// exists only through the discretisation error of a coarse grid (e.g. with equal drag
    /// along and across the links, where no loop moves the body) fails this.
    pub fn resolves(&self, u: &[Vector2<f64>]) -> bool {
        let (Ok(fine), Ok(own)) = (
            self.resampled(16 * self.steps, Rule::MIDPOINT),
            self.rollout(u),
        ) else {
            return false;
        };
        let Ok(accurate) = fine.rollout(&prolong(u, fine.steps)) else {
            return false;
        };
        let (Some(a), Some(b)) = (accurate.last(), own.last()) else {
            return false;
        };
        let scale = self.model.kin.swimmer().lengths()[0];
        let dist = |p: &StageState, q: &StageState| {
            ((p[2] - q[2]).powi(2) + (p[3] - q[3]).powi(2) + (scale * (p[4] - q[4])).powi(2)).sqrt()
        };
        dist(a, b) <= 0.2 * dist(&self.terminal.target, &self.start)
    }

    /// The states `s_0 … s_N` under the controls `u`; with a barrier, `Err(ShapeLimit)` unless
    /// every `|α_{k,i}| < α_max` (`k = 1 … N−1`).
    pub fn rollout(&self, u: &[Vector2<f64>]) -> Result<Vec<StageState>, Error> {
        let mut s = self.start;
        let mut out = Vec::with_capacity(u.len() + 1);
        out.push(s);
        for (k, uk) in u.iter().enumerate() {
            s = self.model.step(&s, uk)?;
            if k + 1 < u.len() && !self.limits.inside(&s) {
                return Err(Error::ShapeLimit);
            }
            out.push(s);
        }
        Ok(out)
    }

    /// The cost `J` of the controls `u` ([`Effort`]).
    pub fn cost(&self, u: &[Vector2<f64>]) -> f64 {
        Effort.value(self.h(), u)
    }

    /// What the direct method minimises: `J`, plus the barrier if there is one
    /// ([`Limits::objective`]).
    pub fn objective(&self, u: &[Vector2<f64>], states: &[StageState]) -> f64 {
        self.limits.objective(self.h(), self.cost(u), states)
    }

    /// The derivative of [`Grid::objective`] along the step `du`.
    pub fn objective_slope(
        &self,
        u: &[Vector2<f64>],
        states: &[StageState],
        du: &[Vector2<f64>],
    ) -> f64 {
        let h = self.h();
        self.limits
            .objective_slope(h, Effort.slope(h, u, du), states, du)
    }

    /// Stage derivatives along a rollout for the terminal multiplier `nu` (see [`Linearised`]),
    /// with the barrier's gradient in the costates and its Hessian in the stages' `hss`.
    pub fn linearise(
        &self,
        states: &[StageState],
        u: &[Vector2<f64>],
        nu: &Vector5<f64>,
    ) -> Result<Linearisation, Error> {
        let n = u.len();
        let h = self.h();
        let maps = self.limits.control_maps(self.steps);
        let free = |k: usize, i: usize| maps.as_ref().is_none_or(|m| m[k].free(i));
        let mut lin = Vec::with_capacity(n);
        let mut lambda = vec![StageState::zeros(); n + 1];
        lambda[n] = *nu;
        let mut kkt = 0.0f64;
        let mut grad = vec![Vector2::zeros(); n];
        let mut jumps = vec![Vector2::zeros(); n + 1];
        // Least-squares multiplier: minimise Σ_k |h·u_k + B_kᵀλ_{k+1}|² over the free controls,
        // with λ_{k+1} = Ψ_{k+1}ν + β_{k+1}: Ψ_N = I, Ψ_k = A_kᵀΨ_{k+1}; β_N = 0,
        // β_k = A_kᵀβ_{k+1} + ∇Φ_k (the barrier's gradient).
        let mut psi = nalgebra::Matrix5::<f64>::identity();
        let mut beta = Vector5::<f64>::zeros();
        let mut normal = nalgebra::Matrix5::<f64>::zeros();
        let mut rhs = Vector5::<f64>::zeros();
        for k in (0..n).rev() {
            let mut l = self.model.linearise(&states[k], &u[k], &lambda[k + 1])?;
            let mut g = Effort.gradient(h, &u[k]) + l.b.transpose() * lambda[k + 1];
            // A control tied by an arc (fixed, or an entry) is stationary by the multiplier η
            // of the limit at state k+1: λ^α_{k+1,i} jumps so that h·u_{k,i} + (B_kᵀλ_{k+1})_i = 0
            // (∂α_{k+1,i}/∂u_{k,i} = h). The jump does not enter the Hessians (α enters f
            // linearly).
            for i in 0..2 {
                if !free(k, i) {
                    let jump = -g[i] / h;
                    lambda[k + 1][i] += jump;
                    jumps[k + 1][i] = jump;
                    g[i] = 0.0;
                }
            }
            let mut gk = l.b.transpose() * psi;
            let mut own = Effort.gradient(h, &u[k]) + l.b.transpose() * beta;
            for i in 0..2 {
                if free(k, i) {
                    kkt = kkt.max(g[i].abs() / h);
                } else {
                    gk.row_mut(i).fill(0.0);
                    own[i] = 0.0;
                }
            }
            grad[k] = g;
            normal += gk.transpose() * gk;
            rhs -= gk.transpose() * own;
            lambda[k] = l.a.transpose() * lambda[k + 1];
            beta = l.a.transpose() * beta;
            psi = l.a.transpose() * psi;
            if k > 0
                && let Some((dphi, ddphi)) = self.limits.barrier_derivatives(h, &states[k])
            {
                for i in 0..2 {
                    lambda[k][i] += dphi[i];
                    beta[i] += dphi[i];
                    l.hss[(i, i)] += ddphi[i];
                }
            }
            lin.push(l);
        }
        lin.reverse();
        let nu_ls = normal.cholesky().map(|c| c.solve(&rhs));
        Ok(Linearisation {
            lin,
            lambda,
            jumps,
            grad,
            kkt,
            nu_ls,
        })
    }
}

/// Derivatives of the problem along a rollout.
#[derive(Clone, Debug)]
pub struct Linearisation {
    /// Stage derivatives, `k = 0 … N−1`.
    pub lin: Vec<Linearised>,
    /// Costates `λ_0 … λ_N` for the given `ν`.
    pub lambda: Vec<StageState>,
    /// The jumps of `λ^α_k` at the states on arcs (the limit's multipliers `η_k` times the
    /// arc's sign; zero elsewhere).
    pub jumps: Vec<Vector2<f64>>,
    /// `∇_{u_k}L = h·u_k + B_kᵀλ_{k+1}` (zero for controls tied by arcs).
    pub grad: Vec<Vector2<f64>>,
    /// Stationarity residual `max_k |h·u_k + B_kᵀλ_{k+1}|_∞ / h`.
    pub kkt: f64,
    /// The least-squares multiplier `argmin_ν Σ_k |h·u_k + B_kᵀλ_{k+1}(ν)|²` (`None` if the
    /// terminal state does not depend on the controls in every direction).
    pub nu_ls: Option<Vector5<f64>>,
}

/// An iterate: controls, their rollout and a terminal multiplier estimate.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// `u_0 … u_{N−1}`.
    pub u: Vec<Vector2<f64>>,
    /// `s_0 … s_N`.
    pub states: Vec<StageState>,
    /// `ν`.
    pub nu: Vector5<f64>,
}

impl Point {
    /// The controls `u` with multiplier `nu` on `grid`; `Err` if the rollout fails.
    pub fn new(grid: &Grid, u: Vec<Vector2<f64>>, nu: Vector5<f64>) -> Result<Self, Error> {
        let states = grid.rollout(&u)?;
        Ok(Point { u, states, nu })
    }
}

/// The largest `|α_i|` along a path of stage states.
pub fn max_abs_alpha(states: &[StageState]) -> f64 {
    states
        .iter()
        .map(|s| s[0].abs().max(s[1].abs()))
        .fold(0.0, f64::max)
}

/// The largest `|Σ_{j≤k} h·v_j|` over `k` and both joints: how far controls `v` take the
/// shape from where it starts (for a Newton step `du`: how far it moves the shape path).
pub fn shape_reach(v: &[Vector2<f64>], h: f64) -> f64 {
    let mut offset = Vector2::zeros();
    let mut reach = 0.0f64;
    for d in v {
        offset += d * h;
        reach = reach.max(offset.amax());
    }
    reach
}

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
    /// Whether both tolerances were met.
    pub converged: bool,
    /// At a converged point: whether the second-order sufficient condition holds (the exact
    /// Hessian's QP is strictly convex on the constraint's null space: a strict local minimum).
    pub local_min: bool,
}

/// Newton–SQP from `start` (see the module docs).
pub fn newton(grid: &Grid, start: Point, settings: &Settings) -> Result<Run, Error> {
    let h = grid.h();
    let mut pt = start;
    let mut delta_last = 0.0f64;
    let mut iterations = 0;
    let theta0 = grid.terminal.defect(&pt.states).lp_norm(1);
    let mut filter = Filter::new(theta0);
    let log = std::env::var_os("PURCELL_SQP_LOG").is_some();
    loop {
        let c = grid.terminal.defect(&pt.states);
        let lz = grid.linearise(&pt.states, &pt.u, &pt.nu)?;
        let maps = grid.limits.control_maps(grid.steps);
        let maps = maps.as_deref();
        let done = c.amax() <= settings.tol_defect && lz.kkt <= settings.tol_kkt;
        if done || iterations >= settings.max_iterations {
            let local_min =
                done && Factor::new(&lz.lin, &lz.grad, h, 0.0, maps).is_some_and(|f| f.convex());
            return Ok(finish(grid, pt, lz, iterations, done, local_min));
        }
        iterations += 1;
        // Inertia correction: the smallest δ (0, then from a third of the last one, ×10) that
        // makes the QP convex on the constraint's null space.
        let mut delta = 0.0;
        let factor = loop {
            if let Some(f) = Factor::new(&lz.lin, &lz.grad, h, delta, maps)
                && f.convex()
            {
                break Some(f);
            }
            delta = if delta == 0.0 {
                (delta_last / DELTA_DECAY).max(DELTA_MIN * h)
            } else {
                delta * DELTA_GROWTH
            };
            if delta > DELTA_MAX * h {
                break None;
            }
        };
        let Some(factor) = factor else {
            return Ok(finish(grid, pt, lz, iterations, false, false));
        };
        delta_last = delta;
        // With the Lagrangian's gradient as the linear term the QP's multiplier is the change
        // of `ν` (the constant `−νᵀGδu = νᵀc` drops out), and near a solution every term of the
        // step is small: no cancellation of O(1) terms in the closed loop.
        let Some((du, dnu)) = factor.solve(&lz.lin, &(-c), true) else {
            return Ok(finish(grid, pt, lz, iterations, false, false));
        };
        let nu_qp = pt.nu + dnu;
        if log {
            let mut ds = Vector5::zeros();
            for (l, d) in lz.lin.iter().zip(&du) {
                ds = l.a * ds + l.b * d;
            }
            eprintln!(
                "   linear residual {:.2e} (|c| {:.2e})",
                (ds + c).amax(),
                c.amax()
            );
        }
        // The next Hessian's multiplier: the QP's when the step is Newton's (δ = 0: then the
        // iteration is Newton's method on the KKT system), otherwise the least-squares
        // estimate (a regularised QP's multiplier grows with δ and is meaningless).
        let nu_next = if delta == 0.0 {
            nu_qp
        } else {
            lz.nu_ls.unwrap_or(pt.nu)
        };
        let theta = c.lp_norm(1);
        let phi = grid.objective(&pt.u, &pt.states);
        let slope = grid.objective_slope(&pt.u, &pt.states, &du);
        let trial = |t: f64, extra: Option<&[Vector2<f64>]>| -> Option<(Point, f64, f64)> {
            let u: Vec<Vector2<f64>> = match extra {
                None => pt.u.iter().zip(&du).map(|(a, b)| a + b * t).collect(),
                Some(e) => {
                    pt.u.iter()
                        .zip(&du)
                        .zip(e)
                        .map(|((a, b), e)| a + b + e)
                        .collect()
                }
            };
            let p = Point::new(grid, u, nu_next).ok()?;
            let th = grid.terminal.defect(&p.states).lp_norm(1);
            let ph = grid.objective(&p.u, &p.states);
            Some((p, th, ph))
        };
        let mut accepted = None;
        let mut t = if settings.fraction_to_boundary {
            grid.limits
                .max_step(h, &pt.states, &du, FRACTION_TO_BOUNDARY, 0.0)
        } else {
            1.0
        };
        if settings.trust_radius.is_finite() {
            let reach = shape_reach(&du, h);
            if reach * t > settings.trust_radius {
                t = settings.trust_radius / reach;
            }
        }
        // A trial that takes a state past the limit (by more than rounding) would fail in its
        // rollout: it is skipped without one.
        let wall = grid.limits.max_step(h, &pt.states, &du, 1.0, WALL_SLACK);
        while t > MIN_STEP {
            if t <= wall
                && let Some((p, th, ph)) = trial(t, None)
            {
                if let Some(kind) = filter.acceptable(theta, phi, slope, t, th, ph) {
                    accepted = Some((p, kind));
                    break;
                }
                // Second-order correction of a rejected full step that did not lower θ.
                if t == 1.0
                    && th >= theta
                    && let Some((corr, _)) =
                        factor.solve(&lz.lin, &(-grid.terminal.defect(&p.states)), false)
                    && let Some((q, thq, phq)) = trial(1.0, Some(&corr))
                    && let Some(kind) = filter.acceptable(theta, phi, slope, 1.0, thq, phq)
                {
                    accepted = Some((q, kind));
                    break;
                }
            }
            t *= BACKTRACK;
        }
        if log {
            eprintln!(
                "sqp {iterations}: J {phi:.6} |c| {:.2e} kkt {:.2e} δ {delta:.1e} inertia {}+{} |ν_qp| {:.2e} t {t:.1e} |du| {:.2e}",
                c.amax(),
                lz.kkt,
                factor.negative_h,
                factor.negative_m,
                nu_qp.amax(),
                du.iter().map(|v| v.amax()).fold(0.0, f64::max)
            );
        }
        let Some((p, kind)) = accepted else {
            return Ok(finish(grid, pt, lz, iterations, false, false));
        };
        if kind == StepKind::Constraint {
            filter.add(theta, phi);
        }
        pt = p;
    }
}

/// Whether a step was accepted for lowering the cost (Armijo) or for its progress on the
/// constraint/filter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum StepKind {
    Cost,
    Constraint,
}

/// The filter of Wächter & Biegler (IPOPT's line search), for equality constraints: a trial
/// point is acceptable if no earlier pair `(θ_j, φ_j)` (constraint violation `θ = |c|₁`, cost
/// `φ = J`) dominates it, and if it either lowers the cost enough (when the step is a descent
/// direction for the cost and the iterate nearly feasible) or lowers `θ` or `φ` enough against
/// the current point. No penalty parameter: the line search does not depend on the size of
/// the multipliers.
struct Filter {
    entries: Vec<(f64, f64)>,
    theta_max: f64,
    theta_min: f64,
}

impl Filter {
    fn new(theta0: f64) -> Self {
        Filter {
            entries: Vec::new(),
            theta_max: FILTER_THETA_MAX * theta0.max(1.0),
            theta_min: FILTER_THETA_MIN * theta0.max(1.0),
        }
    }

    fn acceptable(
        &self,
        theta: f64,
        phi: f64,
        slope: f64,
        t: f64,
        th: f64,
        ph: f64,
    ) -> Option<StepKind> {
        if !(th.is_finite() && ph.is_finite()) || th > self.theta_max {
            return None;
        }
        if self.entries.iter().any(|&(tj, pj)| th >= tj && ph >= pj) {
            return None;
        }
        let switching = slope < 0.0 && t * (-slope).powf(FILTER_S_PHI) > theta.powf(FILTER_S_THETA);
        if switching && theta <= self.theta_min {
            (ph <= phi + FILTER_ETA * t * slope).then_some(StepKind::Cost)
        } else {
            (th <= (1.0 - FILTER_GAMMA_THETA) * theta || ph <= phi - FILTER_GAMMA_PHI * theta)
                .then_some(StepKind::Constraint)
        }
    }

    fn add(&mut self, theta: f64, phi: f64) {
        let entry = (
            (1.0 - FILTER_GAMMA_THETA) * theta,
            phi - FILTER_GAMMA_PHI * theta,
        );
        self.entries
            .retain(|&(tj, pj)| !(tj >= entry.0 && pj >= entry.1));
        self.entries.push(entry);
    }
}

fn finish(
    grid: &Grid,
    point: Point,
    lz: Linearisation,
    iterations: usize,
    converged: bool,
    local_min: bool,
) -> Run {
    let defect = grid.terminal.defect(&point.states).amax();
    Run {
        point,
        lambda: lz.lambda,
        jumps: lz.jumps,
        defect,
        kkt: lz.kkt,
        iterations,
        converged,
        local_min,
    }
}

/// The controls of `u` (a grid of `u.len()` steps over the same horizon) on a grid of
/// `steps` steps: the same piecewise-linear shape path `α(t)`, sampled.
pub fn prolong(u: &[Vector2<f64>], steps: usize) -> Vec<Vector2<f64>> {
    let n = u.len();
    // α(t) relative to ᾱ at the coarse nodes, in units where the horizon is n.
    let mut nodes = Vec::with_capacity(n + 1);
    let mut a = Vector2::zeros();
    nodes.push(a);
    for v in u {
        a += v;
        nodes.push(a);
    }
    let at = |j: usize| -> Vector2<f64> {
        let x = j as f64 * n as f64 / steps as f64;
        let i = (x.floor() as usize).min(n.saturating_sub(1));
        let frac = x - i as f64;
        nodes[i] + u[i] * frac
    };
    // u_f = Δα/h_f with α in units of h_c: multiply by h_c/h_f = steps/n.
    let scale = steps as f64 / n as f64;
    let mut out = Vec::with_capacity(steps);
    let mut prev = at(0);
    for j in 1..=steps {
        let next = if j == steps { nodes[n] } else { at(j) };
        out.push((next - prev) * scale);
        prev = next;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Spec;

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

    /// `max_step(…, 1, 0)` is where the step's rollout leaves the barrier's domain.
    #[test]
    fn the_wall_is_where_the_rollout_leaves_the_limit() {
        let p = Problem::new(&Spec {
            alpha_max: Some(1.5),
            ..Spec::default()
        })
        .unwrap();
        let mut grid = Grid::new(&p, 64, Rule::LEFT_POINT).unwrap();
        grid.limits = Limits::Barrier {
            alpha_max: 1.5,
            tau: 1e-6,
        };
        let wave = |a: f64, b: f64| -> Vec<Vector2<f64>> {
            (0..64)
                .map(|k| {
                    let t = core::f64::consts::TAU * k as f64 / 64.0;
                    Vector2::new(a * t.cos(), b * (t + 1.0).cos())
                })
                .collect()
        };
        let u = wave(0.05, 0.04);
        let states = grid.rollout(&u).unwrap();
        for (a, b) in [(0.3, -0.2), (-0.5, 0.1), (0.05, 0.6)] {
            let du = wave(a, b);
            let wall = grid.limits.max_step(grid.h(), &states, &du, 1.0, 0.0);
            assert!(0.0 < wall && wall < 1.0, "{wall}");
            let at = |t: f64| -> Vec<Vector2<f64>> {
                u.iter().zip(&du).map(|(x, d)| x + d * t).collect()
            };
            assert!(grid.rollout(&at(wall * (1.0 - 1e-9))).is_ok());
            assert_eq!(
                grid.rollout(&at(wall * (1.0 + 1e-9))),
                Err(Error::ShapeLimit)
            );
            let fraction = grid
                .limits
                .max_step(grid.h(), &states, &du, FRACTION_TO_BOUNDARY, 0.0);
            assert!((fraction - FRACTION_TO_BOUNDARY * wall).abs() <= 1e-12 * wall);
        }
    }
}
