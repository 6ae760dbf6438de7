//! What `robustness` reports of a gait flown through a mismatched plant: each flight's and each
//! case's results, as the command prints them and its figure draws them.

use crate::replan::{Replan, Replanned};
use purcell_core::gait::GaitParams;
use purcell_solver::tracking::FlightFailure;
use serde::Serialize;

/// One flight's result.
#[derive(Clone, Debug, Serialize)]
pub struct FlightReport {
    /// `max |α_N − ᾱ|`, rad (`purcell_core::TerminalError`).
    pub alpha_error: Option<f64>,
    /// `max |log(ḡ⁻¹ g_N)|`, m or rad.
    pub g_error: Option<f64>,
    /// `Σ h/2·|u_k|²` flown.
    pub cost: Option<f64>,
    /// Largest `|α_i|` of the plant.
    pub max_abs_alpha: Option<f64>,
    /// The tracking law's final estimate of the drag ratio's relative error (0 open loop).
    pub estimated_ratio_error: Option<f64>,
    /// Why the flight stopped, if it did.
    pub failure: Option<String>,
    /// With `--replan`: each re-plan ([`crate::replan`]).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub replans: Vec<Replan>,
    /// With `--replan`: why the estimate was given up, if it was.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub given_up: Option<String>,
    /// The pose error against the nominal pose, per step (not in the report).
    #[serde(skip)]
    pub deviation: Vec<f64>,
}

impl FlightReport {
    /// A flight that stopped, and why.
    pub fn failed(why: String) -> Self {
        FlightReport {
            alpha_error: None,
            g_error: None,
            cost: None,
            max_abs_alpha: None,
            estimated_ratio_error: None,
            failure: Some(why),
            deviation: Vec::new(),
            replans: Vec::new(),
            given_up: None,
        }
    }
}

impl FlightReport {
    /// The report of a re-planned flight of the gait of `params`.
    pub fn replanned(params: &GaitParams, flight: Result<Replanned, FlightFailure>) -> Self {
        match flight {
            Ok(r) => {
                let e = params.terminal_error(&r.end);
                FlightReport {
                    alpha_error: Some(e.alpha),
                    g_error: Some(e.g),
                    cost: Some(r.cost),
                    max_abs_alpha: Some(r.max_abs_alpha),
                    estimated_ratio_error: Some(r.estimate),
                    failure: None,
                    deviation: r.deviation,
                    replans: r.replans,
                    given_up: r.given_up,
                }
            }
            Err(e) => FlightReport::failed(e.to_string()),
        }
    }
}

/// One case: the plant's errors, the noise, and both flights.
#[derive(Clone, Debug, Serialize)]
pub struct CaseReport {
    /// The plant's parameter errors and the noise, as given.
    pub ratio_error: f64,
    /// Of `k`.
    pub drag_error: f64,
    /// Of the links.
    pub length_error: f64,
    /// Pose noise.
    pub pose_noise: f64,
    /// Joint-angle noise.
    pub shape_noise: f64,
    /// Seed.
    pub seed: u64,
    /// The law's controls as they are.
    pub open: FlightReport,
    /// The tracking law.
    pub closed: FlightReport,
}

/// `+10%` for `0.1`.
pub fn percent(v: f64) -> String {
    format!("{:+}%", (v * 1000.0).round() / 10.0)
}
