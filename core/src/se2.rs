//! The group SE(2) of planar rigid motions, its algebra and the maps between them.
//!
//! An element `g = (x, y, θ)` is the matrix `[[R(θ), p], [0, 1]]`; it is stored as
//! `(x, y, cos θ, sin θ)` (as in manif), so composing and acting need no trigonometry and the
//! angle is recovered by `atan2` only when asked. An algebra element (a twist) is
//! `X = (vx, vy, ω)` ([`Tangent`]). With `a = sin ω/ω`, `b = (1 − cos ω)/ω`:
//!
//! ```text
//! exp(X)  = (V(ω)·v, ω),   V(ω) = [[a, −b], [b, a]]
//! Ad_g    = [[cos θ, −sin θ, y], [sin θ, cos θ, −x], [0, 0, 1]]
//! ad_X    = [[0, −ω, vy], [ω, 0, −vx], [0, 0, 0]]
//! dexp_X  = Σ_{n≥0} ad_Xⁿ/(n+1)! = [[a, −b, q₁], [b, a, q₂], [0, 0, 1]],
//!           q = c₂·(vy, −vx) + ω·c₃·(vx, vy),  c₂ = (1 − cos ω)/ω²,  c₃ = (ω − sin ω)/ω³
//! ```
//!
//! `dexp_X` is the left Jacobian of `exp`: `exp(X + δ) = exp(dexp_X·δ)·exp(X) + O(|δ|²)`.
//!
//! Small angles: per-step twists here have `|ω| ≈ 1e-3…1e-2`, where `1 − cos ω` loses every
//! digit in f32. Below `|ω| = 0.01` ([`SMALL_ANGLE`]) all coefficients come from their Taylor
//! series in `ω²`, three terms in f64 (truncation ≤ 2e-16), two in f32 (≤ 8e-11; chosen by
//! [`Real::EPSILON`]), so no trigonometry and no division on the MCU; above, from the half angle (`1 − cos ω = 2 sin²(ω/2)`), which has
//! no cancellation. `c₃` keeps a longer series up to `|ω| = 0.5` ([`C3_SERIES_LIMIT`]).

use crate::Real;
use nalgebra::{Matrix3, Vector2, Vector3};

/// A twist `(vx, vy, ω)`: an element of the Lie algebra se(2) in body coordinates.
pub type Tangent<T> = Vector3<T>;

/// A planar rigid motion `(x, y, θ)`, stored as `(x, y, cos θ, sin θ)`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Se2<T> {
    x: T,
    y: T,
    c: T,
    s: T,
}

/// The scalar functions of `ω` that `exp` and `dexp` are made of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExpCoefficients<T> {
    /// `sin ω`.
    pub sin: T,
    /// `cos ω`.
    pub cos: T,
    /// `a = sin ω / ω`.
    pub a: T,
    /// `b = (1 − cos ω) / ω`.
    pub b: T,
    /// `c₂ = (1 − cos ω) / ω²`.
    pub c2: T,
    /// `c₃ = (ω − sin ω) / ω³`.
    pub c3: T,
}

/// Below this `|ω|` every coefficient is a three-term Taylor series in `ω²`.
pub const SMALL_ANGLE: f64 = 0.01;
/// Below this `|ω|`, `c₃ = (ω − sin ω)/ω³` keeps its series (the closed form cancels).
pub const C3_SERIES_LIMIT: f64 = 0.5;

/// `1 − z/d₁·(1 − z/d₂·(…))`: the nested form of an alternating Taylor series in `z = ω²`.
#[inline(always)]
fn alternating_series<T: Real>(z: T, divisors: &[f64]) -> T {
    let mut acc = T::one();
    for &d in divisors.iter().rev() {
        acc = T::one() - z * T::from_f64(1.0 / d) * acc;
    }
    acc
}

/// `c₀ + c₁z + c₂z²` in `z = ω² < 1e-4` with as many terms as the type needs. For the series
/// here (the coefficients' and their derivatives') the third term is below 1e-9 of the first
/// and the first omitted one below 2e-16, so f32 ([`Real::EPSILON`] ≥ 1e-10) keeps two terms
/// and f64 three.
#[inline(always)]
fn small_angle_series<T: Real>(z: T, [c0, c1, c2]: [f64; 3]) -> T {
    let tail = if T::EPSILON < 1e-10 {
        T::from_f64(c1) + z * T::from_f64(c2)
    } else {
        T::from_f64(c1)
    };
    T::from_f64(c0) + z * tail
}

