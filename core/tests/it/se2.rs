//! SE(2) properties in the manif discipline: each identity on the identity element, on tiny
//! perturbations (1e-8) and on random elements; Jacobians against finite differences.

use crate::common;

use common::*;
use nalgebra::{Matrix3, Vector2, Vector3};
use proptest::prelude::*;
use purcell_core::se2::{self, ExpCoefficients};
use purcell_core::{Real, Se2, Tangent};

/// Largest componentwise difference of two twists.
fn tdist(a: &Tangent<f64>, b: &Tangent<f64>) -> f64 {
    (a - b).abs().max()
}

/// The 3×3 matrix of a motion.
fn matrix(g: &Se2<f64>) -> Matrix3<f64> {
    Matrix3::new(
        g.cos(),
        -g.sin(),
        g.x(),
        g.sin(),
        g.cos(),
        g.y(),
        0.0,
        0.0,
        1.0,
    )
}

/// The 3×3 matrix of a twist (the hat map).
fn hat(x: &Tangent<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -x.z, x.x, x.z, 0.0, x.y, 0.0, 0.0, 0.0)
}

/// `Σ_{n<40} ad_Xⁿ/(n+1)!`: the defining series of `dexp`, summed directly.
fn dexp_series(x: &Tangent<f64>) -> Matrix3<f64> {
    let ad = se2::ad(x);
    let (mut term, mut sum) = (Matrix3::identity(), Matrix3::identity());
    for n in 1..40 {
        term = term * ad / f64::from(n + 1);
        sum += term;
    }
    sum
}

/// `dexp_X δ` and the central difference of `t ↦ log(exp(X + tδ)·exp(X)⁻¹)` at `t`, which it
/// must match if `dexp` is the left Jacobian of `exp`.
fn left_jacobian_and_difference<T: Real>(
    x: &Tangent<T>,
    d: &Vector3<T>,
    t: T,
) -> (Vector3<T>, Vector3<T>) {
    let gi = se2::exp(x).inverse();
    let plus = (se2::exp(&(x + d * t)) * gi).log();
    let minus = (se2::exp(&(x - d * t)) * gi).log();
    let fd = (plus - minus) / (T::from_f64(2.0) * t);
    (fd, se2::dexp(x) * d)
}

