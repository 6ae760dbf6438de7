//! Checks of an extremal by routes independent of the direct method that found it.
//!
//! - [`law_residual`]: the core's control law ([`purcell_core::Kinematics::law_step`], the
//!   forward recursion the firmware runs), started at every step from the trajectory's state
//!   and costate, must give back the trajectory's control.
//! - [`terminal_residual`]: the controls re-integrated from scratch through the core's
//!   [`purcell_core::Kinematics::step`] from `(ᾱ, e)` must reach `(β, ḡ)`.
//! - [`kkt`]: the gradient of the direct problem's Lagrangian with respect to the
//!   controls, in reverse mode through the core's kinematics on dual numbers, with the
//!   multipliers the costate gives (MODEL.md §5, "Multipliers"): `λ = −Ad_{g_N}ᵀμ` for
//!   `log(ḡ⁻¹g_N) = 0` and `ν = −ξ^{N−1}` for `α_N = β` (the end shape's value does not enter
//!   the gradient: MODEL.md §12). With a joint limit, the states found
//!   on it get multipliers `η_k` of `σ·α_{k,i} ≤ α_max` solved from the stationarity of the
//!   control that moves them (`u_{k−1,i}`), as the sweep reaches them (MODEL.md §9); the
//!   residual is then that of the other controls, and every `η_k` must be `≥ 0`.
//!
//! The second-order check (no conjugate point) is the inertia of the direct method's own
//! Riccati factorisation with the exact Hessian ([`super::riccati::Factor::convex`]).

use super::cost::{Cost, Costs, Power, StageCost};
use super::settings::ON_LIMIT;
use super::solution::Trajectory;
use super::stage::coordinates;
use crate::dual::Dual;
use crate::problem::Problem;
use nalgebra::{SVector, Vector2, Vector3};
use purcell_core::{OnArcs, Se2, State};

/// `max_k |u_law(α_k, g_k, ξ^{k−1}, μ) − u_k|_∞` of the core's law of the problem's cost
/// ([`purcell_core::Kinematics::law_step_for`]), relative to `max_k |u_k|_∞` (absolute when
/// the controls are zero). Errors if the law refuses a state (e.g. past the overlap limit).
/// For the power cost, the residual of its law's equations instead ([`power_law_residual`]).
pub fn law_residual(
    problem: &Problem,
    t: &Trajectory,
    mu: &Vector3<f64>,
) -> Result<f64, purcell_core::Error> {
    if problem.cost == Cost::Power {
        return power_law_residual(problem, t, mu);
    }
    let kin = problem.kinematics::<f64>()?;
    let passes = problem.cost.passes::<f64>();
    let mut worst = 0.0f64;
    let mut scale = 0.0f64;
    for ((s, u), xi) in t.states.iter().zip(&t.controls).zip(&t.xis) {
        let step = kin.law_step_for(s, xi, mu, problem.cost, OnArcs::NONE, passes)?;
        worst = worst.max((step.u - u).amax());
        scale = scale.max(u.amax());
    }
    Ok(if scale > 0.0 { worst / scale } else { worst })
}

/// The power cost's law (MODEL.md §11) at every step, from the trajectory's state, control
/// and `ξ^{k−1}`, through the core's connection, `Ad` and `dexp`: `ζ^k = dexp_{X_k}ᵀAd_{g_k}ᵀμ`,
/// `ξ^k = ξ^{k−1} + hB_ku_k + (h/2)c_k`, and `max_k |G(α_k)u_k − ξ^k + A(α_k)ᵀζ^k|_∞`
/// relative to `max_k |G(α_k)u_k|_∞`.
pub fn power_law_residual(
    problem: &Problem,
    t: &Trajectory,
    mu: &Vector3<f64>,
) -> Result<f64, purcell_core::Error> {
    let power = Power::new(&problem.swimmer);
    let h = problem.h;
    let mut worst = 0.0f64;
    let mut scale = 0.0f64;
    for ((s, u), xi) in t.states.iter().zip(&t.controls).zip(&t.xis) {
        let c = problem.swimmer.connection_with_derivatives(&s.alpha)?;
        let zeta =
            purcell_core::se2::dexp(&(c.a * u * -h)).transpose() * s.g.adjoint_transpose_mul(mu);
        let m = power.metric(s.alpha.x, s.alpha.y);
        let bu = Vector2::new(zeta.dot(&(c.da[0] * u)), zeta.dot(&(c.da[1] * u)));
        let cu = Vector2::new(u.dot(&(m.dg[0] * u)), u.dot(&(m.dg[1] * u)));
        let xi_k = xi + bu * h + cu * (0.5 * h);
        let gu = m.g * u;
        worst = worst.max((gu - xi_k + c.a.transpose() * zeta).amax());
        scale = scale.max(gu.amax());
    }
    Ok(if scale > 0.0 { worst / scale } else { worst })
}

