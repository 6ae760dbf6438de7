//! The exact discrete kinematics `α ← α + hu`, `g ← g·exp(−hA(α)u)`.

use crate::common;

use common::*;
use nalgebra::Vector2;
use proptest::prelude::*;
use purcell_core::{State, se2};

/// 50 controls of up to 2 rad/s: with `h = 0.01` a shape moves by at most 1 rad.
fn controls() -> impl Strategy<Value = Vec<Vector2<f64>>> {
    prop::collection::vec(
        (-2.0..2.0f64, -2.0..2.0f64).prop_map(|(a, b)| Vector2::new(a, b)),
        50,
    )
}

proptest! {
    #![proptest_config(proptest_config())]

    /// Left invariance: the same controls replayed from `q·g₀` give `q·g_k` at every step
    /// (and the same shapes).
    #[test]
    fn kinematics_are_left_invariant(
        a0 in (-2.0..2.0f64, -2.0..2.0f64),
        g0 in se2(),
        q in se2(),
        us in controls(),
    ) {
        let kin = paper_kinematics::<f64>();
        let alpha = Vector2::new(a0.0, a0.1);
        let mut s = State { alpha, g: g0 };
        let mut t = State { alpha, g: q * g0 };
        for u in &us {
            s = kin.step(&s, u).unwrap();
            t = kin.step(&t, u).unwrap();
            prop_assert_eq!(s.alpha, t.alpha);
            prop_assert!(se2_distance(&(q * s.g), &t.g) <= 1e-13 * scale(&q) * scale(&g0));
        }
    }

    /// One step is `(α + hu, g·exp(X))` with `X = twist(A(α), u) = −hA(α)u`.
    #[test]
    fn step_is_shape_euler_and_group_exponential(
        a0 in (-2.0..2.0f64, -2.0..2.0f64),
        g in se2(),
        u in (-5.0..5.0f64, -5.0..5.0f64),
    ) {
        let kin = paper_kinematics::<f64>();
        let (alpha, u) = (Vector2::new(a0.0, a0.1), Vector2::new(u.0, u.1));
        let next = kin.step(&State { alpha, g }, &u).unwrap();
        prop_assert_eq!(next.alpha, alpha + u * kin.h());
        let a = kin.swimmer().connection(&alpha).unwrap();
        let x = kin.twist(&a, &u);
        prop_assert!((x + a * u * kin.h()).abs().max() <= 1e-16 * (1.0 + u.abs().max()));
        prop_assert_eq!(next.g, g * se2::exp(&x));
    }

    /// A zero control moves nothing.
    #[test]
    fn zero_control_is_a_fixed_point(a0 in (-3.0..3.0f64, -3.0..3.0f64), g in se2()) {
        let kin = paper_kinematics::<f64>();
        let s = State { alpha: Vector2::new(a0.0, a0.1), g };
        let next = kin.step(&s, &Vector2::zeros()).unwrap();
        prop_assert_eq!(next.alpha, s.alpha);
        // Only the renormalisation of the rotation in `compose` may move it, by an ulp.
        prop_assert!(se2_distance(&next.g, &g) <= 4.0 * f64::EPSILON);
    }
}
