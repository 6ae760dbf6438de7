//! The control law of the discrete maximum principle, run forward (MODEL.md §5).
//!
//! Unknowns: a constant spatial momentum `μ ∈ se(2)*` and the initial costate `ξ^{−1} ∈ R²`.
//! For each step `k`, given `α_k`, `g_k` and `ξ^{k−1}`:
//!
//! ```text
//! m_k = Ad_{g_k}ᵀ μ                              body-frame momentum
//! ζ^k = dexp_{X_k}ᵀ m_k,   X_k = −h A(α_k) u_k   (implicit in u_k, see below)
//! B_k = [ζ^kᵀ ∂A/∂α_i(α_k) e_j]_{ij}            so that ∇_α⟨ζ, A(α)u⟩ = B u
//! u_k = (I − h B_k)⁻¹ (ξ^{k−1} − A(α_k)ᵀ ζ^k)     i.e. the paper's u_k = ξ^k − A*(α_k) ζ^k
//! ξ^k = ξ^{k−1} + h B_k u_k
//! α_{k+1} = α_k + h u_k,   g_{k+1} = g_k exp(X_k)
//! ```
//!
//! `ζ^k` depends on `u_k` only through `dexp_{X_k}`, an `O(h|A u|) ≈ 1e-3` effect. Pass 0 takes
//! `ζ = m_k` and solves the 2×2 system for `u⁰`. Then a fixed number of passes,
//! [`Real::FIXED_POINT_PASSES`], of one of two kinds ([`Real::QUASI_NEWTON`]):
//! - plain fixed-point passes (`f32`, 2 passes): `ζ ← dexp_Xᵀ m_k` for the last `u`, solve
//!   again; each contracts by about `h|A||m|` (measured 6e-3 → 3e-5 → 2e-7);
//! - quasi-Newton passes (`f64`, 3 passes) on `R(u) = (I − hB(ζ(u)))u − ξ^{k−1} + Aᵀζ(u) = 0`:
//!   `u ← u − N·R(u)`, `N` the inverse of `∂R/∂u` at `u⁰` with `∂ζ/∂u` to first order in `X`
//!   (`dexp_X ≈ I + ½ad_X`); each contracts by about `|X|` times more (measured
//!   6e-3 → 3e-8 → 1.4e-13 → rounding). `ξ^k` then uses `ζ^k` of the final step.
//!
//! Both converge to the same `u_k`, the root of the law's equations. The work per step is
//! fixed: no loop runs to a tolerance.

use crate::kinematics::{Kinematics, State};
use crate::se2::{self, ExpCoefficients, Tangent};
use crate::swimmer::Connection;
use crate::{Error, Real};
use nalgebra::{Matrix3x2, Vector2, Vector3};

/// One step of the control law.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LawStep<T> {
    /// The control `u_k` (shape velocity, rad/s).
    pub u: Vector2<T>,
    /// The next state `(α_{k+1}, g_{k+1})`.
    pub next: State<T>,
    /// The costate `ξ^k`, to feed into step `k + 1`.
    pub xi: Vector2<T>,
}

impl<T: Real> Kinematics<T> {
    /// One step of the law with the type's fixed number of passes,
    /// [`Real::FIXED_POINT_PASSES`].
    ///
    /// Errors: [`Error::NonFinite`] for non-finite input or result, [`Error::ShapeLimit`]
    /// if `α_k` or `α_{k+1}` is at or past `|α_i| = π`, [`Error::Singular`] if
    /// `I − h B_k` is singular, [`Error::NotRotation`] as [`State::check`].
    #[inline]
    pub fn law_step(
        &self,
        state: &State<T>,
        xi_prev: &Vector2<T>,
        mu: &Vector3<T>,
    ) -> Result<LawStep<T>, Error> {
        self.law_step_with_passes(state, xi_prev, mu, T::FIXED_POINT_PASSES)
    }

    /// One step of the law with `passes` passes of the type's kind ([`Real::QUASI_NEWTON`];
    /// 0: `ζ = m_k`, no `dexp`). For measuring the residual the passes leave; use
    /// [`Kinematics::law_step`] otherwise.
    pub fn law_step_with_passes(
        &self,
        state: &State<T>,
        xi_prev: &Vector2<T>,
        mu: &Vector3<T>,
        passes: usize,
    ) -> Result<LawStep<T>, Error> {
        if !T::all_finite([xi_prev.x, xi_prev.y, mu.x, mu.y, mu.z]) {
            return Err(Error::NonFinite);
        }
        state.check()?;
        self.law_step_trusted(state, xi_prev, mu, passes)
    }

