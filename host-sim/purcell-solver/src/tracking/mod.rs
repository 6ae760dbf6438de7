//! The gait under model error (docs/ROBUSTNESS.md): flights through a plant whose drag ratio,
//! drag coefficient and link lengths differ from the model's, open loop (the law's controls
//! as they are) and closed loop (the core's tracking law, [`purcell_core::tracking`], with
//! gains from a time-varying LQR along the extremal and a running estimate of the drag-ratio
//! error).
//!
//! [`gains`] computes the tracking table offline; [`flight`] flies a gait through a plant.

pub mod flight;
pub mod gains;

pub use flight::{Control, FlightFailure, Noise, Outcome, fly};
pub use gains::{Design, Table, table};
pub use purcell_core::tracking::{Mismatch, joint_bound};

use crate::solver::Trajectory;
use purcell_core::{Error, Gait};

/// The whole trajectory of the `f64` replay of `gait` with its checkpoints, as firmware flies
/// it: states, controls and the costates `ξ^{k−1}` (`k = 0..=N`); the nominal a tracking table
/// is computed along.
///
/// Errors: the replay's.
pub fn nominal(gait: &Gait<'_>) -> Result<Trajectory, Error> {
    let mut replay = gait.replay::<f64>()?;
    let mut t = Trajectory {
        xis: vec![gait.params().costate::<f64>().xi],
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
