//! The core's small-angle switch suite (`purcell_core::testkit::switch_suite`) over the
//! solver's dual numbers, with the core's test kit's strategies: the values as in f64, and the
//! derivatives the duals carry through either branch of each switch against the series'
//! derivatives, so that they are continuous across it (the KKT certificate differentiates
//! the core's kinematics on duals, `purcell_solver::solver::certificate`).

use nalgebra::{Vector2, Vector3};
use proptest::prelude::*;
use purcell_core::se2::{C3_SERIES_LIMIT, ExpCoefficients, SMALL_ANGLE};
use purcell_core::testkit::se2_parts;
use purcell_core::testkit::strategies::{angle_across_switches, proptest_config};
use purcell_core::testkit::switch_suite::{
    coefficients, dexp_transpose, exp, momentum, series, twist_across_switches, within,
};
use purcell_core::{Kinematics, State, Swimmer, Tangent};
use purcell_solver::dual::Dual;

type D = Dual<1>;

/// Relative errors (in ε) of the derivatives in `ω` of `a, b, c₂, c₃, sin, cos` on duals.
fn derivatives(w: f64) -> [f64; 6] {
    let k = ExpCoefficients::new(D::variable(w, 0));
    let s = series(w);
    [
        (k.a, s.da),
        (k.b, s.db),
        (k.c2, s.dc2),
        (k.c3, s.dc3),
        (k.sin, 1.0 - w * s.b),
        (k.cos, -w * s.a),
    ]
    .map(|(got, want)| (got.d[0] - want).abs() / want.abs() / f64::EPSILON)
}

/// `∂(dexp_Xᵀm)/∂ω` by duals against the hand-written Jacobian in f64, relative to its size.
fn dual_jacobian(x: [f64; 3], m: [f64; 3]) -> f64 {
    let xd = Tangent::new(D::constant(x[0]), D::constant(x[1]), D::variable(x[2], 0));
    let md = Vector3::new(D::constant(m[0]), D::constant(m[1]), D::constant(m[2]));
    let by_dual = ExpCoefficients::new(xd.z).dexp_transpose_mul(&xd, &md);
    let xf = Tangent::new(x[0], x[1], x[2]);
    let mf = Vector3::new(m[0], m[1], m[2]);
    let by_hand = ExpCoefficients::new(x[2])
        .dexp_transpose_mul_jacobian(&xf, &mf)
        .d_omega;
    let scale = by_hand.amax().max(1e-300);
    (0..3)
        .map(|i| (by_dual[i].d[0] - by_hand[i]).abs())
        .fold(0.0, f64::max)
        / scale
}

/// Bounds, 10× the worst measured over 300 000 cases of these strategies: the values as in
/// f64 (`core/tests/it/switches.rs`); the derivatives of `b`, `sin`, `cos` 6.5 ε (bound 65 ε);
/// those of `a`, `c₂`, `c₃` 3.6e-11 relative (bound 4e-10), at `|ω|` just below
/// `SMALL_ANGLE`, where the duals differentiate the truncated series (its first omitted term
/// is below rounding for the value, not for the derivative); the duals' `∂(dexp_Xᵀm)/∂ω`
/// against the hand-written Jacobian 3.7e-13 relative (bound 4e-12).
const DERIVATIVES: [f64; 6] = [
    4e-10 / f64::EPSILON,
    65.0,
    4e-10 / f64::EPSILON,
    4e-10 / f64::EPSILON,
    65.0,
    65.0,
];

proptest! {
    #![proptest_config(proptest_config())]

    #[test]
    fn dual_values_match_the_series_as_f64_does(x in twist_across_switches(), m in momentum()) {
        within(coefficients::<D>(x[2]), [20.0, 20.0, 20.0, 270.0, 20.0, 20.0])?;
        prop_assert!(exp::<D>(x) <= 25.0);
        prop_assert!(dexp_transpose::<D>(x, m) <= 60.0);
    }

    #[test]
    fn dual_derivatives_match_the_series_across_the_switches(w in angle_across_switches()) {
        within(derivatives(w), DERIVATIVES)?;
    }

    /// The kinematics step the KKT certificate differentiates, on duals seeded on `u`, with
    /// its twist's angle on either side of each switch: the derivatives of the next pose
    /// match central differences of the f64 step: 9.1e-11 at worst over 10 000 cases (8 184
    /// with an `h ≤ 2`, a third of them at `|ω|` near 0.01, a fifth near 0.5), bound 1e-9.
    #[test]
    fn dual_derivatives_of_a_step_match_central_differences_across_the_switches(
        alpha in (-1.5..1.5f64, -1.5..1.5f64), phi in 0.0..core::f64::consts::TAU,
        w in angle_across_switches(),
    ) {
        let alpha = [alpha.0, alpha.1];
        let Some((h, u)) = step_for(alpha, phi, w) else { return Ok(()) };
        if let Some(e) = step_derivatives(alpha, h, u) {
            prop_assert!(e <= 1e-9, "{e:e}");
        }
    }

    #[test]
    fn dual_derivatives_of_dexp_transpose_are_the_jacobian(x in twist_across_switches(), m in momentum()) {
        let e = dual_jacobian(x, m);
        prop_assert!(e <= 4e-12, "{e:e}");
    }
}

