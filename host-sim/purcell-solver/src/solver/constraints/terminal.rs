//! The terminal constraint `c(u) = s_N − s̄ = 0`: five equations, `α_N = β` (the end shape;
//! `β = ᾱ` for a loop) and
//! `(x, y, θ)_N = ḡ` in the coordinates `s = (α1, α2, x, y, θ)`.
//!
//! Its multiplier `ν` is the last costate, `λ_N = ν` ([`crate::solver::linearisation`]),
//! and the Newton step meets its linearisation `δs_N = −c` as the LQ problem's terminal
//! equality ([`crate::solver::riccati`]).

use crate::solver::stage::StageState;
use nalgebra::Vector5;

/// The end state a path must reach.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Terminal {
    /// `s̄ = (β, x̄, ȳ, θ̄)`.
    pub target: StageState,
}

impl Terminal {
    /// `c = s_N − s̄` of a rollout `s_0 … s_N` (infinite for an empty one).
    pub fn defect(&self, states: &[StageState]) -> Vector5<f64> {
        states
            .last()
            .map_or(Vector5::repeat(f64::INFINITY), |s| s - self.target)
    }
}
