//! The versioned costate file (`costate.json`): a gait as JSON, for people and scripts.
//!
//! ```text
//! { "format": "purcell-costate", "version": 3,
//!   "model": {"links": [L0, L1, L2], "drag": k, "ratio": r},
//!   "h": 0.01, "steps": 10000, "alpha0": [a1, a2], "target": [x, y, theta],
//!   "mu": [m1, m2, m3], "xi0": [x1, x2],            // xi0 = ξ^{−1}
//!   "checkpoint_every": 100,
//!   "alpha_max": 1.5,                                 // null: no joint limit
//!   "alpha_end": [b1, b2],                            // version 4 (5: optional): the end shape
//!   "cost": "power",                                  // version 5 only: the running cost
//!   "arcs": [{"joint": 2, "sign": 1, "first": 1276, "last": 1418}, ...],
//!   "checkpoints": [{"k": 100, "alpha": [a1, a2], "g": [x, y, cos, sin], "xi": [x1, x2]}, ...] }
//! ```
//!
//! Between the tag (`format`, `version`) and `arcs` the fields are the core's gait schema,
//! [`GaitParams`], each arc a [`purcell_core::Arc`] (joint 1 or 2, sign ±1, the first and last
//! state on the limit, MODEL.md §9) and each checkpoint a [`CheckpointRecord`]: the binary gait
//! file (`purcell-sim export`, read by `purcell_core::Gait::from_bytes`) holds the same numbers,
//! and both go through the same validation, `purcell_core::gait::check`.
//!
//! Checkpoint `k` holds `(α_k, g_k, ξ̃^{k−1})` of the solution (`ξ̃`: the costate with state
//! `k`'s jump on the joint limit, MODEL.md §9); a replay restarts from it at step `k` (see
//! `purcell_core::replay`: resetting `ξ` alone does not keep an `f32` replay on the solution).
//! There is one at every multiple of `checkpoint_every` below `steps` and one at every arc's
//! `last`, where the replay needs it. `g` is stored as `(x, y, cos θ, sin θ)`, the core's own
//! representation, so it comes back bit for bit.
//!
//! Versions: 3 is written for a loop (`α_N = ᾱ`), 4 for a gait whose end shape differs from
//! its start: version 3 with `alpha_end` (the end shape `α_N`) after `alpha_max`; 2 (no
//! `alpha_max`, no `arcs`: a gait without a joint limit) is still read; 1 (checkpoints of `ξ`
//! alone) is refused. Versions 2 and 3 have no `alpha_end`: their end shape is `alpha0`.
//! Version 5 is a gait of a cost other than the effort (MODEL.md §11): version 3 with `cost`
//! (`"power"`) and `alpha_end` if it has an end shape of its own; files of the effort are
//! versions 3 and 4 as before, and every older version reads as the effort.
//!
//! Numbers are written in shortest round-trip form, so reading gives the same bits back.
//! Reading is strict: unknown fields, missing fields (`alpha_max` and `arcs` included in
//! version 3), wrong lengths, a different `format` or `version`, and whatever
//! `purcell_core::gait::check` refuses (non-finite values, shapes at the overlap limit,
//! rotations off unit length, arcs out of order or off the limit, checkpoints anywhere but at
//! every multiple of `checkpoint_every` below `steps` and at the arcs' exits) are typed errors.
//! A file replayed in `f32` must also fit `f32` ([`purcell_solver::problem::check_gait_precision`]).

pub use purcell_core::Arc;
pub use purcell_core::gait::{CheckpointRecord, GaitParams, Model};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The `format` tag.
pub const FORMAT: &str = "purcell-costate";
/// The version this build writes for a loop.
pub const VERSION: u64 = 3;
/// The version this build writes for a gait with an end shape of its own (`alpha_end`).
pub const VERSION_END_SHAPE: u64 = 4;
/// The version this build writes for a gait of a cost other than the effort (`cost`).
pub const VERSION_COST: u64 = 5;
/// The older version this build still reads: no joint limit, no arcs.
pub const VERSION_WITHOUT_ARCS: u64 = 2;
/// The fields version 3 added.
const ARC_FIELDS: [&str; 2] = ["alpha_max", "arcs"];
/// The field version 4 added (optional in version 5).
const END_FIELD: &str = "alpha_end";
/// The field version 5 added.
const COST_FIELD: &str = "cost";

