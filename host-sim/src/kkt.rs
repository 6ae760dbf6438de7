//! An optimality check that does not use the control law: the gradient of the direct
//! problem's Lagrangian with respect to the controls (MODEL.md §5, "Multipliers").
//!
//! `L(u) = Σ h/2 |u_k|² + ⟨λ, log(ḡ⁻¹ g_N(u))⟩ + ⟨ν, α_N(u) − ᾱ⟩` with `λ = −Ad_{g_N}ᵀ μ`
//! and `ν = −ξ^{N−1}`. The gradient is computed in reverse mode through the plain
//! kinematics ([`purcell_core::Kinematics::step`], not the law): each step's Jacobian with
//! respect to `(α_k, x_k, y_k, θ_k, u_k)` comes from a 7-tangent [`Dual`] evaluation, and the
//! adjoint `a_k = (∂s_{k+1}/∂s_k)ᵀ a_{k+1}` runs backwards from `a_N = ∂Φ/∂s_N`, giving
//! `∂L/∂u_k = h u_k + (∂s_{k+1}/∂u_k)ᵀ a_{k+1}`. At an extremal it vanishes; the reported
//! number is `max_k |∂L/∂u_k| / h`, comparable with `|u|`.

use crate::dual::Dual;
use crate::problem::Problem;
use nalgebra::{SVector, Vector2, Vector3};
use purcell_core::{Real, Se2, State};

type D = Dual<7>;

/// `max_k |∂L/∂u_k|_∞ / h` for the trajectory `(states[k], controls[k])`, `k < N`, its end
/// state `end = (α_N, g_N)`, and the costate's `μ` and `ξ^{N−1}`.
pub fn kkt_residual(
    problem: &Problem,
    states: &[State<f64>],
    controls: &[Vector2<f64>],
    end: &State<f64>,
    mu: &Vector3<f64>,
    xi_last: &Vector2<f64>,
) -> Result<f64, purcell_core::Error> {
    let kin = problem.kinematics::<D>()?;
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
    for (s, u) in states.iter().zip(controls).rev() {
        let [a1, a2, px, py, th] = coordinates(s);
        let x = [a1, a2, px, py, th, u.x, u.y];
        let w = |i: usize| D::variable(x[i], i);
        let st = State {
            alpha: Vector2::new(w(0), w(1)),
            g: Se2::new(w(2), w(3), w(4)),
        };
        let next = kin.step(&st, &Vector2::new(w(5), w(6)))?;
        let out = coordinates(&next);
        let mut grad = [0.0; 7];
        for (o, a) in out.iter().zip(adj.iter()) {
            for (gi, di) in grad.iter_mut().zip(o.d) {
                *gi += a * di;
            }
        }
        let gu = Vector2::new(problem.h * u.x + grad[5], problem.h * u.y + grad[6]);
        worst = worst.max(gu.amax() / problem.h);
        adj = SVector::<f64, 5>::from_fn(|i, _| grad[i]);
    }
    Ok(worst)
}

/// `s = (α1, α2, x, y, θ)` of a state, for any scalar.
fn coordinates<T: Real>(s: &State<T>) -> [T; 5] {
    [s.alpha.x, s.alpha.y, s.g.x(), s.g.y(), s.g.theta()]
}
