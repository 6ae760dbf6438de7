//! The one error type of the core.

/// Why a core computation refused its input or could not produce a finite result.
///
/// Every fallible function returns this instead of panicking; nothing is partially written.
/// New variants may be added in minor versions (hence `#[non_exhaustive]`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Error {
    /// An input number was NaN or infinite, or a result overflowed to one.
    NonFinite,
    /// A joint angle reached the link-overlap limit: `|α_i| ≥ π` (or a stricter caller limit).
    ShapeLimit,
    /// Swimmer parameters not finite and positive (link lengths, drag coefficient, drag ratio).
    InvalidParameters,
    /// Time step `h` not finite and positive, or a horizon of zero steps.
    InvalidStep,
    /// A linear solve met a (numerically) singular matrix: the drag matrix `W_ξ` or the
    /// control-law matrix `I − h·B_k` (a costate so large that `h·|B_k|` is near 1).
    Singular,
    /// Costate checkpoints must have strictly increasing step indices within the horizon.
    CheckpointOrder,
    /// A fixed-capacity buffer is full.
    CapacityExceeded,
    /// A gait's checkpoints are not exactly at every multiple of its spacing below its horizon
    /// and at its arcs' exits ([`crate::gait::check`]).
    CheckpointSpacing,
    /// A rotation `(cos θ, sin θ)` is not of unit length: to `1e-9` in a stored gait
    /// ([`crate::gait`]), to [`crate::kinematics::UNIT_ROTATION_TOLERANCE`] where a state
    /// enters the core ([`crate::State::check`]).
    NotRotation,
    /// Not a gait file: the bytes do not start with the gait magic ([`crate::gait`]).
    GaitMagic,
    /// A gait file of a version this build does not read (the version found).
    GaitVersion(u16),
    /// A gait file shorter or longer than its header says (truncated or padded).
    GaitLength,
    /// A gait file whose CRC-32 does not match its contents (corrupted).
    GaitChecksum,
    /// A gait file whose sections are missing, unknown, out of bounds, of the wrong record
    /// size, or whose `f32` checkpoint table is not its `f64` table rounded.
    GaitLayout,
    /// A joint-limit arc with a joint other than 1 or 2, a sign other than ±1, or steps outside
    /// `1 ≤ first ≤ last < N` ([`crate::arc::check`]).
    ArcInvalid,
    /// Joint-limit arcs not sorted by `(first, joint)`, or two arcs of one joint sharing a
    /// state ([`crate::arc::check`]).
    ArcOrder,
    /// A joint-limit arc's last state has no checkpoint (a replay restores one there).
    ArcCheckpoint,
    /// At the checkpoint of an arc's exit, the joint is not on its limit `sign·α_max`
    /// ([`crate::gait::check`]).
    ArcOffLimit,
    /// A gait's joint limit `α_max` is not in `]max |ᾱ_i|, π[`, is missing although the gait
    /// has arcs, or a checkpoint lies past it ([`crate::gait::check`]).
    JointLimit,
}

impl Error {
    /// What went wrong, in one line (the [`Display`](core::fmt::Display) text without the
    /// numbers some variants carry): for logging on targets without `core::fmt`.
    pub const fn message(&self) -> &'static str {
        match self {
            Error::NonFinite => "non-finite number in input or result",
            Error::ShapeLimit => "joint angle at or past the link-overlap limit |alpha_i| >= pi",
            Error::InvalidParameters => {
                "swimmer parameters must be finite and positive (lengths, drag k, ratio r)"
            }
            Error::InvalidStep => {
                "time step h must be finite and positive, and the horizon at least one step"
            }
            Error::Singular => "singular matrix (degenerate drag matrix or I - h*B)",
            Error::CheckpointOrder => {
                "checkpoint steps must be strictly increasing and within the horizon"
            }
            Error::CapacityExceeded => "fixed-capacity buffer is full",
            Error::CheckpointSpacing => {
                "gait checkpoints must sit at every multiple of checkpoint_every below the horizon and at every arc's last step, nowhere else"
            }
            Error::NotRotation => "rotation (cos theta, sin theta) is not of unit length",
            Error::GaitMagic => "not a gait file (bad magic)",
            Error::GaitVersion(_) => "unsupported gait file version",
            Error::GaitLength => "gait file length differs from its header (truncated?)",
            Error::GaitChecksum => "gait file checksum (CRC-32) mismatch: the file is corrupted",
            Error::GaitLayout => "malformed gait file (sections or tables)",
            Error::ArcInvalid => {
                "joint-limit arc must have joint 1 or 2, sign +1 or -1 and 1 <= first <= last < steps"
            }
            Error::ArcOrder => {
                "joint-limit arcs must be sorted by (first, joint), and arcs of one joint must not overlap"
            }
            Error::ArcCheckpoint => "a joint-limit arc's last step has no checkpoint",
            Error::ArcOffLimit => {
                "at an arc's exit checkpoint the joint is not on its limit sign*alpha_max"
            }
            Error::JointLimit => {
                "joint limit alpha_max must be in ]max|alpha0_i|, pi[, present with arcs, and no checkpoint may lie past it"
            }
        }
    }
}

impl core::fmt::Display for Error {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::GaitVersion(v) => write!(
                f,
                "unsupported gait file version {v} (this build reads versions 1 to {})",
                crate::gait::VERSION
            ),
            e => f.write_str(e.message()),
        }
    }
}

impl core::error::Error for Error {}

/// Logs the [`Error::message`] (and the version of [`Error::GaitVersion`]).
#[cfg(feature = "defmt")]
impl defmt::Format for Error {
    fn format(&self, f: defmt::Formatter<'_>) {
        match self {
            Error::GaitVersion(v) => defmt::write!(
                f,
                "unsupported gait file version {=u16} (this build reads versions 1 to {=u16})",
                *v,
                crate::gait::VERSION
            ),
            e => defmt::write!(f, "{=str}", e.message()),
        }
    }
}
