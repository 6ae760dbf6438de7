//! The running cost of the discrete problem, behind one interface ([`StageCost`]), as acados
//! keeps its cost modules apart from its dynamics and constraints.
//!
//! The solver's cost is the control effort ([`Effort`], MODEL.md §4),
//! `J = Σ_{k<N} h/2·|u_k|²`. Every other module reaches it through [`StageCost`]: the value
//! ([`super::grid::Grid::cost`]), its slope along a step (the line search), the gradient
//! of each stage (the Lagrangian's gradient and the certificate's KKT residual) and the
//! Hessian of each stage (the Riccati step). The core's law `u = ξ − Aᵀζ` is this cost's
//! stationarity condition: a new cost is a new type implementing [`StageCost`], and a law of
//! its own.

use nalgebra::{Matrix2, Vector2};

/// A running cost `J = Σ_k ℓ(u_k)` on a grid of step `h`, stage by stage.
pub trait StageCost {
    /// `J` of the controls `u`.
    fn value(&self, h: f64, u: &[Vector2<f64>]) -> f64;
    /// The derivative of `J` along the step `du`: `Σ_k ∇ℓ(u_k)·du_k`.
    fn slope(&self, h: f64, u: &[Vector2<f64>], du: &[Vector2<f64>]) -> f64;
    /// `∇ℓ(u_k)`.
    fn gradient(&self, h: f64, u: &Vector2<f64>) -> Vector2<f64>;
    /// `∇²ℓ` (the effort's is the same at every stage).
    fn hessian(&self, h: f64) -> Matrix2<f64>;
}

/// The control effort `ℓ(u) = h/2·|u|²`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Effort;

impl StageCost for Effort {
    /// `J = h/2·Σ_k |u_k|²` (`h/2` taken out of the sum).
    fn value(&self, h: f64, u: &[Vector2<f64>]) -> f64 {
        0.5 * h * u.iter().map(|v| v.norm_squared()).sum::<f64>()
    }

    /// `h·Σ_k u_k·du_k`.
    fn slope(&self, h: f64, u: &[Vector2<f64>], du: &[Vector2<f64>]) -> f64 {
        h * u.iter().zip(du).map(|(a, b)| a.dot(b)).sum::<f64>()
    }

    /// `h·u_k`.
    fn gradient(&self, h: f64, u: &Vector2<f64>) -> Vector2<f64> {
        u * h
    }

    /// `h·I`.
    fn hessian(&self, h: f64) -> Matrix2<f64> {
        Matrix2::identity() * h
    }
}
