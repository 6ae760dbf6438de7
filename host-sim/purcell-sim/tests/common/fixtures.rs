//! The costate files the command-line tests start from (and edit), and the committed test
//! data.

use std::path::PathBuf;

/// A version-2 costate file of 200 steps (no joint limit) with one checkpoint, at `k = 100`;
/// it replays (exit 0) in every precision.
pub const COSTATE_V2: &str = r#"{"format":"purcell-costate","version":2,
 "model":{"links":[1,1,1],"drag":1,"ratio":2},"h":0.01,"steps":200,"alpha0":[0,0],
 "target":[0.1,0.1,0],"mu":[0.1,0.2,0.0],"xi0":[0.01,-0.02],"checkpoint_every":100,
 "checkpoints":[{"k":100,"alpha":[0.01,-0.02],"g":[0.001,0.0,1,0],"xi":[0.01,-0.02]}]}"#;

/// [`COSTATE_V2`] in version 3 with a joint limit and one arc of joint 1 ([`ARC`]) ending at
/// its checkpoint.
pub const COSTATE_V3: &str = r#"{"format":"purcell-costate","version":3,
 "model":{"links":[1,1,1],"drag":1,"ratio":2},"h":0.01,"steps":200,"alpha0":[0,0],
 "target":[0.1,0.1,0],"mu":[0.1,0.2,0.0],"xi0":[0.01,-0.02],"checkpoint_every":100,
 "alpha_max":0.5,"arcs":[{"joint":1,"sign":1,"first":90,"last":100}],
 "checkpoints":[{"k":100,"alpha":[0.5,-0.02],"g":[0.001,0.0,1,0],"xi":[0.01,-0.02]}]}"#;

/// The `arcs` field of [`COSTATE_V3`], with its comma.
pub const ARC: &str = r#""arcs":[{"joint":1,"sign":1,"first":90,"last":100}],"#;

/// `name` in this crate's `tests/data`.
pub fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// `name` in the core's `tests/data` (the committed gait files).
pub fn core_data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../core/tests/data")
        .join(name)
}
