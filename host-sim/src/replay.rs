//! Replaying a stored costate through the core, in `f64` and `f32`, and measuring how far
//! the end lands from `(ᾱ, ḡ)`.

use crate::costate_file::CostateFile;
use nalgebra::{Vector2, Vector3};
use purcell_core::{Checkpoint, Costate, Kinematics, Real, Replay, State};
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
}

/// What a replay of a costate file in scalar `T` starts from.
pub struct Setup<T> {
    /// The discrete system.
    pub kinematics: Kinematics<T>,
    /// `(ᾱ, e)`.
    pub start: State<T>,
    /// `(μ, ξ^{−1})`.
    pub costate: Costate<T>,
    /// The file's checkpoints, or none.
    pub checkpoints: Vec<Checkpoint<T>>,
    /// `N`.
    pub steps: u32,
}

impl<T: Real> Setup<T> {
    /// The file's numbers rounded to `T`, with or without its checkpoints.
    pub fn new(file: &CostateFile, checkpoints: bool) -> Result<Self, String> {
        let problem = file.problem().map_err(|e| e.to_string())?;
        let kinematics = problem.kinematics::<T>().map_err(|e| e.to_string())?;
        let c = T::from_f64;
        let costate = Costate {
            mu: Vector3::new(c(file.mu[0]), c(file.mu[1]), c(file.mu[2])),
            xi: Vector2::new(c(file.xi0[0]), c(file.xi0[1])),
        };
        let checkpoints = if checkpoints {
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
        Ok(Setup {
            kinematics,
            start,
            costate,
            checkpoints,
            steps: file.steps,
        })
    }

    /// The replay.
    pub fn replay(&self) -> Result<Replay<'_, T>, String> {
        Replay::new(
            self.kinematics,
            self.start,
            self.costate,
            self.steps,
            &self.checkpoints,
        )
        .map_err(|e| e.to_string())
    }
}

/// How far `state` is from `reference`: `(max |α − α_ref|, max |log(g_ref⁻¹ g)|)` (radians;
/// metres / radians). The one error metric of replays.
pub fn state_error<T: Real>(state: &State<T>, reference: &State<f64>) -> (f64, f64) {
    let a = Vector2::new(
        state.alpha.x.to_f64() - reference.alpha.x,
        state.alpha.y.to_f64() - reference.alpha.y,
    );
    let g = purcell_core::Se2::from_rotation(
        state.g.x().to_f64(),
        state.g.y().to_f64(),
        state.g.cos().to_f64(),
        state.g.sin().to_f64(),
    );
    (a.amax(), reference.g.between(&g).log().amax())
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
    };
    let run = || -> Result<State<T>, String> {
        let setup = Setup::<T>::new(file, checkpoints)?;
        setup.replay()?.finish().map_err(|e| e.to_string())
    };
    match run() {
        Ok(end) => {
            let [x, y, th] = file.target;
            let target = State {
                alpha: Vector2::new(file.alpha0[0], file.alpha0[1]),
                g: purcell_core::Se2::new(x, y, th),
            };
            let (alpha_error, g_error) = state_error(&end, &target);
            let (ex, ey) = (end.g.x().to_f64() - x, end.g.y().to_f64() - y);
            out.alpha_error = Some(alpha_error);
            out.g_error = Some(g_error);
            out.position_error = Some((ex * ex + ey * ey).sqrt());
        }
        Err(e) => out.failure = Some(e),
    }
    out
}

/// The states `(α_k, g_k)` of the `f64` replay of `file` (with its checkpoints) at about
/// `points` evenly spaced steps, always with `k = 0` and `k = N`.
pub fn gait_states(file: &CostateFile, points: usize) -> Result<Vec<State<f64>>, String> {
    let setup = Setup::<f64>::new(file, true)?;
    let mut replay = setup.replay()?;
    let stride = (file.steps as usize / points.max(1)).max(1);
    let mut states = Vec::new();
    while let Some(sample) = replay.step().map_err(|e| e.to_string())? {
        if (sample.k as usize).is_multiple_of(stride) {
            states.push(sample.state);
        }
    }
    states.push(*replay.state());
    Ok(states)
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