/// On either side of each switch, one ulp apart, both signs: the duals' derivatives jump by
/// no more than the bounds above allow (4e-10 relative).
#[test]
fn dual_derivatives_are_continuous_across_each_switch() {
    for s in [SMALL_ANGLE, -SMALL_ANGLE, C3_SERIES_LIMIT, -C3_SERIES_LIMIT] {
        let below = f64::from_bits(s.to_bits() - 1);
        let (k0, k1) = (
            ExpCoefficients::new(D::variable(below, 0)),
            ExpCoefficients::new(D::variable(s, 0)),
        );
        for (name, lo, hi) in [
            ("a", k0.a, k1.a),
            ("b", k0.b, k1.b),
            ("c2", k0.c2, k1.c2),
            ("c3", k0.c3, k1.c3),
            ("sin", k0.sin, k1.sin),
            ("cos", k0.cos, k1.cos),
        ] {
            let jump = (lo.d[0] - hi.d[0]).abs() / hi.d[0].abs();
            assert!(jump <= 4e-10, "{name} at {s}: {jump:e}");
        }
    }
}

/// A control `u` at shape `α` and a step `h` whose twist `X = −h·A(α)·u` has angle `ω`:
/// `u` a unit vector at angle `phi` (its sign chosen so that `h > 0`); `None` where
/// `(A u)_θ` is too small for an `h ≤ 2`.
fn step_for(alpha: [f64; 2], phi: f64, w: f64) -> Option<(f64, [f64; 2])> {
    let a = Swimmer::<f64>::purcell()
        .connection(&Vector2::new(alpha[0], alpha[1]))
        .ok()?;
    let dir = Vector2::new(phi.cos(), phi.sin());
    let z = (a * dir).z;
    let h = w.abs() / z.abs();
    let sign = -(w * z).signum();
    (h <= 2.0).then_some((h, [sign * dir.x, sign * dir.y]))
}

/// `(x, y, cos θ, sin θ)` of the next state of `step` from `(α, e)` on duals seeded on `u`,
/// against central differences of the f64 step (`δ = 1e-6`), relative to `1 + |∂|`.
fn step_derivatives(alpha: [f64; 2], h: f64, u: [f64; 2]) -> Option<f64> {
    let kin = |h: f64| Kinematics::new(Swimmer::<f64>::purcell(), h).unwrap();
    let s64 = State::at_origin(Vector2::new(alpha[0], alpha[1]));
    let next = |u: Vector2<f64>| kin(h).step(&s64, &u).ok().map(|s| se2_parts(&s.g));
    let two = Swimmer::<Dual<2>>::purcell();
    let kd = Kinematics::new(two, Dual::constant(h)).unwrap();
    let sd = State::at_origin(Vector2::new(
        Dual::constant(alpha[0]),
        Dual::constant(alpha[1]),
    ));
    let ud = Vector2::new(Dual::variable(u[0], 0), Dual::variable(u[1], 1));
    let g = kd.step(&sd, &ud).ok()?.g;
    let by_dual = [g.x(), g.y(), g.cos(), g.sin()];
    let d = 1e-6;
    let mut worst = 0.0f64;
    for j in 0..2 {
        let mut e = Vector2::zeros();
        e[j] = d;
        let u = Vector2::new(u[0], u[1]);
        let (p, m) = (next(u + e)?, next(u - e)?);
        for i in 0..4 {
            let fd = (p[i] - m[i]) / (2.0 * d);
            worst = worst.max((by_dual[i].d[j] - fd).abs() / (1.0 + fd.abs()));
        }
    }
    Some(worst)
}
