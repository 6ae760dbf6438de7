//! Shared helpers for the workspace-level tests: realistic costates of the paper's problem,
//! f64 → f32 conversion of core types, and a full replay into a vector.
//!
//! The costates are extremals of MODEL.md §4 (the paper's problem: `h = 0.01`, `N = 10 000`,
//! `ᾱ = 0`, `ḡ = (0.1, 0.1, 0)`) found by `purcell-sim`; they are inputs here, not
//! expected results: every test derives what it asserts from the core itself.

use nalgebra::{Vector2, Vector3};
use purcell_core::{Checkpoint, Costate, Error, Kinematics, Replay, Sample, Se2, State, Swimmer};

/// Time step of the paper's problem.
pub const H: f64 = 0.01;
/// Horizon of the paper's problem.
pub const STEPS: u32 = 10_000;

#[path = "../core/tests/common/fixtures.rs"]
mod fixtures;
pub use fixtures::{costate_mu6, costate_mu13};

/// The paper's swimmer and time step in the scalar `T`.
pub fn paper_kinematics<T: purcell_core::Real>() -> Kinematics<T> {
    // h = 0.01 is finite and positive: `new` cannot fail; map the impossible error anyway.
    Kinematics::new(Swimmer::purcell(), T::from_f64(H)).unwrap_or_else(|e| panic!("{e}"))
}

/// Replays `steps` steps of the law from `α = 0, g = e` and returns every sample and `(α_N, g_N)`.
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

/// Rounds a 2-vector to f32.
pub fn v2_f32(v: &Vector2<f64>) -> Vector2<f32> {
    v.map(|x| x as f32)
}

/// Rounds a 3-vector to f32.
pub fn v3_f32(v: &Vector3<f64>) -> Vector3<f32> {
    v.map(|x| x as f32)
}

/// Rounds a costate to f32.
pub fn costate_f32(c: &Costate<f64>) -> Costate<f32> {
    Costate {
        mu: v3_f32(&c.mu),
        xi: v2_f32(&c.xi),
    }
}

/// `(x, y, cos θ, sin θ)` of a motion, widened to f64.
pub fn se2_parts<T: purcell_core::Real>(g: &Se2<T>) -> [f64; 4] {
    [g.x(), g.y(), g.cos(), g.sin()].map(|v| v.to_f64())
}

/// Largest componentwise distance between two motions, in `(x, y, cos θ, sin θ)`.
pub fn se2_distance<T: purcell_core::Real, U: purcell_core::Real>(g: &Se2<T>, q: &Se2<U>) -> f64 {
    let (a, b) = (se2_parts(g), se2_parts(q));
    a.iter()
        .zip(b.iter())
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, f64::max)
}

/// `(α, g)` rounded to f32, component by component (`g` by `x, y, cos θ, sin θ`).
pub fn state_f32(s: &State<f64>) -> State<f32> {
    let g = &s.g;
    State {
        alpha: v2_f32(&s.alpha),
        g: Se2::from_rotation(g.x() as f32, g.y() as f32, g.cos() as f32, g.sin() as f32),
    }
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
            xi: v2_f32(&w[0].xi),
        })
        .collect()
}
