//! The running cost the law minimises (MODEL.md §11), behind one type: [`Cost`] names it (a
//! gait file stores the name), `Law` is what the law of [`crate::law`] asks of it.
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
//!   `ξ^k = ξ^{k−1} + hB_ku_k + (h/2)c_k`, `c_{k,i} = u_kᵀ∂G/∂α_i u_k` (`cost/power.rs`).
//!
//! A third cost is a module with a `Law` (in [`crate::law`]): its first iterate, its plain
//! pass and its terms of the one Newton pass ([`crate::passes`]), and a name here.
//!
//! [`Effort`] and [`Power`] are also types: the [`RunningCost`] parameter of a
//! [`crate::Replay`], so that a replay's law is fixed when it is built (one compiled step per
//! cost, the effort's the same code as before the power existed) and a caller that reads the
//! cost from a gait file chooses once, outside its loop of steps
//! ([`crate::Gait::replay_for`]).

mod power;

pub(crate) use power::PowerLaw;

use crate::kinematics::{Kinematics, State};
pub use crate::law::Effort;
use crate::law::{LawStep, OnArcs, check_inputs};
use crate::passes::Passes;
use crate::{Error, Real};
use nalgebra::{Vector2, Vector3};

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

impl<T: Real> Kinematics<T> {
    /// [`Kinematics::law_step`] of the running cost `cost` (MODEL.md §11): the stationarity
    /// `G(α_k)u_k = ξ^k − A(α_k)ᵀζ^k` and the shape costate's update with the cost's shape
    /// gradient (see [`crate::cost`]); [`Cost::Effort`] is [`Kinematics::law_step`]. The cost
    /// stands where the law's own step takes it (after `μ`). Errors as [`Kinematics::law_step`].
    #[inline]
    pub fn law_step_for(
        &self,
        state: &State<T>,
        xi_prev: &Vector2<T>,
        mu: &Vector3<T>,
        cost: Cost,
        on: OnArcs,
        passes: Passes,
    ) -> Result<LawStep<T>, Error> {
        match cost {
            Cost::Effort => self.law_step(state, xi_prev, mu, on, passes),
            Cost::Power => {
                check_inputs(state, xi_prev, mu)?;
                let power = PowerLaw::new(self.swimmer());
                self.law_step_trusted(state, xi_prev, mu, power, on, passes)
            }
        }
    }
}
