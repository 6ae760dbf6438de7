//! The exact discrete kinematics on `R² × SE(2)`.
//!
//! ```text
//! α_{k+1} = α_k + h·u_k,     g_{k+1} = g_k · exp(X_k),     X_k = −h·A(α_k)·u_k
//! ```
//!
//! The group update is exact for a shape velocity held constant over the step at its value
//! `u_k` and the connection frozen at `α_k`: no projection, no drift off SE(2).

use crate::se2::{self, Se2, Tangent};
use crate::swimmer::{connection_mul, within_limit};
use crate::{Error, Real, Swimmer};
use nalgebra::{Matrix3x2, Vector2};

/// The swimmer's configuration: shape `α` (joint angles) and position `g ∈ SE(2)`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct State<T> {
    /// Joint angles `(α1, α2)`, radians, each in `]−π, π[`.
    pub alpha: Vector2<T>,
    /// Position of the middle link's frame.
    pub g: Se2<T>,
}

impl<T: Real> State<T> {
    /// Shape `α` at the identity position.
    pub fn at_origin(alpha: Vector2<T>) -> Self {
        State {
            alpha,
            g: Se2::identity(),
        }
    }

    /// `Ok` if every number is finite, the shape is admissible (`|α_i| < π`) and the
    /// rotation is one: `|cos²θ + sin²θ − 1| ≤` [`UNIT_ROTATION_TOLERANCE`].
    ///
    /// For states entering the core (a start, a checkpoint, the input of a checked step).
    /// The state a step returns is checked without the rotation (three operations fewer
    /// per step): [`Se2::compose`] keeps a unit rotation unit.
    #[inline]
    pub fn check(&self) -> Result<(), Error> {
        self.check_step_output()?;
        let (c, s) = (self.g.cos(), self.g.sin());
        if (c * c + s * s - T::one()).abs() <= T::from_f64(UNIT_ROTATION_TOLERANCE) {
            Ok(())
        } else {
            Err(Error::NotRotation)
        }
    }

    /// Finite and admissible: [`State::check`] without the rotation. Always inlined, as
    /// [`Kinematics::advance`].
    #[inline(always)]
    pub(crate) fn check_step_output(&self) -> Result<(), Error> {
        let (a, g) = (&self.alpha, &self.g);
        if !T::all_finite([a.x, a.y, g.x(), g.y(), g.cos(), g.sin()]) {
            return Err(Error::NonFinite);
        }
        within_limit(a.x, a.y)
    }
}

/// How far `cos²θ + sin²θ` of a state entering the core may be from 1: about 800 `f32`
/// roundings (an `f64` rotation rounded to `f32` is within 2.4e-7), and small enough that the
/// first [`Se2::compose`] brings it back to rounding (its first-order renormalisation leaves
/// `¾e²` of an error `e`).
pub const UNIT_ROTATION_TOLERANCE: f64 = 1e-4;

/// A swimmer with a fixed time step `h`: the discrete system the control law runs on.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Kinematics<T> {
    swimmer: Swimmer<T>,
    h: T,
}

impl<T: Real> Kinematics<T> {
    /// Errors: [`Error::InvalidStep`] unless `h` is finite and positive.
    pub fn new(swimmer: Swimmer<T>, h: T) -> Result<Self, Error> {
        if h.is_finite() && h > T::zero() {
            Ok(Kinematics { swimmer, h })
        } else {
            Err(Error::InvalidStep)
        }
    }

    /// The swimmer.
    pub fn swimmer(&self) -> &Swimmer<T> {
        &self.swimmer
    }

    /// The time step `h`.
    pub fn h(&self) -> T {
        self.h
    }

    /// The body twist of one step, `X = −h·A·u`.
    #[inline]
    pub fn twist(&self, a: &Matrix3x2<T>, u: &Vector2<T>) -> Tangent<T> {
        -connection_mul(a, &Vector2::new(self.h * u.x, self.h * u.y))
    }

    /// One step of the kinematics under the control `u` (rad/s).
    ///
    /// Errors: [`Error::NonFinite`], [`Error::ShapeLimit`] if `α_k` or `α_{k+1}` is at or
    /// past the link-overlap limit, [`Error::NotRotation`] if `g_k`'s rotation is not one.
    pub fn step(&self, state: &State<T>, u: &Vector2<T>) -> Result<State<T>, Error> {
        state.check()?;
        if !T::all_finite([u.x, u.y]) {
            return Err(Error::NonFinite);
        }
        let a = self.swimmer.connection(&state.alpha)?;
        let x = self.twist(&a, u);
        self.advance(state, u, &se2::exp(&x))
    }

    /// `(α + h·u, g·step)`, checked. Always inlined: a replay has two law steps (free and on
    /// an arc), and a hint would put this, a caller of each, out of line with its `Result`
    /// going through memory (on the M4F, 1.5× the step).
    #[inline(always)]
    pub(crate) fn advance(
        &self,
        state: &State<T>,
        u: &Vector2<T>,
        step: &Se2<T>,
    ) -> Result<State<T>, Error> {
        let next = State {
            alpha: Vector2::new(state.alpha.x + self.h * u.x, state.alpha.y + self.h * u.y),
            g: state.g.compose(step),
        };
        next.check_step_output()?;
        Ok(next)
    }
}
