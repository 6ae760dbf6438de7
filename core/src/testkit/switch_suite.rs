//! One property suite over a scalar type (`f32`, `f64` in `core/tests/it/switches.rs`; the
//! solver's dual numbers in `host-sim/purcell-solver/tests/it/switches.rs`): the SE(2)
//! coefficients the law and the KKT certificate evaluate, on both sides of every small-angle
//! switch ([`crate::se2::SMALL_ANGLE`], [`crate::se2::C3_SERIES_LIMIT`]), against their Taylor
//! series summed in f64 (independent of the switches). Each check returns its error in units
//! of the type's [`Real::EPSILON`], for bounds per precision.

use crate::se2::{self, ExpCoefficients};
use crate::testkit::strategies::angle_across_switches;
use crate::{Real, Tangent};
use nalgebra::Vector3;
use proptest::prelude::*;

/// A twist `[vx, vy, ω]` with `|v_i| < 5` and `ω` on either side of a switch
/// ([`angle_across_switches`]).
pub fn twist_across_switches() -> impl Strategy<Value = [f64; 3]> {
    (-5.0..5.0f64, -5.0..5.0f64, angle_across_switches()).prop_map(|(x, y, w)| [x, y, w])
}

/// A momentum `m` with components in `]−10, 10[`, for `dexp_Xᵀ m`.
pub fn momentum() -> impl Strategy<Value = [f64; 3]> {
    (-10.0..10.0f64, -10.0..10.0f64, -10.0..10.0f64).prop_map(|(a, b, c)| [a, b, c])
}

/// `Ok` if each of the six errors ([`coefficients`]' order) is within its bound, else the
/// failing case with the coefficient's index and error.
pub fn within(errors: [f64; 6], bounds: [f64; 6]) -> Result<(), TestCaseError> {
    for (i, (e, bound)) in errors.iter().zip(bounds).enumerate() {
        prop_assert!(*e <= bound, "coefficient {i}: {e} eps");
    }
    Ok(())
}

/// The coefficients of `exp`/`dexp` at `ω` and their derivatives in `ω`, by their Taylor
/// series (30 terms: to rounding for `|ω| ≤ 1`).
#[derive(Clone, Copy, Debug)]
pub struct Series {
    /// `a = sin ω / ω`.
    pub a: f64,
    /// `b = (1 − cos ω) / ω`.
    pub b: f64,
    /// `c₂ = (1 − cos ω) / ω²`.
    pub c2: f64,
    /// `c₃ = (ω − sin ω) / ω³`.
    pub c3: f64,
    /// `da/dω`.
    pub da: f64,
    /// `db/dω`.
    pub db: f64,
    /// `dc₂/dω`.
    pub dc2: f64,
    /// `dc₃/dω`.
    pub dc3: f64,
}

/// `Σ_k (−1)ᵏ ω^{2k+odd} / (2k+shift)!` and its derivative in `ω`.
fn sum(w: f64, shift: i32, odd: i32) -> (f64, f64) {
    let fact = |n: i32| (1..=n).map(f64::from).product::<f64>();
    let (mut f, mut df) = (0.0, 0.0);
    for k in (0..30).rev() {
        let p = 2 * k + odd;
        let s = if k % 2 == 0 { 1.0 } else { -1.0 } / fact(2 * k + shift);
        f += s * w.powi(p);
        if p > 0 {
            df += s * f64::from(p) * w.powi(p - 1);
        }
    }
    (f, df)
}

/// The coefficients at `ω` and their derivatives, by their series.
pub fn series(w: f64) -> Series {
    let (a, da) = sum(w, 1, 0);
    let (b, db) = sum(w, 2, 1);
    let (c2, dc2) = sum(w, 2, 0);
    let (c3, dc3) = sum(w, 3, 0);
    Series {
        a,
        b,
        c2,
        c3,
        da,
        db,
        dc2,
        dc3,
    }
}

