//! A gait's replay of whichever cost the gait has, held at run time ([`AnyReplay`]): for a
//! caller that keeps a replay between calls and cannot be generic over the cost (the C API,
//! a control loop's pilot). Its variants are the rows of [`crate::for_each_cost!`].

use crate::cost::{Cost, RunningCost};
use crate::{Error, Real, Replay, Sample, State};

/// [`AnyReplay`] and what dispatches on it, from the rows of [`crate::for_each_cost!`].
macro_rules! any_replay {
    ({} $($(#[$attr:meta])* $ty:ident = $code:literal, $name:literal;)*) => {
        /// A replay running the law of its gait's cost ([`crate::Gait::replay_any`]): each
        /// cost's step is its own compiled code, reached by one match on the variant per call.
        #[derive(Clone, Debug)]
        pub enum AnyReplay<'a, T> {
            $(
                #[doc = concat!("A gait of the cost `", $name, "`.")]
                $ty(Replay<'a, T, crate::cost::$ty>),
            )*
        }

        impl<'a, T: Real> AnyReplay<'a, T> {
            /// Runs `with` on the replay, of its own cost: the one match on the variant. A
            /// loop that must cost the effort's step what it did before the power existed
            /// runs each cost's code around its step in `with` (the C API, the control loop's
            /// pilot): a match on [`AnyReplay::step`]'s result costs about 10 instructions per
            /// step on the M4F.
            #[inline(always)]
            pub fn with_mut<W: WithAnyReplay<'a, T>>(&mut self, with: W) -> W::Output {
                match self {
                    $(AnyReplay::$ty(r) => with.run(r),)*
                }
            }

            /// [`Replay::step`].
            #[inline]
            pub fn step(&mut self) -> Result<Option<&Sample<T>>, Error> {
                match self {
                    $(AnyReplay::$ty(r) => r.step(),)*
                }
            }

            /// [`Replay::state`].
            #[inline]
            pub fn state(&self) -> &State<T> {
                match self {
                    $(AnyReplay::$ty(r) => r.state(),)*
                }
            }

            /// [`Replay::last_sample`].
            #[inline]
            pub fn last_sample(&self) -> Option<&Sample<T>> {
                match self {
                    $(AnyReplay::$ty(r) => r.last_sample(),)*
                }
            }

            /// [`Replay::steps_done`].
            #[inline]
            pub fn steps_done(&self) -> u32 {
                match self {
                    $(AnyReplay::$ty(r) => r.steps_done(),)*
                }
            }

            /// Runs `with` for `cost` with the variant that holds a replay of it: for a caller
            /// that builds the replay in a frame of its own, one per cost (the C API).
            #[inline(always)]
            pub fn for_cost<W: WithVariant<'a, T>>(cost: Cost, with: W) -> W::Output {
                match cost {
                    $(Cost::$ty => with.run::<crate::cost::$ty>(AnyReplay::$ty),)*
                }
            }
        }
    };
}

crate::for_each_cost!(any_replay);

/// What a caller does with the replay an [`AnyReplay`] holds ([`AnyReplay::with_mut`]): one
/// function generic over the cost.
pub trait WithAnyReplay<'a, T> {
    /// What it gives.
    type Output;
    /// Runs on `replay`, which runs the law of `C`.
    fn run<C: RunningCost>(self, replay: &mut Replay<'a, T, C>) -> Self::Output;
}

/// What a caller does with the variant of [`AnyReplay`] that holds a replay of a cost
/// ([`AnyReplay::for_cost`]).
pub trait WithVariant<'a, T> {
    /// What it gives.
    type Output;
    /// Runs for the cost `C`, whose replays `variant` holds.
    fn run<C: RunningCost>(self, variant: fn(Replay<'a, T, C>) -> AnyReplay<'a, T>)
    -> Self::Output;
}
