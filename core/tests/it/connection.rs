//! The local connection `A(α)` of MODEL.md §2 and its closed-form derivatives.

use crate::common;

use common::*;
use nalgebra::{Matrix3x2, Vector2};
use proptest::prelude::*;
use purcell_core::Swimmer;

/// Random valid parameters: link lengths 0.3–2, drag 0.1–10, ratio 0.5–4.
fn swimmer() -> impl Strategy<Value = Swimmer<f64>> {
    (
        (0.3..2.0f64, 0.3..2.0f64, 0.3..2.0f64),
        0.1..10.0f64,
        0.5..4.0f64,
    )
        .prop_map(|((l0, l1, l2), k, r)| Swimmer::new([l0, l1, l2], k, r).unwrap())
}

fn max_abs(m: &Matrix3x2<f64>) -> f64 {
    m.abs().max()
}

proptest! {
    #![proptest_config(proptest_config())]

    /// `∂A/∂αᵢ` equals the central difference `(A(α + tεᵢ) − A(α − tεᵢ))/2t`, `t = 1e-6`
    /// (truncation `t²/6·|∂³A| ≲ 1e-11`, rounding `1e-16/t = 1e-10`).
    #[test]
    fn connection_derivative_matches_central_difference(sw in swimmer(), alpha in alpha()) {
        let c = sw.connection_with_derivatives(&alpha).unwrap();
        let t = 1e-6;
        for (i, e) in [Vector2::new(t, 0.0), Vector2::new(0.0, t)].iter().enumerate() {
            let fd = (sw.connection(&(alpha + e)).unwrap() - sw.connection(&(alpha - e)).unwrap()) / (2.0 * t);
            let err = max_abs(&(fd - c.da[i]));
            prop_assert!(err <= 1e-8 * (1.0 + max_abs(&c.da[i])), "∂A/∂α{}: {err:e}", i + 1);
        }
    }

    /// `A` from `connection` and from `connection_with_derivatives` are the same numbers.
    #[test]
    fn connection_is_the_same_with_or_without_derivatives(sw in swimmer(), alpha in alpha()) {
        prop_assert_eq!(sw.connection(&alpha).unwrap(), sw.connection_with_derivatives(&alpha).unwrap().a);
    }

    /// The drag coefficient `k` scales all forces and cancels: `A` does not depend on it.
    #[test]
    fn connection_does_not_depend_on_drag_coefficient(sw in swimmer(), k in 0.01..100.0f64, alpha in alpha()) {
        let other = Swimmer::new(sw.lengths(), k, sw.ratio()).unwrap();
        let (a, b) = (sw.connection(&alpha).unwrap(), other.connection(&alpha).unwrap());
        prop_assert!(max_abs(&(a - b)) <= 1e-14 * (1.0 + max_abs(&a)));
    }

    /// Dimensional analysis: scaling every length by `s` scales the translational rows
    /// (x, y) of `A` by `s` and leaves the rotational row (θ) alone.
    #[test]
    fn connection_scales_with_length(sw in swimmer(), s in 0.1..10.0f64, alpha in alpha()) {
        let [l0, l1, l2] = sw.lengths();
        let big = Swimmer::new([s * l0, s * l1, s * l2], sw.drag(), sw.ratio()).unwrap();
        let (a, b) = (sw.connection(&alpha).unwrap(), big.connection(&alpha).unwrap());
        let want = Matrix3x2::from_fn(|i, j| if i < 2 { s * a[(i, j)] } else { a[(i, j)] });
        prop_assert!(max_abs(&(b - want)) <= 1e-13 * (1.0 + max_abs(&want)));
    }

    /// Mirror symmetry of the symmetric swimmer (`L1 = L2`): reflecting the body across its
    /// y-axis swaps the links, `(α1, α2) → (−α2, −α1)`, and maps `ξ = (vx, vy, ω)` to
    /// `S ξ = (−vx, vy, −ω)`; so `A(α) = −S·A(α')·P` with `P` the swap of the columns.
    #[test]
    fn connection_is_mirror_symmetric_for_equal_outer_links(l0 in 0.3..2.0f64, l in 0.3..2.0f64, r in 0.5..4.0f64, alpha in alpha()) {
        let sw = Swimmer::new([l0, l, l], 1.0, r).unwrap();
        let a = sw.connection(&alpha).unwrap();
        let m = sw.connection(&Vector2::new(-alpha.y, -alpha.x)).unwrap();
        let sign = [-1.0, 1.0, -1.0];
        let want = Matrix3x2::from_fn(|i, j| -sign[i] * m[(i, 1 - j)]);
        prop_assert!(max_abs(&(a - want)) <= 1e-14 * (1.0 + max_abs(&a)), "{a}\n{want}");
    }

    /// Reflection across the body's x-axis (any lengths): `α → −α`,
    /// `(vx, vy, ω) → (vx, −vy, −ω)`, so `A(α) = −diag(1, −1, −1)·A(−α)`.
    #[test]
    fn connection_is_symmetric_under_reflection_across_the_body_axis(sw in swimmer(), alpha in alpha()) {
        let a = sw.connection(&alpha).unwrap();
        let m = sw.connection(&-alpha).unwrap();
        let sign = [1.0, -1.0, -1.0];
        let want = Matrix3x2::from_fn(|i, j| -sign[i] * m[(i, j)]);
        prop_assert!(max_abs(&(a - want)) <= 1e-14 * (1.0 + max_abs(&a)), "{a}\n{want}");
    }

    /// The f32 connection agrees with the f64 one to rounding over the admissible shapes
    /// (κ(W_ξ) ≤ ~30 for |α| ≤ 3, so ≤ 4κε of max|A|; see `vectors.rs` for the derivation).
    #[test]
    fn connection_f32_agrees_with_f64(alpha in alpha()) {
        let a64 = Swimmer::<f64>::purcell().connection_with_derivatives(&alpha).unwrap();
        let a32 = Swimmer::<f32>::purcell().connection_with_derivatives(&alpha.map(|v| v as f32)).unwrap();
        let eps = f64::from(f32::EPSILON);
        let input = 0.5 * eps * alpha.abs().max() * (max_abs(&a64.da[0]) + max_abs(&a64.da[1]));
        let err = max_abs(&(a32.a.map(f64::from) - a64.a));
        prop_assert!(err <= 120.0 * eps * max_abs(&a64.a) + input, "{err:e}");
    }
}