    /// [`Kinematics::law_step_with_passes`] for inputs already known to be valid: `state`
    /// passes [`State::check`], `ξ^{k−1}` and `μ` are finite (a [`crate::Replay`] knows
    /// this from its start checks and the previous step's output checks). Still checks
    /// every output, so it cannot return a non-finite or inadmissible result.
    #[inline]
    pub(crate) fn law_step_trusted(
        &self,
        state: &State<T>,
        xi_prev: &Vector2<T>,
        mu: &Vector3<T>,
        passes: usize,
    ) -> Result<LawStep<T>, Error> {
        let conn = self.swimmer().connection_unchecked(&state.alpha)?;
        let sc = Scaled::new(&conn, self.h());
        let m = state.g.adjoint_transpose_mul(mu);

        let mut zeta = m;
        let mut pass = 0;
        loop {
            // Pass `pass` (0: ζ = m_k): u = (I − hB)⁻¹ (ξ^{k−1} − Aᵀζ) by Cramer's rule.
            let (mut b11, mut b12, mut b21, mut b22) = sc.hb(&zeta);
            let (p11, p22) = (T::one() - b11, T::one() - b22);
            let inv = inverse_det(p11 * p22 - b12 * b21)?;
            let r = xi_prev - sc.at(&zeta);
            let mut u = Vector2::new((p22 * r.x + b12 * r.y) * inv, (p11 * r.y + b21 * r.x) * inv);
            let quasi_newton = T::QUASI_NEWTON && passes > 0;
            if quasi_newton {
                // From u⁰, all `passes` passes as quasi-Newton steps on R(u) = 0.
                u = sc.quasi_newton(&m, xi_prev, (p11, p22, b12, b21), u, passes)?;
                pass = passes;
            }
            let x = sc.twist(&u);
            let k = ExpCoefficients::new(x.z);
            if pass == passes {
                // ξ^k = ξ^{k−1} + hB u: for plain passes with the ζ that u was solved with,
                // for quasi-Newton with ζ^k = dexp_Xᵀ m_k of the final step.
                if quasi_newton {
                    (b11, b12, b21, b22) = sc.hb(&k.dexp_transpose_mul(&x, &m));
                }
                let xi = Vector2::new(
                    xi_prev.x + (b11 * u.x + b12 * u.y),
                    xi_prev.y + (b21 * u.x + b22 * u.y),
                );
                if !T::all_finite([u.x, u.y, xi.x, xi.y]) {
                    return Err(Error::NonFinite);
                }
                let next = self.advance(state, &u, &se2::exp_with(&k, &x))?;
                return Ok(LawStep { u, next, xi });
            }
            zeta = k.dexp_transpose_mul(&x, &m);
            pass += 1;
        }
    }
}

/// The connection scaled once per step: `h·∂A/∂α_i` (so the passes form `h·B` directly) and
/// `−h·A` (the twist).
struct Scaled<'a, T: Real> {
    a: &'a Matrix3x2<T>,
    d1: Matrix3x2<T>,
    d2: Matrix3x2<T>,
    nha: Matrix3x2<T>,
}

impl<'a, T: Real> Scaled<'a, T> {
    #[inline(always)]
    fn new(conn: &'a Connection<T>, h: T) -> Self {
        let [d1, d2] = conn.da.map(|d| d * h);
        Scaled {
            a: &conn.a,
            d1,
            d2,
            nha: conn.a * -h,
        }
    }

    /// `hB(ζ)_ij = ζᵀ h∂A/∂α_i e_j`, as `(b11, b12, b21, b22)`.
    #[inline(always)]
    fn hb(&self, z: &Vector3<T>) -> (T, T, T, T) {
        let (d1, d2) = (&self.d1, &self.d2);
        (
            z.x * d1.m11 + z.y * d1.m21 + z.z * d1.m31,
            z.x * d1.m12 + z.y * d1.m22 + z.z * d1.m32,
            z.x * d2.m11 + z.y * d2.m21 + z.z * d2.m31,
            z.x * d2.m12 + z.y * d2.m22 + z.z * d2.m32,
        )
    }

    /// `X = −hAu`.
    #[inline(always)]
    fn twist(&self, u: &Vector2<T>) -> Tangent<T> {
        let n = &self.nha;
        Tangent::new(
            n.m11 * u.x + n.m12 * u.y,
            n.m21 * u.x + n.m22 * u.y,
            n.m31 * u.x + n.m32 * u.y,
        )
    }

    /// `Aᵀζ`.
    #[inline(always)]
    fn at(&self, z: &Vector3<T>) -> Vector2<T> {
        let a = self.a;
        Vector2::new(
            a.m11 * z.x + a.m21 * z.y + a.m31 * z.z,
            a.m12 * z.x + a.m22 * z.y + a.m32 * z.z,
        )
    }