impl<T: Real> ExpCoefficients<T> {
    /// Coefficients at angle `ω`, accurate to rounding for every `ω` (see the module docs).
    /// The small-angle series is inlined (it is what a control step takes); the rest is not.
    #[inline(always)]
    pub fn new(w: T) -> Self {
        let z = w * w;
        if w.abs() >= T::from_f64(SMALL_ANGLE) {
            return Self::not_small(w, z);
        }
        let a = small_angle_series(z, [1.0, -1.0 / 6.0, 1.0 / 120.0]);
        let c2 = small_angle_series(z, [0.5, -1.0 / 24.0, 1.0 / 720.0]);
        let c3 = small_angle_series(z, [1.0 / 6.0, -1.0 / 120.0, 1.0 / 5040.0]);
        let b = w * c2;
        ExpCoefficients {
            sin: w * a,
            cos: T::one() - w * b,
            a,
            b,
            c2,
            c3,
        }
    }

    /// [`ExpCoefficients::new`] for `|ω| ≥ SMALL_ANGLE`.
    #[inline(never)]
    fn not_small(w: T, z: T) -> Self {
        let aw = w.abs();
        let half_w = T::half() * w;
        let (sh, ch) = half_w.sin_cos();
        let sinc_h = sh / half_w;
        let two = T::from_f64(2.0);
        let sin = two * sh * ch;
        let c3 = if aw < T::from_f64(C3_SERIES_LIMIT) {
            // Σ (−1)ᵏ zᵏ/(2k+3)!, truncation < 2e-19 relative for |ω| < 0.5.
            T::from_f64(1.0 / 6.0) * alternating_series(z, &[20.0, 42.0, 72.0, 110.0, 156.0, 210.0])
        } else {
            (w - sin) / (z * w)
        };
        ExpCoefficients {
            sin,
            cos: T::one() - two * sh * sh,
            a: sinc_h * ch,
            b: sinc_h * sh,
            c2: T::half() * sinc_h * sinc_h,
            c3,
        }
    }

    /// `dexp_Xᵀ·m` for the twist `X` these coefficients were made for (see the module docs):
    /// `(a·m_x + b·m_y, a·m_y − b·m_x, c₂·P + c₃·ωQ + m_z)` with `P = v_y m_x − v_x m_y`,
    /// `Q = v_x m_x + v_y m_y` (the last component is `q·(m_x, m_y) + m_z`).
    #[inline]
    pub fn dexp_transpose_mul(&self, x: &Tangent<T>, m: &Vector3<T>) -> Vector3<T> {
        let (p, q) = (x.y * m.x - x.x * m.y, x.x * m.x + x.y * m.y);
        Vector3::new(
            self.a * m.x + self.b * m.y,
            self.a * m.y - self.b * m.x,
            self.c2 * p + self.c3 * (x.z * q) + m.z,
        )
    }

    /// `∂(dexp_Xᵀ·m)/∂X` for the twist these coefficients were made for. Uses the
    /// coefficients' derivatives `a' = (cos ω − a)/ω`, `b' = a − c₂`, `c₂' = (a − 2c₂)/ω`,
    /// `c₃' = (c₂ − 3c₃)/ω`, from their series below [`SMALL_ANGLE`] (truncated as in
    /// [`ExpCoefficients::new`]).
    #[inline(always)]
    pub fn dexp_transpose_mul_jacobian(
        &self,
        x: &Tangent<T>,
        m: &Vector3<T>,
    ) -> DexpTransposeJacobian<T> {
        let w = x.z;
        let (da, dc2, dc3) = if w.abs() < T::from_f64(SMALL_ANGLE) {
            // ω·Σ_{k≥1} (−1)ᵏ 2k z^{k−1}/(2k+d)! for d = 1, 2, 3.
            let z = w * w;
            (
                w * small_angle_series(z, [-1.0 / 3.0, 1.0 / 30.0, -1.0 / 840.0]),
                w * small_angle_series(z, [-1.0 / 12.0, 1.0 / 180.0, -1.0 / 6720.0]),
                w * small_angle_series(z, [-1.0 / 60.0, 1.0 / 1260.0, -1.0 / 60480.0]),
            )
        } else {
            let two = T::from_f64(2.0);
            (
                (self.cos - self.a) / w,
                (self.a - two * self.c2) / w,
                (self.c2 - T::from_f64(3.0) * self.c3) / w,
            )
        };
        let db = self.a - self.c2;
        let (p, q) = (x.y * m.x - x.x * m.y, x.x * m.x + x.y * m.y);
        let wc3 = w * self.c3;
        DexpTransposeJacobian {
            d_omega: Vector3::new(
                da * m.x + db * m.y,
                da * m.y - db * m.x,
                dc2 * p + (self.c3 + w * dc3) * q,
            ),
            dz_dv: (wc3 * m.x - self.c2 * m.y, self.c2 * m.x + wc3 * m.y),
        }
    }

