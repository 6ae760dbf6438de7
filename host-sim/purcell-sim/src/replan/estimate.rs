//! The re-plan's estimate of the drag ratio from the flight so far, and its test whether a
//! drag-ratio error explains what was measured (docs/ROBUSTNESS.md, "Re-planning").
//!
//! With the joint angles `α_j`, the controls flown `u_j` and the known start pose
//! `g_0`, the model at drag ratio `r(1 + ε)` predicts the pose
//! `g_{j+1}(ε) = g_j(ε)·exp(−h·A_{r(1+ε)}(α_j)·u_j)`; the fit minimises
//! `S(ε) = Σ_{j=1..k} |log(ĝ_j⁻¹ g_j(ε))|²` over `ε` by Gauss–Newton (the derivative by a
//! forward difference). The prediction runs open loop over the whole history, so a pose's
//! noise enters only its own residual.
//!
//! A link-length error drifts in directions a drag-ratio error does not: the fit leaves a
//! residual. [`Fit::verdict`] accepts the estimate when the residual's root mean square is
//! at most [`UNEXPLAINED`] of the drift's (that at `ε = 0`) plus twice the pose noise's
//! standard deviation `σ`; otherwise the data are not a drag-ratio error, and the re-plan keeps
//! the flight on its current plan (the open loop before the first re-plan). A drift within
//! `2σ` says nothing either way. The estimate's standard error is `σ/|∂r/∂ε|` (Gauss–Newton's,
//! `r` the residual vector).

use nalgebra::Vector2;
use purcell_core::{Error, Kinematics, Se2, State, Swimmer};

/// The share of the drift a drag-ratio fit may leave unexplained.
pub const UNEXPLAINED: f64 = 0.1;

/// Gauss–Newton iterations at most; the fit stops earlier once `|Δε| <` [`STEP_TOLERANCE`].
const ITERATIONS: usize = 8;

/// See [`ITERATIONS`].
const STEP_TOLERANCE: f64 = 1e-10;

/// The fit looks for `ε` within `±RANGE` (the drag ratio stays positive).
pub const RANGE: f64 = 0.5;

/// The forward difference's step in `ε`.
const DIFFERENCE: f64 = 1e-6;

/// A fit of the drag ratio's relative error to the flight so far.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    /// `ε̂`: the plant's drag ratio is `r(1 + ε̂)`.
    pub ratio_error: f64,
    /// Root mean square of the residual at `ε̂` (per pose component, m and rad).
    pub residual: f64,
    /// Root mean square of the residual at `ε = 0`: the drift against the model.
    pub drift: f64,
    /// The standard error of `ε̂` under pose noise of standard deviation 1 (`1/|∂r/∂ε|`):
    /// times the noise's, the estimate's.
    pub spread: f64,
    /// The pose the model at `ε̂` predicts at the last step: the flight's pose, estimated
    /// from every measurement so far (a single one's noise averaged out).
    pub pose: Se2<f64>,
}

/// What a fit says of the flight measured with pose noise of standard deviation `sigma`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Verdict {
    /// The drift is within the noise (`drift ≤ 2σ`, or below [`FLOOR`]): nothing to estimate.
    Agrees,
    /// A drag-ratio error explains the drift: `ε̂` and its standard error `σ·spread`.
    Ratio {
        /// `ε̂`.
        estimate: f64,
        /// Its standard error.
        error: f64,
    },
    /// A drag-ratio error leaves more than [`UNEXPLAINED`] of the drift (plus `2σ`): the
    /// share it leaves.
    Unexplained(f64),
}

/// Drift (m, rad, root mean square) below which a noise-free flight agrees with its model:
/// the replay's rounding.
pub const FLOOR: f64 = 1e-9;

impl Fit {
    /// The verdict on data measured with pose noise `sigma` (see the [module docs](self)).
    pub fn verdict(&self, sigma: f64) -> Verdict {
        if self.drift <= 2.0 * sigma + FLOOR {
            Verdict::Agrees
        } else if self.residual <= UNEXPLAINED * self.drift + 2.0 * sigma {
            Verdict::Ratio {
                estimate: self.ratio_error,
                error: sigma * self.spread,
            }
        } else {
            Verdict::Unexplained(self.residual / self.drift)
        }
    }
}

/// The model's poses predicted at `r(1 + eps)` from `start` along the joint angles of
/// `measured` (`k + 1` states) under `controls` (`k`), minus the measured poses: the
/// residuals `log(ĝ_j⁻¹ g_j(ε))`, `j = 1..=k`, flattened, and the last pose predicted.
fn residuals(
    model: &Kinematics<f64>,
    eps: f64,
    start: &Se2<f64>,
    measured: &[State<f64>],
    controls: &[Vector2<f64>],
) -> Result<(Vec<f64>, Se2<f64>), Error> {
    let sw = model.swimmer();
    let swimmer = Swimmer::new(sw.lengths(), sw.drag(), sw.ratio() * (1.0 + eps))?;
    let kin = Kinematics::new(swimmer, model.h())?;
    let mut g = *start;
    let mut r = Vec::with_capacity(3 * controls.len());
    for (m, u) in measured.windows(2).zip(controls) {
        let state = State {
            alpha: m[0].alpha,
            g,
        };
        g = kin.step(&state, u)?.g;
        r.extend_from_slice(m[1].g.between(&g).log().as_slice());
    }
    Ok((r, g))
}

/// Root mean square of `r` (0 for none).
fn rms(r: &[f64]) -> f64 {
    if r.is_empty() {
        0.0
    } else {
        (r.iter().map(|v| v * v).sum::<f64>() / r.len() as f64).sqrt()
    }
}

/// The fit of `ε` to the states `measured` (`k + 1`, the first at `start`'s step: the joint
/// angles as flown, the poses as measured) and the controls flown between them, `model` the
/// gait's kinematics (module docs).
///
/// Errors: the kinematics' (a prediction leaving the admissible shapes, or not finite).
pub fn fit(
    model: &Kinematics<f64>,
    start: &Se2<f64>,
    measured: &[State<f64>],
    controls: &[Vector2<f64>],
) -> Result<Fit, Error> {
    let res = |eps| residuals(model, eps, start, measured, controls);
    let (mut r, mut pose) = res(0.0)?;
    let drift = rms(&r);
    let (mut eps, mut spread) = (0.0, f64::INFINITY);
    for _ in 0..ITERATIONS {
        let (shifted, _) = res(eps + DIFFERENCE)?;
        let (mut jr, mut jj) = (0.0, 0.0);
        for (a, b) in shifted.iter().zip(&r) {
            let j = (a - b) / DIFFERENCE;
            jr += j * b;
            jj += j * j;
        }
        if jj == 0.0 {
            break;
        }
        spread = 1.0 / jj.sqrt();
        let step = (eps - jr / jj).clamp(-RANGE, RANGE) - eps;
        eps += step;
        (r, pose) = res(eps)?;
        if step.abs() < STEP_TOLERANCE {
            break;
        }
    }
    Ok(Fit {
        ratio_error: eps,
        residual: rms(&r),
        drift,
        spread,
        pose,
    })
}
