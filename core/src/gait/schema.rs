//! The gait's schema: [`GaitParams`], its [`Model`] and the [`CheckpointRecord`]s, in `f64` as
//! stored, and the checks of each one alone (the gait's whole validation is
//! [`crate::gait::check`]).

use crate::kinematics::{Kinematics, State};
use crate::replay::{Checkpoint, Costate, TerminalError};
use crate::swimmer::check_shape;
use crate::table::VALUES;
use crate::{Cost, Error, Real, Se2, Swimmer};
use nalgebra::{Vector2, Vector3};

/// How far `cos² θ + sin² θ` of a stored rotation may be from 1.
const UNIT_TOLERANCE: f64 = 1e-9;
/// The swimmer's geometry and drag as stored (see [`Swimmer::new`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct Model {
    /// `(L0 middle, L1 front, L2 rear)`, metres.
    pub links: [f64; 3],
    /// Drag coefficient `k`.
    pub drag: f64,
    /// Drag ratio `r` (normal over tangential).
    pub ratio: f64,
}

/// Everything a gait holds besides its checkpoints, in `f64` as stored.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct GaitParams {
    /// The swimmer.
    pub model: Model,
    /// Time step `h`, seconds.
    pub h: f64,
    /// Number of steps `N`.
    pub steps: u32,
    /// Start shape `ᾱ`, radians (also the end shape unless `alpha_end` says otherwise).
    pub alpha0: [f64; 2],
    /// Target position `ḡ = (x, y, θ)`, reached from the identity.
    pub target: [f64; 3],
    /// Spatial momentum `μ`.
    pub mu: [f64; 3],
    /// Shape costate before the first step, `ξ^{−1}`.
    pub xi0: [f64; 2],
    /// Spacing of the periodic checkpoints in steps (0: none): there is one at every
    /// multiple of it below `N`, besides those at the arcs' exits ([`crate::gait::check`]).
    pub checkpoint_every: u32,
    /// The joint limit `|α_i| ≤ α_max` the gait was solved under, radians (`None`: only the
    /// links' overlap, `|α_i| < π`); required by arcs, which rest on it.
    pub alpha_max: Option<f64>,
    /// The end shape `α_N` when it differs from the start (a transition, not a loop),
    /// radians; `None`: `α_N = ᾱ`. Absent from a file that does not store one.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub alpha_end: Option<[f64; 2]>,
    /// The running cost the costate was solved for, whose law replays it (MODEL.md §11);
    /// absent (the effort) from a file that does not store one.
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "is_effort"))]
    pub cost: Cost,
}

/// Whether `cost` is the effort, which a file leaves out.
#[cfg(feature = "serde")]
fn is_effort(cost: &Cost) -> bool {
    *cost == Cost::Effort
}

/// One checkpoint `(k, α_k, g_k, ξ^{k−1})` as stored, `g` as `(x, y, cos θ, sin θ)`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct CheckpointRecord {
    /// Step index `k`.
    pub k: u32,
    /// `α_k`, radians.
    pub alpha: [f64; 2],
    /// `g_k` as `(x, y, cos θ, sin θ)`, the core's own representation.
    pub g: [f64; 4],
    /// `ξ^{k−1}`.
    pub xi: [f64; 2],
}

fn all_finite<const N: usize>(xs: [f64; N]) -> Result<(), Error> {
    if f64::all_finite(xs) {
        Ok(())
    } else {
        Err(Error::NonFinite)
    }
}