    /// The translation column `q` of `dexp_X`.
    #[inline(always)]
    fn dexp_column(&self, x: &Tangent<T>) -> (T, T) {
        let wc3 = x.z * self.c3;
        (self.c2 * x.y + wc3 * x.x, wc3 * x.y - self.c2 * x.x)
    }
}

/// `∂(dexp_Xᵀ·m)/∂X` by its nonzero parts: only the last component of `dexp_Xᵀ·m` depends on
/// `(v_x, v_y)`; all three depend on `ω`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DexpTransposeJacobian<T> {
    /// `∂(dexp_Xᵀ·m)/∂ω`.
    pub d_omega: Vector3<T>,
    /// `∂(dexp_Xᵀ·m)_z/∂(v_x, v_y)`.
    pub dz_dv: (T, T),
}

impl<T: Real> DexpTransposeJacobian<T> {
    /// The derivative along `dX`: `∂(dexp_Xᵀ·m)/∂X · dX`.
    #[inline(always)]
    pub fn mul(&self, dx: &Tangent<T>) -> Vector3<T> {
        let mut d = self.d_omega * dx.z;
        d.z += self.dz_dv.0 * dx.x + self.dz_dv.1 * dx.y;
        d
    }
}

/// `exp(X)`.
#[inline]
pub fn exp<T: Real>(x: &Tangent<T>) -> Se2<T> {
    let k = ExpCoefficients::new(x.z);
    exp_with(&k, x)
}

/// `exp(X)` from coefficients already computed for `X.z`.
#[inline]
pub fn exp_with<T: Real>(k: &ExpCoefficients<T>, x: &Tangent<T>) -> Se2<T> {
    Se2 {
        x: k.a * x.x - k.b * x.y,
        y: k.b * x.x + k.a * x.y,
        c: k.cos,
        s: k.sin,
    }
}

/// `dexp_X = Σ ad_Xⁿ/(n+1)!`, the left Jacobian of `exp`.
pub fn dexp<T: Real>(x: &Tangent<T>) -> Matrix3<T> {
    let k = ExpCoefficients::new(x.z);
    let (q1, q2) = k.dexp_column(x);
    let (z, o) = (T::zero(), T::one());
    Matrix3::new(k.a, -k.b, q1, k.b, k.a, q2, z, z, o)
}

/// `ad_X = [[0, −ω, vy], [ω, 0, −vx], [0, 0, 0]]`: `ad_X·Y` is the Lie bracket `[X, Y]`.
pub fn ad<T: Real>(x: &Tangent<T>) -> Matrix3<T> {
    let z = T::zero();
    Matrix3::new(z, -x.z, x.y, x.z, z, -x.x, z, z, z)
}

impl<T: Real> Se2<T> {
    /// The identity `(0, 0, 0)`.
    pub fn identity() -> Self {
        Se2 {
            x: T::zero(),
            y: T::zero(),
            c: T::one(),
            s: T::zero(),
        }
    }

    /// The motion `(x, y, θ)`.
    pub fn new(x: T, y: T, theta: T) -> Self {
        let (s, c) = theta.sin_cos();
        Se2 { x, y, c, s }
    }

    /// The motion with translation `(x, y)` and rotation `(cos θ, sin θ)` given directly, as
    /// read back from [`Se2::cos`] and [`Se2::sin`] (say of an `f64` motion rounded to `f32`),
    /// so a stored motion comes back bit for bit. `(cos, sin)` must have unit length to
    /// rounding; [`Se2::compose`] keeps it there from then on.
    pub fn from_rotation(x: T, y: T, cos: T, sin: T) -> Self {
        Se2 {
            x,
            y,
            c: cos,
            s: sin,
        }
    }

    /// Translation `x`.
    pub fn x(&self) -> T {
        self.x
    }
    /// Translation `y`.
    pub fn y(&self) -> T {
        self.y
    }
    /// `cos θ`.
    pub fn cos(&self) -> T {
        self.c
    }
    /// `sin θ`.
    pub fn sin(&self) -> T {
        self.s
    }
    /// Rotation angle `θ ∈ ]−π, π]`.
    pub fn theta(&self) -> T {
        let t = self.s.atan2(self.c);
        if t <= -T::pi() { T::pi() } else { t }
    }
    /// `(x, y, θ)` with `θ ∈ ]−π, π]`.
    pub fn to_xytheta(&self) -> Vector3<T> {
        Vector3::new(self.x, self.y, self.theta())
    }

