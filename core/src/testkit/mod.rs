//! The test kit shared by the workspace's test crates (feature `test-kit`, which needs `std`
//! and `proptest`; without it nothing here is built), as nalgebra exports its proptest
//! strategies behind a feature:
//!
//! - [`strategies`]: proptest strategies for the core's types, and the runner's settings
//!   ([`strategies::proptest_config`]);
//! - [`switch_suite`]: the SE(2) small-angle switch suite, generic over the scalar;
//! - the paper's problem: its swimmer and time step ([`paper_kinematics`], [`H`]), horizon
//!   ([`STEPS`]) and extremal costates ([`costate_mu13`], [`costate_mu6`]);
//! - the `f64 → f32` roundings of a state and a costate ([`state_f32`], [`costate_f32`]) and a
//!   distance between motions ([`se2_distance`]).
//!
//! Not part of the core's API for firmware: test code only.
// Test code: a fixture that cannot be built panics; the suite indexes fixed-size arrays.
#![allow(clippy::panic, clippy::indexing_slicing)]

mod fixtures;
pub mod strategies;
pub mod switch_suite;

pub use fixtures::{H, STEPS, costate_mu6, costate_mu13, paper_kinematics};

use crate::{Costate, Real, Se2, State};

/// `(x, y, cos θ, sin θ)` of a motion, widened to `f64`.
pub fn se2_parts<T: Real>(g: &Se2<T>) -> [f64; 4] {
    [g.x(), g.y(), g.cos(), g.sin()].map(|v| v.to_f64())
}

/// Largest componentwise distance between two motions, in `(x, y, cos θ, sin θ)`.
pub fn se2_distance<T: Real, U: Real>(g: &Se2<T>, q: &Se2<U>) -> f64 {
    let (a, b) = (se2_parts(g), se2_parts(q));
    a.iter()
        .zip(b.iter())
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, f64::max)
}

/// `(α, g)` rounded to `f32` component by component (`g` by `x, y, cos θ, sin θ`, as a
/// gait's `f32` checkpoint table stores it).
pub fn state_f32(s: &State<f64>) -> State<f32> {
    let g = &s.g;
    State {
        alpha: s.alpha.map(|v| v as f32),
        g: Se2::from_rotation(g.x() as f32, g.y() as f32, g.cos() as f32, g.sin() as f32),
    }
}

/// `(μ, ξ)` rounded to `f32`.
pub fn costate_f32(c: &Costate<f64>) -> Costate<f32> {
    Costate {
        mu: c.mu.map(|v| v as f32),
        xi: c.xi.map(|v| v as f32),
    }
}
