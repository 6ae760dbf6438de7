//! The gait under model error (docs/ROBUSTNESS.md): flights through a plant whose drag ratio,
//! drag coefficient and link lengths differ from the model's, open loop (the law's controls
//! as they are) and closed loop (the core's tracking law, [`purcell_core::tracking`], with
//! gains from a time-varying LQR along the extremal and a running estimate of the drag-ratio
//! error).
//!
//! [`gains`] computes the tracking table offline, its gain on the ratio error optionally from
//! the plant's neighbouring extremal ([`plan`]); [`flight`] flies a gait through a plant.

pub mod flight;
pub mod gains;
pub mod plan;

pub use flight::{Control, FlightFailure, Noise, Outcome, Sensor, fly, fly_gait, pose_deviation};
pub use gains::{Design, Table, table};
pub use plan::{PLAN_STEP, PlanError, PlanStep, neighbouring};
pub use purcell_core::tracking::{Mismatch, joint_bound};

use crate::problem::Problem;
use crate::solver::Trajectory;
use purcell_core::cost::RunningCost;
use purcell_core::gait::WithReplay;
use purcell_core::{Error, Gait, Replay};

/// The whole trajectory of the `f64` replay of `gait` with its checkpoints, as firmware flies
/// it (the law of the gait's cost): states, controls and the costates `ξ^{k−1}`
/// (`k = 0..=N`); the nominal a tracking table is computed along.
///
/// Errors: the replay's.
pub fn nominal(gait: &Gait<'_>) -> Result<Trajectory, Error> {
    gait.with_replay(true, Nominal(gait.params().costate::<f64>().xi))?
}

/// [`nominal`] of a replay of any cost, from the costate `ξ^{−1}`.
struct Nominal(nalgebra::Vector2<f64>);

impl<'a> WithReplay<'a, f64> for Nominal {
    type Output = Result<Trajectory, Error>;

    fn run<C: RunningCost>(self, mut replay: Replay<'a, f64, C>) -> Self::Output {
        let mut t = Trajectory {
            xis: vec![self.0],
            ..Trajectory::default()
        };
        while let Some(sample) = replay.step()? {
            t.states.push(sample.state);
            t.controls.push(sample.u);
            t.xis.push(*replay.xi());
        }
        t.states.push(*replay.state());
        Ok(t)
    }
}

/// Where a table's gain on `ε` comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum Feedforward {
    /// The plant's neighbouring extremal ([`plan`]).
    Extremal,
    /// The LQR's own: no plan asked for, or the gait has none, and why.
    Lqr(PlanError),
}

/// The tracking table of `gait` along `nominal`, its `f64` replay ([`nominal`]), under `design`, its gain
/// on `ε` from the plant's neighbouring extremal if `design.plan` asks for it and the gait has
/// one ([`plan`]): what `export --tracking` stores and `robustness` flies.
///
/// Errors: [`table`]'s.
pub fn table_of(
    gait: &Gait<'_>,
    nominal: &Trajectory,
    design: &Design,
) -> Result<(Table, Feedforward), Error> {
    let p = gait.params();
    let planned = if design.plan {
        Problem::of_gait(p)
            .map_err(|e| PlanError::Problem(e.to_string()))
            .and_then(|problem| neighbouring(&problem, nominal, &p.costate::<f64>().mu))
    } else {
        Err(PlanError::Off)
    };
    let (steps, source) = match planned {
        Ok(steps) => (Some(steps), Feedforward::Extremal),
        Err(why) => (None, Feedforward::Lqr(why)),
    };
    let t = table(
        &p.kinematics()?,
        &nominal.states,
        &nominal.controls,
        design,
        steps.as_deref(),
    )?;
    Ok((t, source))
}
