//! The versioned costate file (`costate.json`) shared with the firmware.
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
//! Checkpoint `k` holds `(α_k, g_k, ξ^{k−1})` of a plain `f64` replay from `(μ, ξ^{−1})`; a
//! replay restarts from it at step `k` (see `purcell_core::replay`: resetting `ξ` alone does
//! not keep an `f32` replay on the solution). `g` is stored as `(x, y, cos θ, sin θ)`, the
//! core's own representation, so it comes back bit for bit. Version 1 (checkpoints of `ξ`
//! alone) is refused.
//!
//! ```text
//! ```
//!
//! Numbers are written in shortest round-trip form, so reading gives the same bits back.
//! Reading is strict: unknown fields, missing fields, wrong lengths, a different `format`
//! or `version`, non-finite values, and checkpoints anywhere else than at every multiple of
//! `checkpoint_every` in `]0, steps[` are typed errors. A file replayed in `f32` must also
//! fit `f32` ([`CostateFile::check_precision`]).

use serde::{Deserialize, Serialize};

/// The `format` tag.
pub const FORMAT: &str = "purcell-costate";
/// The only version this build reads and writes.
pub const VERSION: u64 = 2;

/// Model parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Model {
    /// `(L0, L1, L2)`, metres.
    pub links: [f64; 3],
    /// Drag coefficient `k`.
    pub drag: f64,
    /// Drag ratio `r`.
    pub ratio: f64,
}

/// One checkpoint `(k, α_k, g_k, ξ^{k−1})`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CheckpointEntry {
    /// Step index.
    pub k: u32,
    /// `α_k`, radians.
    pub alpha: [f64; 2],
    /// `g_k` as `(x, y, cos θ, sin θ)`.
    pub g: [f64; 4],
    /// `ξ^{k−1}`.
    pub xi: [f64; 2],
}

/// The whole file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CostateFile {
    /// Always [`FORMAT`].
    pub format: String,
    /// Always [`VERSION`].
    pub version: u64,
    /// Model parameters.
    pub model: Model,
    /// Step `h`, seconds.
    pub h: f64,
    /// Steps `N`.
    pub steps: u32,
    /// `ᾱ`, radians.
    pub alpha0: [f64; 2],
    /// `ḡ = (x, y, θ)`.
    pub target: [f64; 3],
    /// `μ`.
    pub mu: [f64; 3],
    /// `ξ^{−1}`.
    pub xi0: [f64; 2],
    /// Checkpoint spacing in steps.
    pub checkpoint_every: u32,
    /// Checkpoints at `k = M, 2M, …` below `steps` (`M` = `checkpoint_every`), all of them.
    pub checkpoints: Vec<CheckpointEntry>,
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
    /// A value is out of range.
    #[error("invalid costate file: {0}")]
    Invalid(String),
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
            None => {
                return Err(CostateFileError::Invalid(
                    "version must be a non-negative integer".into(),
                ));
            }
        }
        let file: CostateFile = serde_json::from_str(text).map_err(CostateFileError::Malformed)?;
        file.validate()?;
        Ok(file)
    }

    fn validate(&self) -> Result<(), CostateFileError> {
        let bad = |m: &str| Err(CostateFileError::Invalid(m.into()));
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if !finite(&self.model.links)
            || !finite(&[self.model.drag, self.model.ratio, self.h])
            || !finite(&self.alpha0)
            || !finite(&self.target)
            || !finite(&self.mu)
            || !finite(&self.xi0)
        {
            return bad("non-finite number");
        }
        if self.steps == 0 {
            return bad("steps must be positive");
        }
        // Checkpoints sit at k = M, 2M, … below N, every one of them (none if M = 0): a
        // checkpoint at k = 0 would silently replace the start (α0, identity, ξ^{−1}).
        let every = u64::from(self.checkpoint_every);
        let expected = (u64::from(self.steps) - 1).checked_div(every).unwrap_or(0);
        if self.checkpoints.len() as u64 != expected {
            return Err(CostateFileError::Invalid(format!(
                "checkpoint_every = {every} and steps = {} call for {expected} checkpoints \
                 (k = M, 2M, ... below steps), the file has {}",
                self.steps,
                self.checkpoints.len()
            )));
        }
        for (i, c) in (1u64..).zip(&self.checkpoints) {
            if u64::from(c.k) != i * every {
                return Err(CostateFileError::Invalid(format!(
                    "checkpoint {i} is at k = {}, not at k = {i} * checkpoint_every = {}",
                    c.k,
                    i * every
                )));
            }
            if !(finite(&c.xi) && finite(&c.alpha) && finite(&c.g)) {
                return bad("non-finite checkpoint");
            }
            let shape = nalgebra::Vector2::new(c.alpha[0], c.alpha[1]);
            if purcell_core::swimmer::check_shape(&shape).is_err() {
                return bad("checkpoint shape at or past the link-overlap limit |alpha_i| >= pi");
            }
            let norm = c.g[2] * c.g[2] + c.g[3] * c.g[3];
            if (norm - 1.0).abs() > 1e-9 {
                return bad("checkpoint rotation (cos, sin) is not of unit length");
            }
        }
        Ok(())
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
            alpha_max: core::f64::consts::PI,
        })
    }
}
