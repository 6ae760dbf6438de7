//! The costates of the paper's problem that the tests start from, in one place: extremals of
//! MODEL.md §4 (`h = 0.01`, `N = 10 000`, `ᾱ = 0`, `ḡ = (0.1, 0.1, 0)`) found by
//! `purcell-sim`. They are inputs, not expected results.
//!
//! A module of the core's test helpers (`core/tests/common`), so the published crate's tests
//! are self-contained; the workspace tests (`purcell-tests`, not published) include this file
//! by path (a dev-dependency of the core on `purcell-tests` would be a cycle).

use nalgebra::{Vector2, Vector3};
use purcell_core::Costate;

/// An extremal with `|μ| ≈ 13.3` (a loop that swings past `|α| = 2.5`).
pub fn costate_mu13() -> Costate<f64> {
    Costate {
        mu: Vector3::new(
            1.532_914_552_615_802_8,
            13.222_390_687_754_31,
            0.593_346_744_546_872_6,
        ),
        xi: Vector2::new(2.262_121_649_874_644, -1.952_433_722_666_657_5),
    }
}

/// An extremal with `|μ| ≈ 6.4` (the cheapest admissible one found).
pub fn costate_mu6() -> Costate<f64> {
    Costate {
        mu: Vector3::new(
            1.267_405_852_682_282_5,
            6.195_325_497_329_788,
            -1.054_518_565_868_840_5,
        ),
        xi: Vector2::new(0.645_028_386_460_496_6, -1.333_507_114_196_018_2),
    }
}
