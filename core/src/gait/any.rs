//! A gait's replay of whichever cost the gait has, held at run time ([`AnyReplay`]): for a
//! caller that keeps a replay between calls and cannot be generic over the cost (the C API,
//! a control loop's pilot).

use crate::cost::{Effort, Power};
use crate::{Error, Real, Replay, Sample, State};

/// A replay running the law of its gait's cost ([`crate::Gait::replay_any`]): each cost's
/// step is its own compiled code, reached by one match on the variant per call.
#[derive(Clone, Debug)]
pub enum AnyReplay<'a, T> {
    /// A gait of the joints' effort.
    Effort(Replay<'a, T, Effort>),
    /// A gait of the power the fluid dissipates.
    Power(Replay<'a, T, Power>),
}

impl<T: Real> AnyReplay<'_, T> {
    /// [`Replay::step`]. A loop that must cost the effort's step what it did before the
    /// power existed matches on the variant and runs each cost's code around its step (the C
    /// API, the control loop's pilot): a match on this one's result costs about 10
    /// instructions per step on the M4F.
    #[inline]
    pub fn step(&mut self) -> Result<Option<&Sample<T>>, Error> {
        match self {
            AnyReplay::Effort(r) => r.step(),
            AnyReplay::Power(r) => r.step(),
        }
    }

    /// [`Replay::state`].
    #[inline]
    pub fn state(&self) -> &State<T> {
        match self {
            AnyReplay::Effort(r) => r.state(),
            AnyReplay::Power(r) => r.state(),
        }
    }

    /// [`Replay::last_sample`].
    #[inline]
    pub fn last_sample(&self) -> Option<&Sample<T>> {
        match self {
            AnyReplay::Effort(r) => r.last_sample(),
            AnyReplay::Power(r) => r.last_sample(),
        }
    }

    /// [`Replay::steps_done`].
    #[inline]
    pub fn steps_done(&self) -> u32 {
        match self {
            AnyReplay::Effort(r) => r.steps_done(),
            AnyReplay::Power(r) => r.steps_done(),
        }
    }
}
