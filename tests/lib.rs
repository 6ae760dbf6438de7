//! Helpers of the workspace-level tests beyond the core's test kit (`purcell_core::testkit`:
//! the paper's problem and extremals, `f64 → f32` roundings, distances): a full replay into a
//! vector, and the `f32` checkpoints of an `f64` replay.

use purcell_core::testkit::state_f32;
use purcell_core::{Checkpoint, Costate, Error, Kinematics, Replay, Sample, State};

/// Replays `steps` steps of the law from `start` and returns every sample and `(α_N, g_N)`.
pub fn replay_all<T: purcell_core::Real>(
    kinematics: Kinematics<T>,
    start: State<T>,
    costate: Costate<T>,
    steps: u32,
    checkpoints: &[Checkpoint<T>],
) -> Result<(Vec<Sample<T>>, State<T>), Error> {
    let mut replay = Replay::new(kinematics, start, costate, steps, checkpoints)?;
    let samples = replay.by_ref().collect::<Result<Vec<_>, _>>()?;
    Ok((samples, *replay.state()))
}

/// The checkpoints `(k, α_k, g_k, ξ^{k−1})` every `every` steps of an f64 replay, rounded to
/// f32.
pub fn checkpoints_f32(samples: &[Sample<f64>], every: u32) -> Vec<Checkpoint<f32>> {
    samples
        .windows(2)
        .filter(|w| w[1].k % every == 0)
        .map(|w| Checkpoint {
            k: w[1].k,
            state: state_f32(&w[1].state),
            xi: w[0].xi.map(|v| v as f32),
        })
        .collect()
}
