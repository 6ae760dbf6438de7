//! What every function returns: [`PurcellStatus`], one code for each of the core's errors
//! ([`purcell_core::Error`]) and for each misuse of the API, and its message.

use purcell_core::Error;
use purcell_core::gait::VERSION;

/// The result of a call: `PURCELL_STATUS_OK` (0), `PURCELL_STATUS_FINISHED` (1), or an error
/// (negative). The codes from -101 on are the core's errors, each as its reader or replay
/// returns it (`purcell_core::Error`); `purcell_status_message` gives their text.
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PurcellStatus {
    /// Success; for `purcell_flight_step`: a step ran, its sample is readable.
    Ok = 0,
    /// `purcell_flight_step`: every step has run (no step ran now); the digest, when kept, now
    /// includes the final state.
    Finished = 1,
    /// A pointer argument is NULL.
    Null = -1,
    /// The flight is not aligned to 8 bytes (declare it as a `PurcellFlight`).
    Misaligned = -2,
    /// The flight was never opened (a zeroed `PurcellFlight`, as a static is).
    NotOpen = -3,
    /// `purcell_flight_open`: an option bit this build does not know.
    BadOptions = -4,
    /// `purcell_flight_sample`: no step has run yet.
    NoSample = -5,
    /// The flight has steps left (the digest and the terminal error need all of them).
    NotFinished = -6,
    /// The flight was opened without `PURCELL_OPTION_DIGEST`.
    NoDigest = -7,
    /// A number of the gait or of a step was NaN or infinite.
    NonFinite = -101,
    /// A joint angle reached the link-overlap limit `|α_i| ≥ π`.
    ShapeLimit = -102,
    /// The gait's swimmer parameters are not finite and positive.
    InvalidParameters = -103,
    /// The gait's time step is not finite and positive, or it has no step.
    InvalidStep = -104,
    /// A singular matrix in a step (drag matrix or `I − h·B_k`).
    Singular = -105,
    /// Checkpoint steps not strictly increasing within the horizon.
    CheckpointOrder = -106,
    /// A fixed-capacity buffer is full.
    CapacityExceeded = -107,
    /// Checkpoints not at every multiple of the gait's spacing and at its arcs' exits.
    CheckpointSpacing = -108,
    /// A stored rotation `(cos θ, sin θ)` is not of unit length.
    NotRotation = -109,
    /// Not a gait file (bad magic).
    GaitMagic = -110,
    /// A gait file version this build does not read.
    GaitVersion = -111,
    /// The gait file's length differs from its header (truncated or padded).
    GaitLength = -112,
    /// The gait file's CRC-32 does not match (corrupted).
    GaitChecksum = -113,
    /// Malformed sections or tables, or the `f32` table is not the `f64` one rounded.
    GaitLayout = -114,
    /// A joint-limit arc with a bad joint, sign or steps.
    ArcInvalid = -115,
    /// Joint-limit arcs out of order or overlapping.
    ArcOrder = -116,
    /// A joint-limit arc's last step has no checkpoint.
    ArcCheckpoint = -117,
    /// At an arc's exit checkpoint the joint is not on its limit.
    ArcOffLimit = -118,
    /// The gait's joint limit `α_max` is out of range or missing.
    JointLimit = -119,
    /// An error of a newer core that this API does not name.
    CoreOther = -199,
}

/// The core's errors and their codes: the one table both directions read. `GaitVersion`
/// matches any version (by variant).
pub(crate) const CORE: [(Error, PurcellStatus); 19] = [
    (Error::NonFinite, PurcellStatus::NonFinite),
    (Error::ShapeLimit, PurcellStatus::ShapeLimit),
    (Error::InvalidParameters, PurcellStatus::InvalidParameters),
    (Error::InvalidStep, PurcellStatus::InvalidStep),
    (Error::Singular, PurcellStatus::Singular),
    (Error::CheckpointOrder, PurcellStatus::CheckpointOrder),
    (Error::CapacityExceeded, PurcellStatus::CapacityExceeded),
    (Error::CheckpointSpacing, PurcellStatus::CheckpointSpacing),
    (Error::NotRotation, PurcellStatus::NotRotation),
    (Error::GaitMagic, PurcellStatus::GaitMagic),
    (Error::GaitVersion(VERSION), PurcellStatus::GaitVersion),
    (Error::GaitLength, PurcellStatus::GaitLength),
    (Error::GaitChecksum, PurcellStatus::GaitChecksum),
    (Error::GaitLayout, PurcellStatus::GaitLayout),
    (Error::ArcInvalid, PurcellStatus::ArcInvalid),
    (Error::ArcOrder, PurcellStatus::ArcOrder),
    (Error::ArcCheckpoint, PurcellStatus::ArcCheckpoint),
    (Error::ArcOffLimit, PurcellStatus::ArcOffLimit),
    (Error::JointLimit, PurcellStatus::JointLimit),
];

impl From<Error> for PurcellStatus {
    fn from(e: Error) -> Self {
        let variant = core::mem::discriminant(&e);
        CORE.iter()
            .find(|(known, _)| core::mem::discriminant(known) == variant)
            .map_or(PurcellStatus::CoreOther, |&(_, code)| code)
    }
}

/// The API's own codes and their messages.
pub(crate) const OWN: [(PurcellStatus, &str); 10] = [
    (PurcellStatus::Ok, "ok"),
    (PurcellStatus::Finished, "finished: every step has run"),
    (PurcellStatus::Null, "NULL pointer argument"),
    (
        PurcellStatus::Misaligned,
        "flight not aligned to 8 bytes (declare it as a PurcellFlight)",
    ),
    (PurcellStatus::NotOpen, "flight not opened"),
    (PurcellStatus::BadOptions, "unknown option bits"),
    (PurcellStatus::NoSample, "no step has run yet"),
    (PurcellStatus::NotFinished, "the flight has steps left"),
    (
        PurcellStatus::NoDigest,
        "flight opened without PURCELL_OPTION_DIGEST",
    ),
    (PurcellStatus::CoreOther, "an error of a newer purcell-core"),
];

impl PurcellStatus {
    /// What the code means, in one line (the core's [`Error::message`] for its errors);
    /// `None` for a number that is no code.
    pub fn message(code: i32) -> Option<&'static str> {
        let core = CORE.iter().map(|(e, s)| (*s, e.message()));
        core.chain(OWN)
            .find(|&(s, _)| s as i32 == code)
            .map(|(_, text)| text)
    }
}
