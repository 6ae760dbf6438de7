//! The running cost the law minimises (MODEL.md §11), behind one type: [`Cost`] names it (a
//! gait file stores the name), [`Law`] is what the law of [`crate::law`] asks of it.
//!
//! A cost `J = Σ_k ℓ(α_k, u_k)` enters the law's equations only through the stationarity in
//! `u_k` and the shape costate's update:
//!
//! ```text
//! ∇_uℓ(α_k, u_k)/h = ξ^k − A(α_k)ᵀζ^k,    ξ^k = ξ^{k−1} + hB_ku_k + ∇_αℓ(α_k, u_k)/h
//! ```
//!
//! - [`Effort`]: `ℓ = h/2·|u|²`, the paper's (MODEL.md §5): `u_k = ξ^k − Aᵀζ^k`.
//! - [`Power`]: `ℓ = h/2·uᵀG(α)u`, the power the fluid dissipates: `G(α_k)u_k = ξ^k − Aᵀζ^k`,
//!   `ξ^k = ξ^{k−1} + hB_ku_k + (h/2)c_k`, `c_{k,i} = u_kᵀ∂G/∂α_i u_k` ([`power`]).
//!
//! A third cost is a module with a [`Law`]: its first iterate and its two kinds of passes
//! ([`crate::passes`]), and a name here.
//!
//! [`Effort`] and [`Power`] are also types: the [`RunningCost`] parameter of a
//! [`crate::Replay`], so that a replay's law is fixed when it is built (one compiled step per
//! cost, the effort's the same code as before the power existed) and a caller that reads the
//! cost from a gait file chooses once, outside its loop of steps
//! ([`crate::Gait::replay_for`]).

mod power;

pub(crate) use power::PowerLaw;

use crate::law::{Equation, Rows};
use crate::{Error, Real};
use nalgebra::Vector2;

/// The costs the core's law runs, by the name a gait file and a costate file store.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "lowercase")
)]
pub enum Cost {
    /// The joints' effort `Σ h/2·|u_k|²` (the paper's).
    #[default]
    Effort,
    /// The power the fluid dissipates, `Σ h/2·u_kᵀG(α_k)u_k` (MODEL.md §11).
    Power,
}

impl Cost {
    /// Every cost.
    pub const ALL: [Cost; 2] = [Cost::Effort, Cost::Power];

    /// Its name (`"effort"`, `"power"`).
    pub const fn name(self) -> &'static str {
        match self {
            Cost::Effort => "effort",
            Cost::Power => "power",
        }
    }

    /// Its code in a gait file (docs/GAIT.md): its index in [`Cost::ALL`].
    pub(crate) const fn code(self) -> u32 {
        self as u32
    }

    /// The cost of a gait file's code; `None` for an unknown one.
    pub(crate) fn from_code(code: u32) -> Option<Cost> {
        Cost::ALL.into_iter().find(|c| c.code() == code)
    }
}

/// A running cost as a type, the law a [`crate::Replay`] runs: [`Effort`] or [`Power`].
pub trait RunningCost: Copy + Default + core::fmt::Debug + sealed::Sealed {
    /// The cost's name.
    const COST: Cost;
}

mod sealed {
    /// Only the core's costs have a law.
    pub trait Sealed {}
    impl Sealed for super::Effort {}
    impl Sealed for super::Power {}
}

impl RunningCost for Effort {
    const COST: Cost = Cost::Effort;
}

/// The power the fluid dissipates as a [`RunningCost`] ([`Cost::Power`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct Power;

impl RunningCost for Power {
    const COST: Cost = Cost::Power;
}

/// A step's `u_k` and `ξ^k`.
pub(crate) type Solution<T> = (Vector2<T>, Vector2<T>);

/// The law's equations of a cost: [`Law::at`] takes what the cost needs at a step's shape.
pub(crate) trait Law<T: Real>: Copy {
    /// The cost at one step.
    type Step: Step<T>;
    /// The cost at the step of `eq`.
    fn at(self, eq: &Equation<T>) -> Self::Step;
}

/// The three parts of a step's solve (see [`crate::law`]), each solving `rows`.
pub(crate) trait Step<T: Real> {
    /// The root of the law's equation linearised at `u = 0` (and, for a cost whose shape
    /// gradient is not zero, its quadratic term taken in by a Newton step), with its `ξ^k`.
    fn first_iterate<R: Rows<T>>(&self, eq: &Equation<T>, rows: R) -> Result<Solution<T>, Error>;
    /// A plain pass from `u` ([`crate::PassKind::Plain`]).
    fn plain_pass<R: Rows<T>>(
        &self,
        eq: &Equation<T>,
        u: &Vector2<T>,
        rows: R,
    ) -> Result<Solution<T>, Error>;
    /// A Newton pass from `u` ([`crate::PassKind::Newton`]).
    fn newton_pass<R: Rows<T>>(
        &self,
        eq: &Equation<T>,
        u: &Vector2<T>,
        rows: R,
    ) -> Result<Solution<T>, Error>;
}

/// The effort `ℓ = h/2·|u|²`: the law of [`crate::law`] as it is ([`Cost::Effort`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct Effort;

impl<T: Real> Law<T> for Effort {
    type Step = Effort;
    #[inline(always)]
    fn at(self, _: &Equation<T>) -> Effort {
        Effort
    }
}

impl<T: Real> Step<T> for Effort {
    #[inline(always)]
    fn first_iterate<R: Rows<T>>(&self, eq: &Equation<T>, rows: R) -> Result<Solution<T>, Error> {
        eq.first_iterate(rows)
    }

    #[inline(always)]
    fn plain_pass<R: Rows<T>>(
        &self,
        eq: &Equation<T>,
        u: &Vector2<T>,
        rows: R,
    ) -> Result<Solution<T>, Error> {
        eq.plain_pass(u, rows)
    }

    #[inline(always)]
    fn newton_pass<R: Rows<T>>(
        &self,
        eq: &Equation<T>,
        u: &Vector2<T>,
        rows: R,
    ) -> Result<Solution<T>, Error> {
        eq.newton_pass(u, rows)
    }
}
