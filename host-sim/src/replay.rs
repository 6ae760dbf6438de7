//! Replaying a stored costate through the core, in `f64` and `f32`, and measuring how far
//! the end lands from `(ᾱ, ḡ)`.

use crate::costate_file::CostateFile;
use nalgebra::{Vector2, Vector3};
use purcell_core::{Checkpoint, Costate, Real, Replay, State};
use serde::Serialize;

/// Terminal error of one replay.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReplayError {
    /// `"f64"` or `"f32"`.
    pub precision: &'static str,
    /// Whether the costate checkpoints were applied.
    pub checkpoints: bool,
    /// `max |α_N − ᾱ|`, radians (`null` if the replay failed).
    pub alpha_error: Option<f64>,
    /// `max |log(ḡ⁻¹ g_N)|` components (metres / radians).
    pub g_error: Option<f64>,
    /// `|p_N − p̄|`, metres.
    pub position_error: Option<f64>,
    /// Why the replay stopped early, if it did.
    pub failure: Option<String>,
    /// The step `k` it failed at (`null` if it did not start, or did not fail).
    pub failed_at_step: Option<u32>,
}

/// Replays `file` in scalar `T`, with or without its checkpoints.
pub fn replay<T: Real>(
    file: &CostateFile,
    precision: &'static str,
    checkpoints: bool,
) -> ReplayError {
    let mut out = ReplayError {
        precision,
        checkpoints,
        alpha_error: None,
        g_error: None,
        position_error: None,
        failure: None,
        failed_at_step: None,
    };
    // Err: the step it failed at (if it started) and why.
    let run = || -> Result<State<T>, (Option<u32>, String)> {
        let before = |e: &dyn std::fmt::Display| (None, e.to_string());
        let problem = file.problem().map_err(|e| before(&e))?;
        let kin = problem.kinematics::<T>().map_err(|e| before(&e))?;
        let c = T::from_f64;
        let cs = Costate {
            mu: Vector3::new(c(file.mu[0]), c(file.mu[1]), c(file.mu[2])),
            xi: Vector2::new(c(file.xi0[0]), c(file.xi0[1])),
        };
        let cps: Vec<Checkpoint<T>> = if checkpoints {
            file.checkpoints
                .iter()
                .map(|e| {
                    let [x, y, cos, sin] = e.g.map(c);
                    Checkpoint {
                        k: e.k,
                        state: State {
                            alpha: Vector2::new(c(e.alpha[0]), c(e.alpha[1])),
                            g: purcell_core::Se2::from_rotation(x, y, cos, sin),
                        },
                        xi: Vector2::new(c(e.xi[0]), c(e.xi[1])),
                    }
                })
                .collect()
        } else {
            Vec::new()
        };
        let start = State::at_origin(Vector2::new(c(file.alpha0[0]), c(file.alpha0[1])));
        let mut replay = Replay::new(kin, start, cs, file.steps, &cps).map_err(|e| before(&e))?;
        loop {
            match replay.step() {
                Ok(Some(_)) => {}
                Ok(None) => return Ok(*replay.state()),
                Err(e) => return Err((Some(replay.steps_done()), e.to_string())),
            }
        }
    };
    match run() {
        Ok(end) => {
            let a = Vector2::new(
                end.alpha.x.to_f64() - file.alpha0[0],
                end.alpha.y.to_f64() - file.alpha0[1],
            );
            let g = purcell_core::Se2::new(
                end.g.x().to_f64(),
                end.g.y().to_f64(),
                end.g.theta().to_f64(),
            );
            let [x, y, th] = file.target;
            let e = purcell_core::Se2::new(x, y, th).between(&g).log();
            out.alpha_error = Some(a.amax());
            out.g_error = Some(e.amax());
            out.position_error = Some(((g.x() - x).powi(2) + (g.y() - y).powi(2)).sqrt());
        }
        Err((step, why)) => {
            out.failed_at_step = step;
            out.failure = Some(why);
        }
    }
    out
}

/// The three replays the `replay` command reports: f64 with checkpoints, f32 with, f32 without.
pub fn standard_replays(file: &CostateFile) -> Vec<ReplayError> {
    vec![
        replay::<f64>(file, "f64", true),
        replay::<f64>(file, "f64", false),
        replay::<f32>(file, "f32", true),
        replay::<f32>(file, "f32", false),
    ]
}
