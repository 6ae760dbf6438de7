//! The initial costate `(μ, ξ^{−1})` and the costate path, read off the direct method's
//! multipliers (MODEL.md §5).
//!
//! The direct method's costate `λ_k = (λ^α, λ_p, λ_θ)` is that of the coordinates
//! `(α, x, y, θ)`. A left perturbation `η = (η_v, η_ω)` of `g_k` moves the coordinates by
//! `δp = η_v + η_ω·Jp`, `δθ = η_ω` (`J` the rotation by π/2), so the left-trivialised costate
//! is `κ = (λ_p, λ_θ + λ_pᵀJp)`; it is the same at every step (the kinematics are
//! left-invariant) and equals `−μ`. Stationarity in `u_k`, `h·u_k + B_kᵀλ_{k+1} = 0`, then
//! reads `u_k = −λ^α_{k+1} − A(α_k)ᵀζ^k` with `ζ^k = dexp_{X_k}ᵀ Ad_{g_k}ᵀ μ`: the law, with
//! `ξ^k = −λ^α_{k+1}`.

use super::solution::Trajectory;
use super::stage::StageState;
use nalgebra::{Vector2, Vector3};
use purcell_core::{Se2, State};

/// `μ = −κ` from the costate `lambda` and the state `s` of one step.
pub fn momentum(lambda: &StageState, s: &StageState) -> Vector3<f64> {
    let (lx, ly, lt) = (lambda[2], lambda[3], lambda[4]);
    // λ_pᵀ J p with J p = (−y, x).
    let lpjp = -lx * s[3] + ly * s[2];
    Vector3::new(-lx, -ly, -(lt + lpjp))
}

/// The terminal multiplier `ν = λ_N` (coordinates) of an extremal with momentum `mu`, last
/// costate `ξ^{N−1}` and end state `s_N`: the inverse of [`momentum`] with `λ^α_N = −ξ^{N−1}`.
pub fn multiplier(mu: &Vector3<f64>, xi_last: &Vector2<f64>, s: &StageState) -> StageState {
    let (lx, ly) = (-mu.x, -mu.y);
    let lpjp = -lx * s[3] + ly * s[2];
    StageState::new(-xi_last.x, -xi_last.y, lx, ly, -mu.z - lpjp)
}

/// The trajectory in the core's terms: states `(α_k, g_k)`, controls, and
/// `ξ^{k−1} = −(λ^α_k − j_k)`, where `j_k` is the jump of `λ^α` at a state on a joint-limit arc
/// (MODEL.md §9: the law's `ξ^{k−1}` is the costate without state `k`'s jump; no jumps without
/// limits).
pub fn trajectory(
    states: &[StageState],
    u: &[Vector2<f64>],
    lambda: &[StageState],
    jumps: &[Vector2<f64>],
) -> Trajectory {
    Trajectory {
        states: states
            .iter()
            .map(|s| State {
                alpha: Vector2::new(s[0], s[1]),
                g: Se2::new(s[2], s[3], s[4]),
            })
            .collect(),
        controls: u.to_vec(),
        xis: lambda
            .iter()
            .zip(jumps)
            .map(|(l, j)| -(Vector2::new(l[0], l[1]) - j))
            .collect(),
    }
}
