//! The one error type of the core.

/// Why a core computation refused its input or could not produce a finite result.
///
/// Every fallible function returns this instead of panicking; nothing is partially written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Error {
    /// An input number was NaN or infinite, or a result overflowed to one.
    NonFinite,
    /// A joint angle reached the link-overlap limit: `|α_i| ≥ π` (or a stricter caller limit).
    ShapeLimit,
    /// Swimmer parameters not finite and positive (link lengths, drag coefficient, drag ratio).
    InvalidParameters,
    /// Time step not finite and positive.
    InvalidStep,
    /// A linear solve met a (numerically) singular matrix: the drag matrix `W_ξ` or the
    /// control-law matrix `I − h·B_k` (a costate so large that `h·|B_k|` is near 1).
    Singular,
    /// Costate checkpoints must have strictly increasing step indices within the horizon.
    CheckpointOrder,
    /// A fixed-capacity buffer is full.
    CapacityExceeded,
    /// A state's rotation `(cos θ, sin θ)` is not of unit length (see
    /// [`crate::kinematics::UNIT_ROTATION_TOLERANCE`]).
    NonUnitRotation,
}

impl core::fmt::Display for Error {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Error::NonFinite => "non-finite number in input or result",
            Error::ShapeLimit => "joint angle at or past the link-overlap limit |alpha_i| >= pi",
            Error::InvalidParameters => {
                "swimmer parameters must be finite and positive (lengths, drag k, ratio r)"
            }
            Error::InvalidStep => "time step h must be finite and positive",
            Error::Singular => "singular matrix (degenerate drag matrix or I - h*B)",
            Error::CheckpointOrder => {
                "checkpoint steps must be strictly increasing and within the horizon"
            }
            Error::CapacityExceeded => "fixed-capacity buffer is full",
            Error::NonUnitRotation => "rotation (cos theta, sin theta) is not of unit length",
        })
    }
}

impl core::error::Error for Error {}