impl GaitParams {
    /// `Ok` if a replay can start from these numbers. Errors: [`Error::NonFinite`] (any
    /// number), [`Error::InvalidParameters`] (model), [`Error::InvalidStep`] (`h ≤ 0` or
    /// `N = 0`), [`Error::ShapeLimit`] (`ᾱ` or the end shape), [`Error::JointLimit`] (an
    /// `α_max` outside `]max |ᾱ_i|, π[` or not above the end shape's `|α_N,i|`).
    pub fn check(&self) -> Result<(), Error> {
        let ([l0, l1, l2], [a1, a2], [tx, ty, tt]) = (self.model.links, self.alpha0, self.target);
        let ([m1, m2, m3], [x1, x2], [b1, b2]) = (self.mu, self.xi0, self.end_shape());
        all_finite([l0, l1, l2, self.model.drag, self.model.ratio, self.h])?;
        all_finite([a1, a2, tx, ty, tt, m1, m2, m3, x1, x2, b1, b2])?;
        self.kinematics::<f64>()?;
        if self.steps == 0 {
            return Err(Error::InvalidStep);
        }
        check_shape(&Vector2::new(a1, a2))?;
        check_shape(&Vector2::new(b1, b2))?;
        match self.alpha_max {
            Some(limit) => {
                let pi = core::f64::consts::PI;
                let widest = a1.abs().max(a2.abs()).max(b1.abs()).max(b2.abs());
                let inside = limit.is_finite() && limit > widest && limit < pi;
                if inside {
                    Ok(())
                } else {
                    Err(Error::JointLimit)
                }
            }
            None => Ok(()),
        }
    }

    /// The swimmer and time step in `T` (each number rounded to nearest).
    ///
    /// Errors: [`Error::InvalidParameters`], [`Error::InvalidStep`].
    pub fn kinematics<T: Real>(&self) -> Result<Kinematics<T>, Error> {
        let m = &self.model;
        let c = T::from_f64;
        Kinematics::new(
            Swimmer::new(m.links.map(c), c(m.drag), c(m.ratio))?,
            c(self.h),
        )
    }

    /// The start `(ᾱ, e)` in `T`.
    pub fn start<T: Real>(&self) -> State<T> {
        State::at_origin(Vector2::new(
            T::from_f64(self.alpha0[0]),
            T::from_f64(self.alpha0[1]),
        ))
    }

    /// The initial costate `(μ, ξ^{−1})` in `T`.
    pub fn costate<T: Real>(&self) -> Costate<T> {
        let ([m1, m2, m3], [x1, x2]) = (self.mu.map(T::from_f64), self.xi0.map(T::from_f64));
        Costate {
            mu: Vector3::new(m1, m2, m3),
            xi: Vector2::new(x1, x2),
        }
    }

    /// The target `ḡ`.
    pub fn target(&self) -> Se2<f64> {
        let [x, y, theta] = self.target;
        Se2::new(x, y, theta)
    }

    /// The end shape `α_N`: `alpha_end`, or `ᾱ` for a loop.
    pub fn end_shape(&self) -> [f64; 2] {
        self.alpha_end.unwrap_or(self.alpha0)
    }

    /// How far `end` lands from `(α_N, ḡ)` ([`TerminalError`]; `α_N` the [`end_shape`]).
    ///
    /// [`end_shape`]: GaitParams::end_shape
    pub fn terminal_error<T: Real>(&self, end: &State<T>) -> TerminalError {
        TerminalError::new(end, &Vector2::from(self.end_shape()), &self.target())
    }
}

impl CheckpointRecord {
    /// `Ok` if the checkpoint can be restored. Errors: [`Error::NonFinite`],
    /// [`Error::ShapeLimit`] (`α_k`), [`Error::NotRotation`] (`|cos² θ + sin² θ − 1| > 1e-9`).
    pub fn check(&self) -> Result<(), Error> {
        let ([a1, a2], [x, y, c, s], [x1, x2]) = (self.alpha, self.g, self.xi);
        all_finite([a1, a2, x, y, c, s, x1, x2])?;
        check_shape(&Vector2::new(a1, a2))?;
        if (c * c + s * s - 1.0).abs() > UNIT_TOLERANCE {
            return Err(Error::NotRotation);
        }
        Ok(())
    }

    /// The checkpoint in `T` (each number rounded to nearest; `g` as stored, not
    /// renormalised).
    pub fn to_checkpoint<T: Real>(&self) -> Checkpoint<T> {
        Checkpoint::from_values(self.k, self.values().map(T::from_f64))
    }

    /// The values in stored order, `α1 α2 x y cos θ sin θ ξ1 ξ2`.
    pub(super) fn values(&self) -> [f64; VALUES] {
        let ([a1, a2], [x, y, c, s], [x1, x2]) = (self.alpha, self.g, self.xi);
        [a1, a2, x, y, c, s, x1, x2]
    }
}
