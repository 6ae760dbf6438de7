//! The running cost of the discrete problem, behind one interface ([`StageCost`]), as acados
//! keeps its cost modules apart from its dynamics and constraints (MODEL.md §11).
//!
//! A cost is `J = Σ_{k<N} ℓ(α_k, u_k)` on a grid of step `h`. Every other module reaches it
//! through [`StageCost`]: the value ([`super::grid::Grid::cost`]), its slope along a step
//! (the line search), the gradient of each stage in the control and in the shape (the
//! Lagrangian's gradient, the costates, the certificate's KKT residual) and the Hessian of each
//! stage (the Riccati step and its inertia). [`Cost`] names the costs a problem can have
//! ([`crate::problem`]); the solver holds it as [`Costs`], the cost with what it needs to be
//! evaluated.
//!
//! - [`Effort`]: `ℓ = h/2·|u|²` (MODEL.md §4), the paper's; it does not depend on the shape.
//! - [`Power`]: `ℓ = h/2·uᵀG(α)u`, the power the fluid dissipates (MODEL.md §11).

mod power;

pub use power::{Metric, Power};

pub use crate::problem::Cost;

use super::stage::StageState;
use nalgebra::{Matrix2, Vector2};

/// A running cost `J = Σ_k ℓ(α_k, u_k)` on a grid of step `h`, stage by stage; `states` are
/// the stage states `s_k = (α, x, y, θ)` of the controls `u` (at least `u.len()` of them).
pub trait StageCost {
    /// `J` of the controls `u` along `states`.
    fn value(&self, h: f64, states: &[StageState], u: &[Vector2<f64>]) -> f64;
    /// The derivative of `J` along the step `du` (the shapes moving with it,
    /// `δα_{k+1} = δα_k + h·du_k`, `δα_0 = 0`).
    fn slope(&self, h: f64, states: &[StageState], u: &[Vector2<f64>], du: &[Vector2<f64>]) -> f64;
    /// `∇_u ℓ(α_k, u_k)`.
    fn gradient(&self, h: f64, s: &StageState, u: &Vector2<f64>) -> Vector2<f64>;
    /// `∇²_uu ℓ(α_k, u_k)`.
    fn hessian(&self, h: f64, s: &StageState, u: &Vector2<f64>) -> Matrix2<f64>;
    /// The shape terms `(∇_α ℓ, ∇²_αα ℓ, ∇²_αu ℓ)`, or `None` for a cost of the controls alone.
    fn shape_terms(&self, h: f64, s: &StageState, u: &Vector2<f64>) -> Option<ShapeTerms>;
}

/// The derivatives of a stage cost in the shape `α` (MODEL.md §11).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeTerms {
    /// `∇_α ℓ`.
    pub gradient: Vector2<f64>,
    /// `∇²_αα ℓ`.
    pub haa: Matrix2<f64>,
    /// `∇²_αu ℓ` (row `i`: `∂/∂α_i`).
    pub hau: Matrix2<f64>,
}

/// [`Costs`] from the rows of [`purcell_core::for_each_cost!`]: each core cost's type is
/// named here by a [`StageCost`] of the same name, made by [`OfSwimmer`].
macro_rules! costs {
    ({} $($(#[$attr:meta])* $ty:ident = $code:literal, $name:literal;)*) => {
        /// A [`Cost`] with what it needs to be evaluated; dispatches [`StageCost`].
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub enum Costs {
            $(
                #[doc = concat!("[`", stringify!($ty), "`].")]
                $ty($ty),
            )*
        }

        impl Costs {
            /// `cost` ready to evaluate for `swimmer`.
            pub fn of(cost: Cost, swimmer: purcell_core::Swimmer<f64>) -> Costs {
                match cost {
                    $(Cost::$ty => Costs::$ty($ty::of(&swimmer)),)*
                }
            }

            fn inner(&self) -> &dyn StageCost {
                match self {
                    $(Costs::$ty(c) => c,)*
                }
            }
        }
    };
}

purcell_core::for_each_cost!(costs);

/// A [`StageCost`] of a swimmer: what [`Costs::of`] makes.
pub trait OfSwimmer {
    /// The cost of `swimmer`.
    fn of(swimmer: &purcell_core::Swimmer<f64>) -> Self;
}

impl StageCost for Costs {
    fn value(&self, h: f64, states: &[StageState], u: &[Vector2<f64>]) -> f64 {
        self.inner().value(h, states, u)
    }

    fn slope(&self, h: f64, states: &[StageState], u: &[Vector2<f64>], du: &[Vector2<f64>]) -> f64 {
        self.inner().slope(h, states, u, du)
    }

    fn gradient(&self, h: f64, s: &StageState, u: &Vector2<f64>) -> Vector2<f64> {
        self.inner().gradient(h, s, u)
    }

    fn hessian(&self, h: f64, s: &StageState, u: &Vector2<f64>) -> Matrix2<f64> {
        self.inner().hessian(h, s, u)
    }

    fn shape_terms(&self, h: f64, s: &StageState, u: &Vector2<f64>) -> Option<ShapeTerms> {
        self.inner().shape_terms(h, s, u)
    }
}

/// The control effort `ℓ(u) = h/2·|u|²`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Effort;

impl OfSwimmer for Effort {
    fn of(_: &purcell_core::Swimmer<f64>) -> Effort {
        Effort
    }
}

impl StageCost for Effort {
    /// `J = h/2·Σ_k |u_k|²` (`h/2` taken out of the sum).
    fn value(&self, h: f64, _: &[StageState], u: &[Vector2<f64>]) -> f64 {
        0.5 * h * u.iter().map(|v| v.norm_squared()).sum::<f64>()
    }

    /// `h·Σ_k u_k·du_k`.
    fn slope(&self, h: f64, _: &[StageState], u: &[Vector2<f64>], du: &[Vector2<f64>]) -> f64 {
        h * u.iter().zip(du).map(|(a, b)| a.dot(b)).sum::<f64>()
    }

    /// `h·u_k`.
    fn gradient(&self, h: f64, _: &StageState, u: &Vector2<f64>) -> Vector2<f64> {
        u * h
    }

    /// `h·I`.
    fn hessian(&self, h: f64, _: &StageState, _: &Vector2<f64>) -> Matrix2<f64> {
        Matrix2::identity() * h
    }

    /// None: the effort does not depend on the shape.
    fn shape_terms(&self, _: f64, _: &StageState, _: &Vector2<f64>) -> Option<ShapeTerms> {
        None
    }
}
