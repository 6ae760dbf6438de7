//! Helpers shared by the integration tests of `purcell-core`: proptest strategies in the
//! manif discipline (identity, tiny perturbations, random elements), realistic states of the
//! paper's problem, and comparisons.
#![allow(dead_code)]

use nalgebra::Vector2;
use proptest::prelude::*;
use purcell_core::{Costate, Kinematics, Replay, Se2, State, Swimmer};

/// proptest's default 256 cases (`PROPTEST_CASES` overrides), no regression files written into the source tree (failures print their
/// minimal input; add it as an explicit test case instead).
pub fn config() -> ProptestConfig {
    ProptestConfig {
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// The core's exported strategies (feature `proptest-strategies`), shared with host-sim's
/// tests (each test file uses some of them).
#[allow(unused_imports)]
pub use purcell_core::strategies::{alpha, angle_across_switches, se2, tangent, tangent_near_pi};

/// `(x, y, cos θ, sin θ)` widened to f64.
pub fn parts<T: purcell_core::Real>(g: &Se2<T>) -> [f64; 4] {
    [g.x(), g.y(), g.cos(), g.sin()].map(|v| v.to_f64())
}

/// Largest componentwise distance between two motions in `(x, y, cos θ, sin θ)`.
pub fn dist<T: purcell_core::Real>(g: &Se2<T>, q: &Se2<T>) -> f64 {
    let (a, b) = (parts(g), parts(q));
    (0..4).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max)
}

/// Largest magnitude of the translation of a motion, at least 1 (a scale for tolerances).
pub fn scale(g: &Se2<f64>) -> f64 {
    1.0f64.max(g.x().abs()).max(g.y().abs())
}

/// The paper's swimmer with `h = 0.01` in the scalar `T`.
pub fn kinematics<T: purcell_core::Real>() -> Kinematics<T> {
    Kinematics::new(Swimmer::purcell(), T::from_f64(0.01)).unwrap()
}

mod fixtures;
#[allow(unused_imports)] // not every test binary uses it
pub use fixtures::costate_mu13;

/// A costate with `|μ| ≈ 4`: the `|μ| ≈ 6.4` extremal of the paper's problem (purcell-solver)
/// scaled by `4/6.4`; its loop is not an extremal but its states are of the same kind.
pub fn costate_mu4() -> Costate<f64> {
    let c = fixtures::costate_mu6();
    let s = 4.0 / 6.4;
    Costate {
        mu: c.mu * s,
        xi: c.xi * s,
    }
}

/// States `(α_k, g_k, ξ^{k−1})` every `every` steps along the f64 replay of `costate`
/// from `α = 0, g = e`, for `steps` steps.
pub fn states_along(
    costate: Costate<f64>,
    steps: u32,
    every: u32,
) -> Vec<(State<f64>, Vector2<f64>)> {
    let replay = Replay::new(
        kinematics(),
        State::at_origin(Vector2::zeros()),
        costate,
        steps,
        &[],
    )
    .unwrap();
    let mut xi_prev = costate.xi;
    let mut out = Vec::new();
    for s in replay {
        let s = s.unwrap();
        if s.k % every == 0 {
            out.push((s.state, xi_prev));
        }
        xi_prev = s.xi;
    }
    out
}

/// f64 state rounded to f32.
pub fn state_f32(s: &State<f64>) -> State<f32> {
    State {
        alpha: s.alpha.map(|v| v as f32),
        g: Se2::new(s.g.x() as f32, s.g.y() as f32, s.g.theta() as f32),
    }
}

pub mod switch_suite;
