//! What the core's integration tests share beyond the test kit (`purcell_core::testkit`, which
//! this module re-exports): realistic states along the paper's extremals, a scale for
//! tolerances, and replays of a gait's parameters from tables in memory.
#![allow(dead_code, unused_imports)] // each test binary uses some of it

pub use purcell_core::testkit::strategies::*;
pub use purcell_core::testkit::*;

use nalgebra::Vector2;
use purcell_core::gait::{GaitParams, Model};
use purcell_core::{Arc, Checkpoint, Costate, Error, Flight, Real, Replay, Se2, State};

/// Largest magnitude of the translation of a motion, at least 1 (a scale for tolerances).
pub fn scale(g: &Se2<f64>) -> f64 {
    1.0f64.max(g.x().abs()).max(g.y().abs())
}

/// A costate with `|μ| ≈ 4`: the `|μ| ≈ 6.4` extremal of the paper's problem (purcell-solver)
/// scaled by `4/6.4`; its loop is not an extremal but its states are of the same kind.
pub fn costate_mu4() -> Costate<f64> {
    let c = costate_mu6();
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
        paper_kinematics(),
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

/// The replay of `p`'s whole horizon from `(ᾱ, e)` and `(μ, ξ^{−1})` with `checkpoints` and
/// `arcs` in memory: what `Gait::replay` runs from the same tables stored in a file.
pub fn replay_in_memory<'a, T: Real>(
    p: &GaitParams,
    checkpoints: &'a [Checkpoint<T>],
    arcs: &'a [Arc],
) -> Replay<'a, T> {
    Replay::with_arcs(
        p.kinematics().unwrap(),
        p.start(),
        p.costate(),
        p.steps,
        checkpoints,
        arcs,
    )
    .unwrap()
}

/// The flight of a replay ([`Replay::fly`] with [`Replay::step`]), or the error that made it
/// or its steps fail.
pub fn fly<T: Real>(replay: Result<Replay<'_, T>, Error>) -> Result<Flight<T>, Error> {
    replay?.fly(Replay::step)
}

/// A gait of the paper's swimmer (unit links, `k = 1`, `r = 2`) with `h = 0.01` from `ᾱ = 0`,
/// checkpoints every 100 steps, no joint limit: the parameters the gaits of these tests share
/// (each sets its own horizon, target and costate).
pub fn paper_gait(steps: u32, target: [f64; 3], mu: [f64; 3], xi0: [f64; 2]) -> GaitParams {
    GaitParams {
        model: Model {
            links: [1.0; 3],
            drag: 1.0,
            ratio: 2.0,
        },
        h: 0.01,
        steps,
        alpha0: [0.0, 0.0],
        target,
        mu,
        xi0,
        checkpoint_every: 100,
        alpha_max: None,
        alpha_end: None,
        cost: purcell_core::Cost::Effort,
    }
}