/// `x` rounded to `T` and back.
pub fn rounded<T: Real>(x: f64) -> f64 {
    T::from_f64(x).to_f64()
}

/// Relative errors of `a, b, c₂, c₃, sin ω, cos ω` at `ω` (rounded to `T`), in `ε_T`.
pub fn coefficients<T: Real>(w: f64) -> [f64; 6] {
    let k = ExpCoefficients::new(T::from_f64(w));
    let w = rounded::<T>(w);
    let s = series(w);
    [
        (k.a, s.a),
        (k.b, s.b),
        (k.c2, s.c2),
        (k.c3, s.c3),
        (k.sin, w * s.a),
        (k.cos, 1.0 - w * s.b),
    ]
    .map(|(got, want)| (got.to_f64() - want).abs() / want.abs() / T::EPSILON)
}

/// `exp(X)` against `(a v_x − b v_y, b v_x + a v_y, ω)` from the series, in `ε_T` relative to
/// `1 + |X|_∞`.
pub fn exp<T: Real>(x: [f64; 3]) -> f64 {
    let g = se2::exp(&Tangent::new(
        T::from_f64(x[0]),
        T::from_f64(x[1]),
        T::from_f64(x[2]),
    ));
    let [vx, vy, w] = x.map(rounded::<T>);
    let s = series(w);
    let want = [
        s.a * vx - s.b * vy,
        s.b * vx + s.a * vy,
        1.0 - w * s.b,
        w * s.a,
    ];
    let got = [g.x(), g.y(), g.cos(), g.sin()].map(|v| v.to_f64());
    let scale = 1.0 + vx.abs().max(vy.abs()).max(w.abs());
    got.iter()
        .zip(want)
        .map(|(g, w)| (g - w).abs())
        .fold(0.0, f64::max)
        / (scale * T::EPSILON)
}

/// `dexp_Xᵀ m` and its derivative in `ω` ([`ExpCoefficients::dexp_transpose_mul`] and
/// `…_jacobian`, which the law and the KKT certificate evaluate) against the series, in `ε_T`
/// relative to `|m|_∞ (1 + |v|_∞)`, and that over `|ω|` for the derivative at and above
/// [`se2::SMALL_ANGLE`] (its closed forms divide a difference of `O(1)` terms by `ω`).
pub fn dexp_transpose<T: Real>(x: [f64; 3], m: [f64; 3]) -> f64 {
    let t = |v: f64| T::from_f64(v);
    let xt = Tangent::new(t(x[0]), t(x[1]), t(x[2]));
    let mt = Vector3::new(t(m[0]), t(m[1]), t(m[2]));
    let k = ExpCoefficients::new(xt.z);
    let value = k.dexp_transpose_mul(&xt, &mt);
    let jac = k.dexp_transpose_mul_jacobian(&xt, &mt);
    let [vx, vy, w] = x.map(rounded::<T>);
    let [mx, my, mz] = m.map(rounded::<T>);
    let s = series(w);
    let (p, q) = (vy * mx - vx * my, vx * mx + vy * my);
    let want_value = [
        s.a * mx + s.b * my,
        s.a * my - s.b * mx,
        s.c2 * p + s.c3 * w * q + mz,
    ];
    let want_d = [
        s.da * mx + s.db * my,
        s.da * my - s.db * mx,
        s.dc2 * p + (s.c3 + w * s.dc3) * q,
    ];
    let scale = mx.abs().max(my.abs()).max(mz.abs()) * (1.0 + vx.abs().max(vy.abs()));
    let err = |got: Vector3<T>, want: [f64; 3]| {
        (0..3)
            .map(|i| (got[i].to_f64() - want[i]).abs())
            .fold(0.0, f64::max)
    };
    let d_scale = if w.abs() >= se2::SMALL_ANGLE {
        scale / w.abs()
    } else {
        scale
    };
    (err(value, want_value) / scale).max(err(jac.d_omega, want_d) / d_scale) / T::EPSILON
}