/// The largest component of `(α_N − β, log(ḡ⁻¹g_N))` when the controls are re-integrated
/// through [`purcell_core::Kinematics::step`] from `(ᾱ, e)`.
pub fn terminal_residual(
    problem: &Problem,
    controls: &[Vector2<f64>],
) -> Result<f64, purcell_core::Error> {
    let kin = problem.kinematics::<f64>()?;
    let mut s = State::at_origin(problem.alpha0);
    for u in controls {
        s = kin.step(&s, u)?;
    }
    let e = problem.target_se2::<f64>().between(&s.g).log();
    Ok((s.alpha - problem.alpha_end).amax().max(e.amax()))
}

type D = Dual<7>;

/// Outcome of [`kkt`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kkt {
    /// `max_k |∂L/∂u_k|_∞ / h` over the controls (rad/s).
    pub residual: f64,
    /// Smallest multiplier `η_k` of the joint limit (`None`: no state on the limit).
    pub min_eta: Option<f64>,
    /// States found on the joint limit.
    pub active: usize,
}

/// The KKT conditions of the direct problem (see the module docs) for the trajectory and the
/// costate's `μ`.
pub fn kkt(
    problem: &Problem,
    t: &Trajectory,
    mu: &Vector3<f64>,
) -> Result<Kkt, purcell_core::Error> {
    let kin = problem.kinematics::<D>()?;
    let (Some(end), Some(xi_last)) = (t.states.last(), t.xis.last()) else {
        return Err(purcell_core::Error::NonFinite);
    };
    // Terminal: Φ(s_N) = ⟨λ, log(ḡ⁻¹ g_N)⟩ + ⟨ν, α_N⟩, s = (α1, α2, x, y, θ).
    let lambda = -end.g.adjoint_transpose_mul(mu);
    let nu = -xi_last;
    let sn = coordinates(end);
    let v = |i: usize| D::variable(sn[i], i);
    let g = Se2::new(v(2), v(3), v(4));
    let e = problem.target_se2::<D>().between(&g).log();
    let phi = e.x * D::constant(lambda.x)
        + e.y * D::constant(lambda.y)
        + e.z * D::constant(lambda.z)
        + v(0) * D::constant(nu.x)
        + v(1) * D::constant(nu.y);
    let mut adj = SVector::<f64, 5>::from_fn(|i, _| phi.d[i]);
    let mut worst = 0.0f64;
    let mut min_eta: Option<f64> = None;
    let mut active = 0;
    let n = t.controls.len();
    let limit = problem.alpha_max;
    let costs = Costs::of(problem.cost, problem.swimmer);
    for (k, (s, u)) in t.states.iter().zip(&t.controls).enumerate().rev() {
        let [a1, a2, px, py, th] = coordinates(s);
        let x = [a1, a2, px, py, th, u.x, u.y];
        let w = |i: usize| D::variable(x[i], i);
        let st = State {
            alpha: Vector2::new(w(0), w(1)),
            g: Se2::new(w(2), w(3), w(4)),
        };
        let next = kin.step(&st, &Vector2::new(w(5), w(6)))?;
        // ∂J/∂u_k, the cost's share of ∂L/∂u_k (and ∂J/∂α_k, of ∂L/∂α_k).
        let sk = SVector::<f64, 5>::from([a1, a2, px, py, th]);
        let cost = costs.gradient(problem.h, &sk, u);
        let shape = costs.shape_terms(problem.h, &sk, u).map(|t| t.gradient);
        let out = coordinates(&next);
        let mut grad = [0.0; 7];
        for (o, a) in out.iter().zip(adj.iter()) {
            for (gi, di) in grad.iter_mut().zip(o.d) {
                *gi += a * di;
            }
        }
        // State k + 1 on the limit (the end state is fixed): η from ∂L/∂u_{k,i} = 0, with
        // ∂(η σ α_{k+1,i})/∂x = η σ (row i of the step's Jacobian).
        for (i, a) in [t.states[k + 1].alpha.x, t.states[k + 1].alpha.y]
            .into_iter()
            .enumerate()
        {
            if !(k + 1 < n && limit.is_some_and(|l| a.abs() >= l * (1.0 - ON_LIMIT))) {
                continue;
            }
            let sigma = a.signum();
            let row = out[i].d;
            let eta = -(cost[i] + grad[5 + i]) / (sigma * row[5 + i]);
            for (gi, di) in grad.iter_mut().zip(row) {
                *gi += eta * sigma * di;
            }
            min_eta = Some(min_eta.map_or(eta, |m| m.min(eta)));
            active += 1;
        }
        let gu = cost + Vector2::new(grad[5], grad[6]);
        worst = worst.max(gu.amax() / problem.h);
        if let Some(ga) = shape {
            grad[0] += ga.x;
            grad[1] += ga.y;
        }
        adj = SVector::<f64, 5>::from_fn(|i, _| grad[i]);
    }
    Ok(Kkt {
        residual: worst,
        min_eta,
        active,
    })
}
