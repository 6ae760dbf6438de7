//! The neighbouring extremal: the plant's own extremal as a function of the drag ratio's
//! relative error `ε`, to first order (MODEL.md §10), the tracking table's alternative gain
//! on `ε` ([`super::Design::plan`]).
//!
//! The gait's extremal is continued ([`continue_to`]) to the drag ratios `r(1 ± δ)`,
//! `δ =` [`PLAN_STEP`]; with `E_k^±` the error of their states against the gait's
//! ([`tracking_error`], the coordinates the tracking law measures in) and `u_k^±` their
//! controls, the plant's extremal at `r(1 + ε)` is, per step, by central differences,
//!
//! ```text
//! e_k(ε) = ψ_k ε + O(ε²),   ψ_k = (E⁺ − E⁻)/2δ,     u_k(ε) = u_k + φ_k ε + O(ε²),   φ_k = (u⁺ − u⁻)/2δ
//! ```
//!
//! Both ends reach the target: `ψ_N = 0` up to the solver's tolerance. A gait with a joint
//! limit has none: its arcs' junctions move with `r`, and the difference quotients are not
//! smooth there.

use crate::problem::Problem;
use crate::solver::continuation::{Warm, continue_to};
use crate::solver::{SolveError, Trajectory};
use nalgebra::{Vector2, Vector3, Vector5};
use purcell_core::Swimmer;
use purcell_core::tracking::tracking_error;

/// `δ` of the central differences: small enough that the continued extremals of the gaits
/// measured stay within the links' overlap (the paper's gait leaves it at `ε = −0.05`).
pub const PLAN_STEP: f64 = 0.02;

/// One step of the plan: the error and control of the plant's extremal per unit `ε`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanStep {
    /// `ψ_k`.
    pub error: Vector5<f64>,
    /// `φ_k`.
    pub control: Vector2<f64>,
}

/// Why a gait has no plan.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PlanError {
    /// Not asked for ([`super::Design::plan`]).
    #[error("not asked for")]
    Off,
    /// The gait has a joint limit (see the module docs).
    #[error("the gait has a joint limit")]
    JointLimit,
    /// The gait's problem or its nominal trajectory is not valid.
    #[error("the gait's problem: {0}")]
    Problem(String),
    /// The continuation to `r(1 + ε)` failed.
    #[error("the extremal at {eps:+} in the drag ratio: {why}")]
    Continuation {
        /// `±δ`.
        eps: f64,
        /// Why.
        why: SolveError,
    },
}

/// The plan along `nominal` (the gait's trajectory with its `N + 1` states) of the extremal of
/// `problem` with momentum `mu` (module docs).
///
/// Errors: [`PlanError`].
pub fn neighbouring(
    problem: &Problem,
    nominal: &Trajectory,
    mu: &Vector3<f64>,
) -> Result<Vec<PlanStep>, PlanError> {
    if problem.alpha_max.is_some() {
        return Err(PlanError::JointLimit);
    }
    let warm = Warm::from_trajectory(nominal, mu, problem.horizon())
        .ok_or_else(|| PlanError::Problem("an empty trajectory".into()))?;
    let continued = |eps: f64| -> Result<Trajectory, PlanError> {
        let fail = |why| PlanError::Continuation { eps, why };
        let sw = &problem.swimmer;
        let swimmer = Swimmer::new(sw.lengths(), sw.drag(), sw.ratio() * (1.0 + eps))
            .map_err(|e| PlanError::Problem(e.to_string()))?;
        let q = Problem {
            swimmer,
            ..*problem
        };
        let x = continue_to(&q, &warm).map_err(fail)?;
        if !x.admissible {
            return Err(fail(SolveError::NoneAdmissible {
                found: 1,
                best_alpha: x.max_abs_alpha,
            }));
        }
        Ok(x.trajectory)
    };
    let (up, down) = (continued(PLAN_STEP)?, continued(-PLAN_STEP)?);
    let n = nominal.controls.len();
    if [&up, &down]
        .iter()
        .any(|t| t.controls.len() != n || t.states.len() != n + 1)
    {
        return Err(PlanError::Problem(
            "a continued extremal on another grid".into(),
        ));
    }
    let d = PLAN_STEP;
    Ok((0..n)
        .map(|k| {
            let at = &nominal.states[k];
            let e = |t: &Trajectory| Vector5::from(tracking_error(at, &t.states[k]));
            let (ep, em) = (e(&up), e(&down));
            PlanStep {
                error: (ep - em) / (2.0 * d),
                control: (up.controls[k] - down.controls[k]) / (2.0 * d),
            }
        })
        .collect())
}