/// The whole file: a tagged gait. Dereferences to its [`GaitParams`] (`file.mu`, `file.h`, …).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CostateFile {
    /// Always [`FORMAT`].
    pub format: String,
    /// [`VERSION`], or [`VERSION_END_SHAPE`] with an end shape (a version-2 file is read as
    /// the same gait in version 3).
    pub version: u64,
    /// Model, `h`, `N`, `ᾱ`, `ḡ`, `μ`, `ξ^{−1}`, checkpoint spacing, joint limit, end shape.
    #[serde(flatten)]
    pub gait: GaitParams,
    /// Joint-limit arcs, sorted by `(first, joint)`.
    pub arcs: Vec<Arc>,
    /// Checkpoints, strictly increasing in `k`, each `k < steps`.
    pub checkpoints: Vec<CheckpointRecord>,
}

impl core::ops::Deref for CostateFile {
    type Target = GaitParams;
    fn deref(&self) -> &GaitParams {
        &self.gait
    }
}

/// Why a costate file was refused.
#[derive(Debug, thiserror::Error)]
pub enum CostateFileError {
    /// Not valid JSON, truncated, or fields of the wrong shape.
    #[error("malformed costate file: {0}")]
    Malformed(#[source] serde_json::Error),
    /// `format` is not [`FORMAT`].
    #[error("not a costate file: format is {0:?}, expected \"purcell-costate\"")]
    WrongFormat(String),
    /// `version` is none of [`VERSION_WITHOUT_ARCS`], [`VERSION`], [`VERSION_END_SHAPE`],
    /// [`VERSION_COST`].
    #[error("unsupported costate file version {0} (this build reads versions 2, 3, 4 and 5)")]
    WrongVersion(u64),
    /// A field a version needs missing from its file, or one it does not have present.
    #[error("invalid costate file: version {version} {which} the field \"{field}\"")]
    VersionField {
        /// The file's version.
        version: u64,
        /// `"needs"` or `"does not have"`.
        which: &'static str,
        /// The field.
        field: &'static str,
    },
    /// A version-5 file of the effort (its gaits are versions 3 and 4).
    #[error(
        "invalid costate file: version 5 is a gait of a cost other than the effort (an effort \
         gait is version 3, or 4 with an end shape)"
    )]
    EffortCost,
    /// `version` is not a non-negative integer.
    #[error("invalid costate file: version must be a non-negative integer")]
    BadVersion,
    /// A value the core refuses (`purcell_core::gait::check`).
    #[error("invalid costate file: {0}")]
    Invalid(#[source] purcell_core::Error),
}

/// Why the costate file at `path` could not be read ([`CostateFile::read`]).
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// Not readable ([`crate::input::read`]).
    #[error("reading {}: {error}", path.display())]
    Unreadable {
        /// The file.
        path: PathBuf,
        /// Why.
        error: std::io::Error,
    },
    /// A binary gait file instead.
    #[error(
        "{}: a binary gait file (export's output), not a costate file (DIR/costate.json); \
         replay, field and export take it as --gait",
        path.display()
    )]
    GaitFile {
        /// The file.
        path: PathBuf,
    },
    /// Not UTF-8.
    #[error("{}: malformed costate file: {error}", path.display())]
    NotText {
        /// The file.
        path: PathBuf,
        /// Why.
        error: std::string::FromUtf8Error,
    },
    /// Refused by [`CostateFile::parse`].
    #[error("{}: {error}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// Why.
        error: CostateFileError,
    },
}

impl CostateFile {
    /// Reads the costate file at `path` (at most [`crate::input::MAX_INPUT_BYTES`]; a binary
    /// gait file is refused as such).
    pub fn read(path: &Path) -> Result<Self, ReadError> {
        let path_buf = || path.to_path_buf();
        let bytes = crate::input::read(path).map_err(|error| ReadError::Unreadable {
            path: path_buf(),
            error,
        })?;
        if bytes.starts_with(&purcell_core::gait::MAGIC) {
            return Err(ReadError::GaitFile { path: path_buf() });
        }
        let text = String::from_utf8(bytes).map_err(|error| ReadError::NotText {
            path: path_buf(),
            error,
        })?;
        Self::parse(&text).map_err(|error| ReadError::Invalid {
            path: path_buf(),
            error,
        })
    }

