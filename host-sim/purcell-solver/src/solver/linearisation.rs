//! The derivatives of the problem along a rollout, in one backward sweep: the stage
//! Jacobians and the Hessians of the stage Lagrangian `ℓ(s_k, u_k) + λ_{k+1}ᵀf`
//! ([`super::stage`], [`super::cost`]), the costates `λ_N = ν`, `λ_k = A_kᵀλ_{k+1} + ∇_sℓ`
//! (with the barrier's gradient, and the jumps by which the joint limit's multipliers hold
//! the controls tied by arcs), the Lagrangian's gradient `∇_{u_k}L = ∇_uℓ + B_kᵀλ_{k+1}`, the
//! stationarity residual and the least-squares multiplier.

use super::constraints::joint_limit::Duals;
use super::cost::StageCost;
use super::grid::Grid;
use super::stage::{Linearised, StageState};
use nalgebra::{Vector2, Vector5};
use purcell_core::Error;

/// Derivatives of the problem along a rollout.
#[derive(Clone, Debug)]
pub struct Linearisation {
    /// Stage derivatives, `k = 0 … N−1`, the cost's Hessian included.
    pub lin: Vec<Linearised>,
    /// Costates `λ_0 … λ_N` for the given `ν`.
    pub lambda: Vec<StageState>,
    /// The jumps of `λ^α_k` at the states on arcs (the limit's multipliers `η_k` times the
    /// arc's sign; zero elsewhere).
    pub jumps: Vec<Vector2<f64>>,
    /// `∇_{u_k}L = ∇_uℓ + B_kᵀλ_{k+1}` (zero for controls tied by arcs).
    pub grad: Vec<Vector2<f64>>,
    /// Stationarity residual `max_k |∇_uℓ + B_kᵀλ_{k+1}|_∞ / h`.
    pub kkt: f64,
    /// The least-squares multiplier `argmin_ν Σ_k |∇_uℓ + B_kᵀλ_{k+1}(ν)|²` (`None` if the
    /// terminal state does not depend on the controls in every direction).
    pub nu_ls: Option<Vector5<f64>>,
}

impl Linearisation {
    /// Stage derivatives along a rollout for the terminal multiplier `nu` (see [`Linearised`]),
    /// with the cost's and the barrier's gradients in the costates and their Hessians in the
    /// stages' (the barrier's primal–dual Hessian if bound multipliers `z` are given, one per
    /// state, [`Limits::barrier_derivatives`]).
    ///
    /// [`Limits::barrier_derivatives`]: super::constraints::joint_limit::Limits::barrier_derivatives
    pub fn new(
        grid: &Grid,
        (states, u): (&[StageState], &[Vector2<f64>]),
        nu: &Vector5<f64>,
        z: &[Duals],
    ) -> Result<Linearisation, Error> {
        let n = u.len();
        let h = grid.h();
        let maps = grid.limits.control_maps(grid.steps);
        let free = |k: usize, i: usize| maps.as_ref().is_none_or(|m| m[k].free(i));
        let mut lin = Vec::with_capacity(n);
        let mut lambda = vec![StageState::zeros(); n + 1];
        lambda[n] = *nu;
        let mut kkt = 0.0f64;
        let mut grad = vec![Vector2::zeros(); n];
        let mut jumps = vec![Vector2::zeros(); n + 1];
        // Least-squares multiplier: minimise Σ_k |∇_uℓ + B_kᵀλ_{k+1}|² over the free controls,
        // with λ_{k+1} = Ψ_{k+1}ν + β_{k+1}: Ψ_N = I, Ψ_k = A_kᵀΨ_{k+1}; β_N = 0,
        // β_k = A_kᵀβ_{k+1} + ∇_sℓ_k + ∇Φ_k (the cost's and the barrier's gradients).
        let mut psi = nalgebra::Matrix5::<f64>::identity();
        let mut beta = Vector5::<f64>::zeros();
        let mut normal = nalgebra::Matrix5::<f64>::zeros();
        let mut rhs = Vector5::<f64>::zeros();
        for k in (0..n).rev() {
            let mut l = grid.model.linearise(&states[k], &u[k], &lambda[k + 1])?;
            let cost = grid.cost.gradient(h, &states[k], &u[k]);
            let mut g = cost + l.b.transpose() * lambda[k + 1];
            // A control tied by an arc (fixed, or an entry) is stationary by the multiplier η
            // of the limit at state k+1: λ^α_{k+1,i} jumps so that h·u_{k,i} + (B_kᵀλ_{k+1})_i = 0
            // (∂α_{k+1,i}/∂u_{k,i} = h). The jump does not enter the Hessians (α enters f
            // linearly, and the cost is not a function of α_{k+1}).
            for i in 0..2 {
                if !free(k, i) {
                    let jump = -g[i] / h;
                    lambda[k + 1][i] += jump;
                    jumps[k + 1][i] = jump;
                    g[i] = 0.0;
                }
            }
            let mut gk = l.b.transpose() * psi;
            let mut own = cost + l.b.transpose() * beta;
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
            add_cost(grid, (&states[k], &u[k]), &mut l, &mut lambda[k], &mut beta);
            if k > 0
                && let Some((dphi, ddphi)) =
                    grid.limits.barrier_derivatives(h, &states[k], z.get(k))
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

/// The cost's share of stage `k` at `(s_k, u_k)`: its control Hessian in `l.huu`, and where it
/// depends on the shape, its shape gradient in `λ_k` and `β_k` and its shape Hessians in
/// `l.hss`, `l.hsu`.
fn add_cost(
    grid: &Grid,
    (s, u): (&StageState, &Vector2<f64>),
    l: &mut Linearised,
    lambda: &mut StageState,
    beta: &mut Vector5<f64>,
) {
    let h = grid.h();
    l.huu += grid.cost.hessian(h, s, u);
    if let Some(t) = grid.cost.shape_terms(h, s, u) {
        for i in 0..2 {
            lambda[i] += t.gradient[i];
            beta[i] += t.gradient[i];
            for j in 0..2 {
                l.hss[(i, j)] += t.haa[(i, j)];
                l.hsu[(i, j)] += t.hau[(i, j)];
            }
        }
    }
}
