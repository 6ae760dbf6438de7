//! A gait's replay of whichever cost the gait has, held at run time ([`AnyReplay`]): for a
//! caller that keeps a replay between calls and cannot be generic over the cost (the C API,
//! a control loop's pilot).

use crate::cost::{Effort, Power};
use crate::gait::read::Stored;
use crate::{Error, Replay, Sample, State};

/// A replay running the law of its gait's cost ([`crate::Gait::replay_any`]): each cost's
/// step is its own compiled code, reached by one match on the variant per call.
#[derive(Clone, Debug)]
pub enum AnyReplay<'a, T> {
    /// A gait of the joints' effort.
    Effort(Replay<'a, T, Effort>),
    /// A gait of the power the fluid dissipates.
    Power(Replay<'a, T, Power>),
}

impl<T: Stored> AnyReplay<'_, T> {
    /// [`Replay::step`]. The effort's step is inlined where this is, the power's is a call:
    /// a caller that inlines both pays for the larger frame on every step (10 instructions
    /// per step of the C API's on the M4F, 692.3 → 702.3).
    #[inline(always)]
    pub fn step(&mut self) -> Result<Option<&Sample<T>>, Error> {
        match self {
            AnyReplay::Effort(r) => r.step(),
            AnyReplay::Power(r) => power_step(r),
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

/// [`Replay::step`] of a power gait, not inlined ([`AnyReplay::step`]).
#[inline(never)]
fn power_step<'r, T: Stored>(
    replay: &'r mut Replay<'_, T, Power>,
) -> Result<Option<&'r Sample<T>>, Error> {
    replay.step()
}