    /// Parses and validates.
    pub fn parse(text: &str) -> Result<Self, CostateFileError> {
        use serde_json::Value;
        let mut object: serde_json::Map<String, Value> =
            crate::input::json(text.as_bytes()).map_err(CostateFileError::Malformed)?;
        // Check the tag and version first, so a newer file says so instead of a field error.
        match object.get("format") {
            Some(Value::String(s)) if s == FORMAT => {}
            Some(v) => return Err(CostateFileError::WrongFormat(v.to_string())),
            None => return Err(CostateFileError::WrongFormat("<missing>".into())),
        }
        let version = object.get("version").and_then(Value::as_u64);
        let version = match version {
            Some(v @ (VERSION | VERSION_WITHOUT_ARCS | VERSION_END_SHAPE | VERSION_COST)) => v,
            Some(v) => return Err(CostateFileError::WrongVersion(v)),
            None => return Err(CostateFileError::BadVersion),
        };
        // (field, whether this version needs it, whether it may have it)
        let arcs = version >= VERSION;
        let end = version == VERSION_END_SHAPE;
        let fields = ARC_FIELDS.map(|f| (f, arcs, arcs)).into_iter().chain([
            (END_FIELD, end, end || version == VERSION_COST),
            (COST_FIELD, version == VERSION_COST, version == VERSION_COST),
        ]);
        for (field, needs, may) in fields {
            match (needs, may, object.contains_key(field)) {
                (true, _, false) => {
                    return Err(CostateFileError::VersionField {
                        version,
                        which: "needs",
                        field,
                    });
                }
                (_, false, true) => {
                    return Err(CostateFileError::VersionField {
                        version,
                        which: "does not have",
                        field,
                    });
                }
                _ => {}
            }
        }
        // A version-2 file is the same gait without a joint limit and without arcs.
        if version == VERSION_WITHOUT_ARCS {
            object.insert("version".into(), VERSION.into());
        }
        object.entry("alpha_max").or_insert(Value::Null);
        object.entry("arcs").or_insert(Value::Array(Vec::new()));
        let file: CostateFile =
            serde_json::from_value(Value::Object(object)).map_err(CostateFileError::Malformed)?;
        if version == VERSION_COST && file.cost == purcell_core::Cost::Effort {
            return Err(CostateFileError::EffortCost);
        }
        purcell_core::gait::check(
            &file.gait,
            file.checkpoints.iter().copied(),
            file.arcs.iter().copied(),
        )
        .map_err(CostateFileError::Invalid)?;
        Ok(file)
    }

    /// The file of `gait`, `arcs` and `checkpoints` (not validated: [`CostateFile::to_gait`]
    /// and [`CostateFile::parse`] do that).
    pub fn new(gait: GaitParams, arcs: Vec<Arc>, checkpoints: Vec<CheckpointRecord>) -> Self {
        CostateFile {
            format: FORMAT.into(),
            version: match (gait.cost, gait.alpha_end) {
                (purcell_core::Cost::Effort, Some(_)) => VERSION_END_SHAPE,
                (purcell_core::Cost::Effort, None) => VERSION,
                _ => VERSION_COST,
            },
            gait,
            arcs,
            checkpoints,
        }
    }

    /// The binary gait file of the same numbers (`purcell_core::gait::encode`).
    ///
    /// Errors: what `purcell_core::gait::check` refuses.
    pub fn to_gait(&self) -> Result<Vec<u8>, purcell_core::Error> {
        let (n, arcs) = (self.checkpoints.len(), self.arcs.len());
        let len = purcell_core::gait::encoded_len_of(&self.gait, n, arcs, 0);
        let mut bytes = vec![0; len];
        purcell_core::gait::encode(&self.gait, &self.checkpoints, &self.arcs, &mut bytes)?;
        Ok(bytes)
    }

    /// Serialises (pretty JSON, shortest round-trip numbers).
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default() + "\n"
    }

    /// The problem this file belongs to ([`purcell_solver::problem::Problem::of_gait`]).
    pub fn problem(
        &self,
    ) -> Result<purcell_solver::problem::Problem, purcell_solver::problem::InputError> {
        purcell_solver::problem::Problem::of_gait(&self.gait)
    }
}
