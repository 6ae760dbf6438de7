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
//! **The costs' one table** is [`for_each_cost!`](crate::for_each_cost): each cost's type,
//! code in a gait file and name. Everything that lists the costs derives from it — [`Cost`]
//! with its names and codes, [`RunningCost`], [`with_cost!`](crate::with_cost) (the one
//! match on a cost known at run time), the law's dispatch, [`crate::gait::AnyReplay`], and
//! outside the core the solver's costs, the CLI's `--cost`, `report.json`'s costs and
//! Python's `cost=`. A third cost is a module with its type and a `CostLaw` (its `Law` in
//! [`crate::law`]: first iterate, plain pass, its terms of the one Newton pass,
//! [`crate::passes`]) and a row of the table.
//!
//! [`Effort`] and [`Power`] are also types: the [`RunningCost`] parameter of a
//! [`crate::Replay`], so that a replay's law is fixed when it is built (one compiled step per
//! cost, the effort's the same code as before the power existed) and a caller that reads the
//! cost from a gait file chooses once, outside its loop of steps
//! ([`crate::Gait::replay_for`], [`crate::with_cost!`]).

mod power;

pub use power::Power;

use crate::kinematics::{Kinematics, State};
pub use crate::law::Effort;
use crate::law::{Free, Law, LawStep, OnArcs, Rows, check_inputs};
use crate::passes::Passes;
use crate::swimmer::Swimmer;
use crate::{Error, Real};
use nalgebra::{Vector2, Vector3};

/// The one table of the costs, handed to `$callback` (a `macro_rules!` macro, by its path),
/// one row per cost: its attributes (docs; `#[default]` on the effort's), then
/// `Type = code, "name";` — the [`RunningCost`] type (in [`crate::cost`]), its code in a gait
/// file (docs/GAIT.md; the effort's 0, as every gait file before the costs had) and its name
/// (the CLI's `--cost`, `report.json`, Python's `cost=`). The tokens in `{ … }` after the
/// callback's path, if any, go first, in braces: a callback takes
/// `{ $($extra:tt)* } $($(#[$attr:meta])* $ty:ident = $code:literal, $name:literal;)*`.
#[macro_export]
macro_rules! for_each_cost {
    ($($callback:ident)::+ $({ $($extra:tt)* })?) => {
        $($callback)::+! {
            { $($($extra)*)? }
            /// The joints' effort `Σ h/2·|u_k|²` (the paper's).
            #[default]
            Effort = 0, "effort";
            /// The power the fluid dissipates, `Σ h/2·u_kᵀG(α_k)u_k` (MODEL.md §11).
            Power = 1, "power";
        }
    };
}

/// `body` with `C` the [`RunningCost`] type of `cost`, a [`Cost`] known at run time: the one
/// match on a cost, from [`for_each_cost!`](crate::for_each_cost), each cost's `body` its own
/// compiled code.
///
/// ```
/// use purcell_core::cost::RunningCost;
/// fn name<C: RunningCost>() -> &'static str {
///     C::COST.name()
/// }
/// let cost = purcell_core::Cost::Power;
/// assert_eq!(purcell_core::with_cost!(cost, C => name::<C>()), "power");
/// ```
#[macro_export]
macro_rules! with_cost {
    ($cost:expr, $c:ident => $body:expr) => {
        $crate::for_each_cost!($crate::__with_cost { $cost, $c => $body })
    };
}