    /// `passes` quasi-Newton steps `u ← u − N·R(u)` from `u⁰` (see the module docs), given
    /// `m_k`, `ξ^{k−1}` and pass 0's `(1 − hB₁₁, 1 − hB₂₂, hB₁₂, hB₂₁)`.
    ///
    /// `N = (∂R/∂u)⁻¹` at `u⁰`: `∂R/∂u = I − hB + (Aᵀ − V)·∂ζ/∂u` with `V = [(h∂A/∂α_i u)ᵀ]_i`,
    /// and to first order in `X`, `ζ = m + ½ ad_Xᵀ m`, so `∂ζ/∂u ≈ ½ K(m)(−hA)` with
    /// `K(m) = [[0, 0, m_y], [0, 0, −m_x], [−m_y, m_x, 0]]`.
    #[inline(always)]
    fn quasi_newton(
        &self,
        m: &Vector3<T>,
        xi_prev: &Vector2<T>,
        (p11, p22, b12, b21): (T, T, T, T),
        u0: Vector2<T>,
        passes: usize,
    ) -> Result<Vector2<T>, Error> {
        let (a, d1, d2, nha) = (self.a, &self.d1, &self.d2, &self.nha);
        let (v1, v2) = (d1 * u0, d2 * u0);
        let (hx, hy) = (T::half() * m.x, T::half() * m.y);
        // ∂ζ/∂u by columns: (hy·n₃, −hx·n₃, hx·n₂ − hy·n₁), nᵢ the rows of −hA.
        let dz = |j: usize| {
            let (n1, n2, n3) = (nha[(0, j)], nha[(1, j)], nha[(2, j)]);
            Vector3::new(hy * n3, -(hx * n3), hx * n2 - hy * n1)
        };
        let (dz1, dz2) = (dz(0), dz(1));
        let g1 = Vector3::new(a.m11 - v1.x, a.m21 - v1.y, a.m31 - v1.z);
        let g2 = Vector3::new(a.m12 - v2.x, a.m22 - v2.y, a.m32 - v2.z);
        let (j11, j12) = (p11 + g1.dot(&dz1), g1.dot(&dz2) - b12);
        let (j21, j22) = (g2.dot(&dz1) - b21, p22 + g2.dot(&dz2));
        let inv = inverse_det(j11 * j22 - j12 * j21)?;
        let (n11, n12, n21, n22) = (j22 * inv, -(j12 * inv), -(j21 * inv), j11 * inv);
        let mut u = u0;
        for _ in 0..passes {
            let x = self.twist(&u);
            let z = ExpCoefficients::new(x.z).dexp_transpose_mul(&x, m);
            // R = (I − hB(ζ))u − ξ^{k−1} + Aᵀζ.
            let (b11, b12, b21, b22) = self.hb(&z);
            let atz = self.at(&z);
            let r1 = (u.x - (b11 * u.x + b12 * u.y)) - xi_prev.x + atz.x;
            let r2 = (u.y - (b21 * u.x + b22 * u.y)) - xi_prev.y + atz.y;
            u = Vector2::new(u.x - (n11 * r1 + n12 * r2), u.y - (n21 * r1 + n22 * r2));
        }
        Ok(u)
    }
}

/// `1/det`, or `Err(Singular)` for a determinant that is not finite or below `1e-6` in size.
#[inline(always)]
fn inverse_det<T: Real>(det: T) -> Result<T, Error> {
    if det.is_finite() && det.abs() > T::from_f64(1e-6) {
        Ok(T::one() / det)
    } else {
        Err(Error::Singular)
    }
}

#[cfg(test)]
mod tests {
    use crate::{Kinematics, Se2, State, Swimmer};
    use approx::assert_relative_eq;
    use nalgebra::{Vector2, Vector3};

    #[test]
    fn one_step_matches_model_test_vector() {
        let kin = Kinematics::new(Swimmer::<f64>::purcell(), 0.01).unwrap();
        let state = State {
            alpha: Vector2::new(0.3, -0.4),
            g: Se2::new(0.05, -0.02, 0.2),
        };
        let mu = Vector3::new(1.5, 13.2, 0.6);
        let s = kin
            .law_step(&state, &Vector2::new(0.01, -0.03), &mu)
            .unwrap();
        let eps = 1e-13;
        assert_relative_eq!(
            s.u,
            Vector2::new(-1.9485070881797708, 2.204985349281734),
            epsilon = eps
        );
        assert_relative_eq!(
            s.next.alpha,
            Vector2::new(0.2805149291182023, -0.37795014650718267),
            epsilon = eps
        );
        assert_relative_eq!(
            s.next.g.to_xytheta(),
            Vector3::new(
                0.04918563550870081,
                -0.013271901098288786,
                0.19942863681122489
            ),
            epsilon = eps
        );
        assert_relative_eq!(
            s.xi,
            Vector2::new(0.03179965609005496, -0.019447012540811347),
            epsilon = eps
        );
    }
}
