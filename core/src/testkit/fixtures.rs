//! The paper's problem that the tests start from, in one place: its swimmer and time step
//! ([`paper_kinematics`], [`H`], [`STEPS`]) and extremals of MODEL.md §4 (`h = 0.01`,
//! `N = 10 000`, `ᾱ = 0`, `ḡ = (0.1, 0.1, 0)`) found by `purcell-sim`. They are inputs, not
//! expected results: every test derives what it asserts from the core itself.

use crate::{Costate, Kinematics, Real, Swimmer};
use nalgebra::{Vector2, Vector3};

/// Time step of the paper's problem, seconds.
pub const H: f64 = 0.01;
/// Horizon of the paper's problem, steps.
pub const STEPS: u32 = 10_000;

/// The paper's swimmer ([`Swimmer::purcell`]) and time step [`H`] in the scalar `T`.
pub fn paper_kinematics<T: Real>() -> Kinematics<T> {
    // h = 0.01 is finite and positive: `new` cannot fail.
    Kinematics::new(Swimmer::purcell(), T::from_f64(H)).unwrap_or_else(|e| panic!("{e}"))
}

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