proptest! {
    #![proptest_config(proptest_config())]

    /// `log(exp(X)) = X` for `|ω| < π`, with rounding relative to `|v|`.
    #[test]
    fn exp_log_round_trip(x in tangent()) {
        let back = se2::exp(&x).log();
        prop_assert!(tdist(&back, &x) <= 4e-15 * (1.0 + x.abs().max()), "{x:?} -> {back:?}");
    }

    /// Near `ω = ±π` the angle is still recovered exactly and the translation to the
    /// conditioning of `V(ω)⁻¹` (`|V⁻¹| ≤ π/2` there): no wrap to the other side.
    #[test]
    fn exp_log_round_trip_near_pi(x in tangent_near_pi()) {
        let back = se2::exp(&x).log();
        prop_assert!(tdist(&back, &x) <= 1e-14 * (1.0 + x.abs().max()), "{x:?} -> {back:?}");
    }

    /// `exp(log g) = g` for every element, including `θ = ±π` (where `log` picks `+π`).
    #[test]
    fn exp_of_log_is_identity_on_the_group(g in se2()) {
        let x = g.log();
        prop_assert!(x.z > -core::f64::consts::PI && x.z <= core::f64::consts::PI);
        prop_assert!(se2_distance(&se2::exp(&x), &g) <= 4e-15 * scale(&g));
    }

    /// Small angles: `exp` equals the matrix exponential's series (to 1e-15 relative), so
    /// no digit is lost in `(1 − cos ω)/ω` at `|ω| ≪ 1` (in f64 and, below, in f32).
    #[test]
    fn exp_coefficients_are_exact_at_small_angles(e in -9.0..-1.0f64, neg in any::<bool>()) {
        let w = if neg { -(10f64.powf(e)) } else { 10f64.powf(e) };
        let k = ExpCoefficients::new(w);
        // References by their series in f64 (10 terms: far past rounding for |ω| ≤ 0.1):
        // a = Σ(−1)ᵏω^{2k}/(2k+1)!, b = Σ(−1)ᵏω^{2k+1}/(2k+2)!, c₂ = b/ω, c₃ = Σ(−1)ᵏω^{2k}/(2k+3)!
        let series = |shift: i32, odd: i32| -> f64 {
            (0..10).map(|k| (-1f64).powi(k) * w.powi(2 * k + odd) / fact(2 * k + shift)).sum()
        };
        let (a_ref, b_ref, c2_ref, c3_ref) = (series(1, 0), series(2, 1), series(2, 0), series(3, 0));
        // A few roundings each (≤ 3 ulp ≈ 7e-16 relative).
        for (got, want) in [(k.a, a_ref), (k.b, b_ref), (k.c2, c2_ref), (k.c3, c3_ref)] {
            prop_assert!((got - want).abs() <= 7e-16 * want.abs(), "ω = {w:e}: {got:e} vs {want:e}");
        }
        // f32 (two terms of each series below |ω| = 0.01): every coefficient keeps full single
        // precision against the series at the rounded ω (the naive b has no digit left below
        // 1e-4), a few roundings each.
        let w32 = f64::from(w as f32);
        let k32 = ExpCoefficients::new(w as f32);
        let series32 = |shift: i32, odd: i32| -> f64 {
            (0..10).map(|k| (-1f64).powi(k) * w32.powi(2 * k + odd) / fact(2 * k + shift)).sum()
        };
        // Worst measured: 0.69·ε in [1e-9, 0.01) (the series; every 997th f32), 1.72·ε in
        // [0.01, 0.1) (the closed forms: sin_cos_f32 of ω/2, a division, a square; every f32).
        let tol = f64::from(f32::EPSILON) * if w32.abs() < 0.01 { 1.0 } else { 2.0 };
        for (got, want) in [
            (k32.a, series32(1, 0)),
            (k32.b, series32(2, 1)),
            (k32.c2, series32(2, 0)),
            (k32.c3, series32(3, 0)),
        ] {
            prop_assert!((f64::from(got) - want).abs() <= tol * want.abs(), "ω = {w32:e}: {got:e} vs {want:e}");
        }
    }

    /// Group axioms: `g·g⁻¹ = g⁻¹·g = e`, `e·g = g·e = g`, associativity,
    /// `(gh)⁻¹ = h⁻¹g⁻¹`, `between(g, h) = g⁻¹h`, and `act` is the matrix action.
    #[test]
    fn compose_and_inverse_satisfy_the_group_axioms(g in se2(), h in se2(), k in se2(), p in (-5.0..5.0f64, -5.0..5.0f64)) {
        let e = Se2::identity();
        let sc = scale(&g) * scale(&h) * scale(&k);
        prop_assert!(se2_distance(&(g * g.inverse()), &e) <= 1e-14 * sc);
        prop_assert!(se2_distance(&(g.inverse() * g), &e) <= 1e-14 * sc);
        prop_assert!(se2_distance(&(e * g), &g) <= 1e-15 * sc && se2_distance(&(g * e), &g) <= 1e-15 * sc);
        prop_assert!(se2_distance(&((g * h) * k), &(g * (h * k))) <= 1e-14 * sc);
        prop_assert!(se2_distance(&(g * h).inverse(), &(h.inverse() * g.inverse())) <= 1e-14 * sc);
        prop_assert!(se2_distance(&g.between(&h), &(g.inverse() * h)) <= 1e-15 * sc);
        prop_assert!((matrix(&(g * h)) - matrix(&g) * matrix(&h)).abs().max() <= 1e-14 * sc);
        let p = Vector2::new(p.0, p.1);
        let q = matrix(&g) * Vector3::new(p.x, p.y, 1.0);
        prop_assert!((g.act(&p) - q.xy()).abs().max() <= 1e-14 * sc);
        prop_assert!(((g * h).act(&p) - g.act(&h.act(&p))).abs().max() <= 1e-13 * sc);
    }

    /// `Ad` is a homomorphism: `Ad_{gh} = Ad_g Ad_h`, `Ad_{g⁻¹} = Ad_g⁻¹`, and it is the
    /// conjugation: `g exp(X) g⁻¹ = exp(Ad_g X)`; `adjoint_transpose_mul` is `Ad_gᵀ μ`.
    #[test]
    fn adjoint_is_a_homomorphism_and_conjugation(g in se2(), h in se2(), x in tangent(), mu in (-10.0..10.0f64, -10.0..10.0f64, -10.0..10.0f64)) {
        let sc = scale(&g) * scale(&h);
        prop_assert!(((g * h).adjoint() - g.adjoint() * h.adjoint()).abs().max() <= 1e-14 * sc);
        prop_assert!((g.inverse().adjoint() * g.adjoint() - Matrix3::identity()).abs().max() <= 1e-14 * sc);
        let lhs = g * se2::exp(&x) * g.inverse();
        let rhs = se2::exp(&(g.adjoint() * x));
        prop_assert!(se2_distance(&lhs, &rhs) <= 1e-13 * sc * sc * (1.0 + x.abs().max()));
        let mu = Vector3::new(mu.0, mu.1, mu.2);
        prop_assert!((g.adjoint_transpose_mul(&mu) - g.adjoint().transpose() * mu).abs().max() <= 1e-14 * sc * 10.0);
    }

    /// `ad_X Y` is the Lie bracket `[X̂, Ŷ]` of the hat matrices, antisymmetric.
    #[test]
    fn ad_is_the_lie_bracket(x in tangent(), y in tangent()) {
        let br = hat(&x) * hat(&y) - hat(&y) * hat(&x);
        let z = se2::ad(&x) * y;
        prop_assert!((hat(&z) - br).abs().max() <= 1e-14 * (1.0 + x.abs().max()) * (1.0 + y.abs().max()));
        prop_assert!((se2::ad(&x) * y + se2::ad(&y) * x).abs().max() <= 1e-14 * (1.0 + x.abs().max()) * (1.0 + y.abs().max()));
    }

    /// `dexp_X = Σ ad_Xⁿ/(n+1)!` (the series summed to 40 terms) for every branch of the
    /// coefficients (`|ω| < 0.01`, `< 0.5`, above).
    #[test]
    fn dexp_equals_its_series(x in tangent()) {
        let d = se2::dexp(&x);
        let s = dexp_series(&x);
        prop_assert!((d - s).abs().max() <= 1e-13 * (1.0 + x.abs().max()), "{x:?}\n{d}\n{s}");
    }

    /// `dexp` is the left Jacobian of `exp`: `exp(X + tδ) ≈ exp(t·dexp_X δ)·exp(X)`, checked
    /// by a central difference of `t ↦ log(exp(X + tδ)·exp(X)⁻¹)` at `t = 1e-5` (truncation
    /// O(t²|X|²), rounding O(1e-16/t)).
    #[test]
    fn dexp_is_the_left_jacobian_of_exp(x in tangent(), d in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)) {
        let (fd, jac) = left_jacobian_and_difference(&x, &Vector3::new(d.0, d.1, d.2), 1e-5);
        prop_assert!((fd - jac).abs().max() <= 1e-8 * (1.0 + x.abs().max()).powi(2), "{fd:?} vs {jac:?}");
    }

    /// The same in f32 at a perturbation of 1e-2 (manif's f32 discipline). Tolerance 6e-5·n²,
    /// `n = 1 + |X|_∞`: 10× the worst measured, 5.6e-6·n² over 200 000 cases of these
    /// strategies (truncation `t²|X|²` and rounding `ε/t` together).
    #[test]
    fn dexp_is_the_left_jacobian_of_exp_f32(x in tangent(), d in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)) {
        let x = x.map(|v| v as f32);
        let d = Vector3::new(d.0 as f32, d.1 as f32, d.2 as f32);
        let (fd, jac) = left_jacobian_and_difference(&x, &d, 1e-2);
        let n = 1.0 + x.abs().max();
        prop_assert!((fd - jac).abs().max() <= 6e-5 * n * n, "{fd:?} vs {jac:?}");
    }

    /// `ExpCoefficients::dexp_transpose_mul_jacobian` is the derivative of `dexp_Xᵀ m` in `X`:
    /// against central differences with `t = 1e-6` (truncation `t²·|∂³|`, rounding `1e-16/t`),
    /// for every kind of twist (`ω` zero, tiny, small-angle series and closed forms).
    #[test]
    fn dexp_transpose_mul_jacobian_matches_central_difference(x in tangent(), m in (-10.0..10.0f64, -10.0..10.0f64, -10.0..10.0f64)) {
        let m = Vector3::new(m.0, m.1, m.2);
        let jac = ExpCoefficients::new(x.z).dexp_transpose_mul_jacobian(&x, &m);
        let t = 1e-6;
        for c in 0..3 {
            let mut d = Vector3::zeros();
            d[c] = t;
            let f = |y: Vector3<f64>| ExpCoefficients::new(y.z).dexp_transpose_mul(&y, &m);
            let fd = (f(x + d) - f(x - d)) / (2.0 * t);
            let err = (fd - jac.mul(&(d / t))).abs().max();
            prop_assert!(err <= 1e-8 * (1.0 + x.abs().max()) * (1.0 + m.abs().max()), "column {c}: {err:e}");
        }
    }

    /// `ExpCoefficients::dexp_transpose_mul` is `dexp_Xᵀ m`.
    #[test]
    fn dexp_transpose_mul_is_the_transpose(x in tangent(), m in (-10.0..10.0f64, -10.0..10.0f64, -10.0..10.0f64)) {
        let m = Vector3::new(m.0, m.1, m.2);
        let k = ExpCoefficients::new(x.z);
        let got = k.dexp_transpose_mul(&x, &m);
        prop_assert!((got - se2::dexp(&x).transpose() * m).abs().max() <= 1e-14 * 10.0 * (1.0 + x.abs().max()));
        prop_assert_eq!(se2::exp_with(&k, &x), se2::exp(&x));
    }
}

