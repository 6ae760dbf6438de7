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
    /// A gait's checkpoints are not at every multiple of its spacing below its horizon
    /// ([`crate::gait::check`]).
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
                "gait checkpoints must sit at every multiple of checkpoint_every below the horizon"
            }
            Error::NotRotation => "rotation (cos theta, sin theta) is not of unit length",
            Error::GaitMagic => "not a gait file (bad magic)",
            Error::GaitVersion(_) => "unsupported gait file version",
            Error::GaitLength => "gait file length differs from its header (truncated?)",
            Error::GaitChecksum => "gait file checksum (CRC-32) mismatch: the file is corrupted",
            Error::GaitLayout => "malformed gait file (sections or tables)",
        }
    }
}

impl core::fmt::Display for Error {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::GaitVersion(v) => write!(
                f,
                "unsupported gait file version {v} (this build reads version {})",
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
                "unsupported gait file version {=u16} (this build reads version {=u16})",
                *v,
                crate::gait::VERSION
            ),
            e => defmt::write!(f, "{=str}", e.message()),
        }
    }
}