/// [`with_cost!`](crate::with_cost)'s match, from the rows of
/// [`for_each_cost!`](crate::for_each_cost).
#[doc(hidden)]
#[macro_export]
macro_rules! __with_cost {
    ({ $cost:expr, $c:ident => $body:expr }
     $($(#[$attr:meta])* $ty:ident = $code:literal, $name:literal;)*) => {
        match $cost {
            $($crate::Cost::$ty => {
                type $c = $crate::cost::$ty;
                $body
            })*
        }
    };
}

/// [`Cost`] and what dispatches on it, from the rows of [`for_each_cost!`](crate::for_each_cost).
macro_rules! costs {
    ({} $($(#[$attr:meta])* $ty:ident = $code:literal, $name:literal;)*) => {
        /// The costs the core's law runs, by the name a gait file and a costate file store.
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
        pub enum Cost {
            $(
                $(#[$attr])*
                #[cfg_attr(feature = "serde", serde(rename = $name))]
                $ty = $code,
            )*
        }

        impl Cost {
            /// Every cost, in the order of their codes.
            pub const ALL: [Cost; [$($name),*].len()] = [$(Cost::$ty),*];

            /// Its name (`"effort"`, `"power"`, …).
            pub const fn name(self) -> &'static str {
                match self {
                    $(Cost::$ty => $name,)*
                }
            }

            /// The passes after the first iterate a flight in `T` runs the cost's law with
            /// ([`Real::PASSES`], or the cost's own: [`Real::POWER_PASSES`]).
            #[inline(always)]
            pub const fn passes<T: Real>(self) -> Passes {
                match self {
                    $(Cost::$ty => <$ty as CostLaw<T>>::PASSES,)*
                }
            }

        }

        $(
            impl sealed::Sealed for $ty {}
            impl RunningCost for $ty {
                const COST: Cost = Cost::$ty;
            }
        )*

        impl<T: Real> Kinematics<T> {
            /// [`Kinematics::law_step_trusted`] of the law of `cost` (a constant in a
            /// replay's step, so that each cost's step compiles only its own law).
            #[inline(always)]
            #[allow(clippy::too_many_arguments)]
            pub(crate) fn law_step_of<R: Rows<T>>(
                &self,
                cost: Cost,
                state: &State<T>,
                xi_prev: &Vector2<T>,
                mu: &Vector3<T>,
                rows: R,
                passes: Passes,
            ) -> Result<LawStep<T>, Error> {
                match cost {
                    $(Cost::$ty => {
                        let law = <$ty as CostLaw<T>>::law(self.swimmer());
                        self.law_step_trusted(state, xi_prev, mu, law, rows, passes)
                    })*
                }
            }
        }
    };
}

for_each_cost!(costs);

impl Cost {
    /// Its code in a gait file (docs/GAIT.md): its row's in
    /// [`for_each_cost!`](crate::for_each_cost).
    pub(crate) const fn code(self) -> u32 {
        self as u32
    }

    /// The cost named `name` ([`Cost::name`]); `None` for an unknown one.
    pub fn named(name: &str) -> Option<Cost> {
        Cost::ALL.into_iter().find(|c| c.name() == name)
    }

    /// The cost of a gait file's code; `None` for an unknown one.
    pub(crate) fn from_code(code: u32) -> Option<Cost> {
        Cost::ALL.into_iter().find(|c| c.code() == code)
    }
}

/// A running cost as a type, the law a [`crate::Replay`] runs: a type of
/// [`for_each_cost!`](crate::for_each_cost).
pub trait RunningCost: Copy + Default + core::fmt::Debug + sealed::Sealed {
    /// The cost's name.
    const COST: Cost;
}

mod sealed {
    /// Only the core's costs have a law.
    pub trait Sealed {}
}

/// A cost's law in `T` ([`crate::law::Law`]) and the passes a flight runs it with.
pub(crate) trait CostLaw<T: Real> {
    /// The law.
    type Law: Law<T>;
    /// The passes after the first iterate of a flight in `T` ([`Real::PASSES`] or the cost's own).
    const PASSES: Passes;
    /// The law of `swimmer`.
    fn law(swimmer: &Swimmer<T>) -> Self::Law;
}

impl<T: Real> CostLaw<T> for Effort {
    type Law = Effort;
    const PASSES: Passes = T::PASSES;
    #[inline(always)]
    fn law(_: &Swimmer<T>) -> Effort {
        Effort
    }
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
        check_inputs(state, xi_prev, mu)?;
        // Off the arcs, the free rows (as `law_step`'s).
        if on == OnArcs::NONE {
            self.law_step_of(cost, state, xi_prev, mu, Free, passes)
        } else {
            self.law_step_of(cost, state, xi_prev, mu, on, passes)
        }
    }
}