fn fact(n: i32) -> f64 {
    (1..=n).map(f64::from).product()
}

/// 10 000 random small steps (`|X|` up to 0.05 in f32 and f64) stay on the group:
/// `cos²θ + sin²θ = 1` to a few ulp, because `compose` renormalises the rotation.
#[test]
fn ten_thousand_random_small_steps_stay_on_the_group() {
    use proptest::test_runner::TestRng;
    let mut rng = TestRng::deterministic_rng(proptest::test_runner::RngAlgorithm::ChaCha);
    let mut g64 = Se2::<f64>::identity();
    let mut g32 = Se2::<f32>::identity();
    let (mut worst64, mut worst32) = (0.0f64, 0.0f64);
    for _ in 0..10_000 {
        let mut r = || (rng.next_u64() as f64 / u64::MAX as f64 - 0.5) * 0.1;
        let x = Vector3::new(r(), r(), r());
        g64 = g64 * se2::exp(&x);
        g32 = g32 * se2::exp(&x.map(|v| v as f32));
        worst64 = worst64.max((g64.cos() * g64.cos() + g64.sin() * g64.sin() - 1.0).abs());
        let (c, s) = (f64::from(g32.cos()), f64::from(g32.sin()));
        worst32 = worst32.max((c * c + s * s - 1.0).abs());
    }
    assert!(worst64 <= 4.0 * f64::EPSILON, "f64 drift {worst64:e}");
    assert!(
        worst32 <= 4.0 * f64::from(f32::EPSILON),
        "f32 drift {worst32:e}"
    );
    // And the stored angle is still a rotation angle: log/exp round trip holds at the end.
    assert!(se2_distance(&se2::exp(&g64.log()), &g64) <= 1e-13 * scale(&g64));
}