    /// Whether every stored number is finite.
    pub fn is_finite(&self) -> bool {
        T::all_finite([self.x, self.y, self.c, self.s])
    }

    /// `self · other`, with the rotation part renormalised to first order
    /// (`(c, s) ← (c, s)·(3 − c² − s²)/2`) so it stays on the group over long products.
    /// Always inlined: a replay's two law steps (free and on a joint-limit arc) both call it.
    #[inline(always)]
    pub fn compose(&self, other: &Self) -> Self {
        let c = self.c * other.c - self.s * other.s;
        let s = self.s * other.c + self.c * other.s;
        let k = T::half() * (T::from_f64(3.0) - (c * c + s * s));
        Se2 {
            x: self.x + self.c * other.x - self.s * other.y,
            y: self.y + self.s * other.x + self.c * other.y,
            c: c * k,
            s: s * k,
        }
    }

    /// `g⁻¹ = (−Rᵀp, −θ)`.
    pub fn inverse(&self) -> Self {
        Se2 {
            x: -(self.c * self.x + self.s * self.y),
            y: self.s * self.x - self.c * self.y,
            c: self.c,
            s: -self.s,
        }
    }

    /// `g⁻¹ · other`.
    pub fn between(&self, other: &Self) -> Self {
        self.inverse().compose(other)
    }

    /// The action on a point: `R p' + p`.
    pub fn act(&self, p: &Vector2<T>) -> Vector2<T> {
        Vector2::new(
            self.x + self.c * p.x - self.s * p.y,
            self.y + self.s * p.x + self.c * p.y,
        )
    }

    /// `log(g)`: the twist `X` with `exp(X) = g` and `ω = θ ∈ ]−π, π]`.
    pub fn log(&self) -> Tangent<T> {
        let w = self.theta();
        let k = ExpCoefficients::new(w);
        // V⁻¹ = [[a, b], [−b, a]]/(a² + b²); a² + b² = sinc²(ω/2) ≥ 4/π² on ]−π, π].
        let d = T::one() / (k.a * k.a + k.b * k.b);
        Vector3::new(
            d * (k.a * self.x + k.b * self.y),
            d * (k.a * self.y - k.b * self.x),
            w,
        )
    }

    /// `Ad_g`, so that `g·exp(X)·g⁻¹ = exp(Ad_g·X)`.
    pub fn adjoint(&self) -> Matrix3<T> {
        let (z, o) = (T::zero(), T::one());
        Matrix3::new(self.c, -self.s, self.y, self.s, self.c, -self.x, z, z, o)
    }

    /// `Ad_gᵀ·μ`: a spatial momentum `μ ∈ se(2)*` seen in the body frame.
    #[inline]
    pub fn adjoint_transpose_mul(&self, mu: &Vector3<T>) -> Vector3<T> {
        Vector3::new(
            self.c * mu.x + self.s * mu.y,
            self.c * mu.y - self.s * mu.x,
            self.y * mu.x - self.x * mu.y + mu.z,
        )
    }
}

impl<T: Real> core::ops::Mul for Se2<T> {
    type Output = Se2<T>;
    fn mul(self, rhs: Self) -> Self {
        self.compose(&rhs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn exp_matches_model_test_vectors() {
        let g = exp(&Vector3::new(1.0, 2.0, 0.7));
        assert_relative_eq!(
            g.to_xytheta(),
            Vector3::new(0.24843151686666864, 2.176561695986991, 0.7),
            epsilon = 1e-14
        );
        let g = exp(&Vector3::new(0.3, -0.2, 1e-6));
        assert_relative_eq!(
            g.to_xytheta(),
            Vector3::new(0.30000009999995, -0.19999984999996667, 1e-6),
            epsilon = 1e-16
        );
    }

    #[test]
    fn coefficient_branches_agree_at_the_switch() {
        for w in [SMALL_ANGLE, C3_SERIES_LIMIT] {
            let lo = ExpCoefficients::new(w * (1.0 - 1e-15));
            let hi = ExpCoefficients::new(w);
            for (p, q) in [
                (lo.a, hi.a),
                (lo.b, hi.b),
                (lo.c2, hi.c2),
                (lo.c3, hi.c3),
                (lo.sin, hi.sin),
                (lo.cos, hi.cos),
            ] {
                assert_relative_eq!(p, q, max_relative = 1e-13);
            }
        }
    }
}
