//! The versioned costate file (`costate.json`): a gait as JSON, for people and scripts.
//!
//! ```text
//! { "format": "purcell-costate", "version": 2,
//!   "model": {"links": [L0, L1, L2], "drag": k, "ratio": r},
//!   "h": 0.01, "steps": 10000, "alpha0": [a1, a2], "target": [x, y, theta],
//!   "mu": [m1, m2, m3], "xi0": [x1, x2],            // xi0 = ξ^{−1}
//!   "checkpoint_every": 100,
//!   "checkpoints": [{"k": 100, "alpha": [a1, a2], "g": [x, y, cos, sin], "xi": [x1, x2]}, ...] }
//! ```
//!
//! Between the tag (`format`, `version`) and `checkpoints` the fields are the core's gait
//! schema, [`GaitParams`], and each checkpoint a [`CheckpointRecord`]: the binary gait file
//! (`purcell-sim export`, read by `purcell_core::Gait::from_bytes`) holds the same numbers, and
//! both go through the same validation, `purcell_core::gait::check`.
//!
//! Checkpoint `k` holds `(α_k, g_k, ξ^{k−1})` of a plain `f64` replay from `(μ, ξ^{−1})`; a
//! replay restarts from it at step `k` (see `purcell_core::replay`: resetting `ξ` alone does
//! not keep an `f32` replay on the solution). `g` is stored as `(x, y, cos θ, sin θ)`, the
//! core's own representation, so it comes back bit for bit. Version 1 (checkpoints of `ξ`
//! alone) is refused.
//!
//! Numbers are written in shortest round-trip form, so reading gives the same bits back.
//! Reading is strict: unknown fields, missing fields, wrong lengths, a different `format`
//! or `version`, and whatever `purcell_core::gait::check` refuses (non-finite values, shapes
//! at the overlap limit, rotations off unit length, checkpoints anywhere but at every multiple
//! of `checkpoint_every` below `steps`) are typed errors. A file replayed in `f32` must also
//! fit `f32` ([`CostateFile::check_precision`]).

pub use purcell_core::gait::{CheckpointRecord, GaitParams, Model};
use serde::{Deserialize, Serialize};

/// The `format` tag.
pub const FORMAT: &str = "purcell-costate";
/// The only version this build reads and writes.
pub const VERSION: u64 = 2;

/// The whole file: a tagged gait. Dereferences to its [`GaitParams`] (`file.mu`, `file.h`, …).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CostateFile {
    /// Always [`FORMAT`].
    pub format: String,
    /// Always [`VERSION`].
    pub version: u64,
    /// Model, `h`, `N`, `ᾱ`, `ḡ`, `μ`, `ξ^{−1}`, checkpoint spacing.
    #[serde(flatten)]
    pub gait: GaitParams,
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
    /// `version` is not [`VERSION`].
    #[error("unsupported costate file version {0} (this build reads version 2)")]
    WrongVersion(u64),
    /// `version` is not a non-negative integer.
    #[error("invalid costate file: version must be a non-negative integer")]
    BadVersion,
    /// A value the core refuses (`purcell_core::gait::check`).
    #[error("invalid costate file: {0}")]
    Invalid(#[source] purcell_core::Error),
}

#[derive(Deserialize)]
struct Header {
    format: Option<serde_json::Value>,
    version: Option<serde_json::Value>,
}

impl CostateFile {
    /// Parses and validates.
    pub fn parse(text: &str) -> Result<Self, CostateFileError> {
        // Check the tag and version first, so a newer file says so instead of a field error.
        let header: Header = serde_json::from_str(text).map_err(CostateFileError::Malformed)?;
        match header.format {
            Some(serde_json::Value::String(s)) if s == FORMAT => {}
            Some(v) => return Err(CostateFileError::WrongFormat(v.to_string())),
            None => return Err(CostateFileError::WrongFormat("<missing>".into())),
        }
        match header.version.as_ref().and_then(|v| v.as_u64()) {
            Some(VERSION) => {}
            Some(v) => return Err(CostateFileError::WrongVersion(v)),
            None => return Err(CostateFileError::BadVersion),
        }
        let file: CostateFile = serde_json::from_str(text).map_err(CostateFileError::Malformed)?;
        purcell_core::gait::check(&file.gait, file.checkpoints.iter().copied())
            .map_err(CostateFileError::Invalid)?;
        Ok(file)
    }

    /// The file of `gait` and `checkpoints` (not validated: [`CostateFile::to_gait`] and
    /// [`CostateFile::parse`] do that).
    pub fn new(gait: GaitParams, checkpoints: Vec<CheckpointRecord>) -> Self {
        CostateFile {
            format: FORMAT.into(),
            version: VERSION,
            gait,
            checkpoints,
        }
    }

    /// The binary gait file of the same numbers (`purcell_core::gait::encode`).
    ///
    /// Errors: what `purcell_core::gait::check` refuses.
    pub fn to_gait(&self) -> Result<Vec<u8>, purcell_core::Error> {
        let mut bytes = vec![0; purcell_core::gait::encoded_len(self.checkpoints.len())];
        purcell_core::gait::encode(&self.gait, &self.checkpoints, &mut bytes)?;
        Ok(bytes)
    }

    /// `Ok` if the file is also valid when replayed in scalar `T` (named `precision` in
    /// messages): its problem ([`crate::problem::Problem::check_precision`]), and every
    /// costate and checkpoint number finite there.
    pub fn check_precision<T: purcell_core::Real>(
        &self,
        precision: &'static str,
    ) -> Result<(), crate::problem::InputError> {
        use crate::problem::check_fits;
        self.problem()?.check_precision::<T>(precision)?;
        check_fits::<T>("mu", &self.mu, false, precision)?;
        check_fits::<T>("xi0", &self.xi0, false, precision)?;
        for c in &self.checkpoints {
            let at = |what| format!("{what} of the checkpoint at k = {}", c.k);
            check_fits::<T>(&at("alpha"), &c.alpha, false, precision)?;
            check_fits::<T>(&at("g"), &c.g, false, precision)?;
            check_fits::<T>(&at("xi"), &c.xi, false, precision)?;
        }
        Ok(())
    }

    /// Serialises (pretty JSON, shortest round-trip numbers).
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default() + "\n"
    }

    /// The problem this file belongs to (validated like command-line input).
    pub fn problem(&self) -> Result<crate::problem::Problem, crate::problem::InputError> {
        crate::problem::Problem::new(&crate::problem::Spec {
            target: self.target,
            horizon: self.h * f64::from(self.steps),
            step: self.h,
            alpha0: self.alpha0,
            links: self.model.links,
            drag: self.model.drag,
            ratio: self.model.ratio,
            alpha_max: None,
        })
    }
}
