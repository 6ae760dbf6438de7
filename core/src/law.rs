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
//! `ζ^k` depends on `u_k` only through `dexp_{X_k}`, an `O(h|A u|) ≈ 1e-3` effect, so a fixed
//! number of fixed-point passes (`ζ ← m`, solve for `u`, `ζ ← dexp_Xᵀ m`, solve again, …)
//! reaches rounding level: [`Real::FIXED_POINT_PASSES`] (2 in f32, 5 in f64) counts the
//! `dexp` corrections. The work per step is fixed: no loop runs to a tolerance.

use crate::kinematics::{Kinematics, State};
use crate::se2::{self, ExpCoefficients, Tangent};
use crate::{Error, Real};
use nalgebra::{Vector2, Vector3};

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
    /// `I − h B_k` is singular.
    #[inline]
    pub fn law_step(
        &self,
        state: &State<T>,
        xi_prev: &Vector2<T>,
        mu: &Vector3<T>,
    ) -> Result<LawStep<T>, Error> {
        self.law_step_with_passes(state, xi_prev, mu, T::FIXED_POINT_PASSES)
    }

    /// One step of the law with `passes` `dexp` corrections (0: `ζ = m_k`, no `dexp`).
    /// For measuring the fixed-point residual; use [`Kinematics::law_step`] otherwise.
    pub fn law_step_with_passes(
        &self,
        state: &State<T>,
        xi_prev: &Vector2<T>,
        mu: &Vector3<T>,
        passes: usize,
    ) -> Result<LawStep<T>, Error> {
        let finite = |v: &[T]| v.iter().all(|x| x.is_finite());
        if !(finite(xi_prev.as_slice()) && finite(mu.as_slice())) {
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
        let h = self.h();
        let a = &conn.a;
        // Scaled once per step: h·∂A/∂α_i (so the loop forms h·B directly) and −h·A (the twist).
        let [d1, d2] = conn.da.map(|d| d * h);
        let nha = a * -h;
        let m = state.g.adjoint_transpose_mul(mu);

        let mut zeta = m;
        let mut pass = 0;
        loop {
            // hB_ij = ζᵀ h∂A/∂α_i e_j.
            let b11 = zeta.x * d1.m11 + zeta.y * d1.m21 + zeta.z * d1.m31;
            let b12 = zeta.x * d1.m12 + zeta.y * d1.m22 + zeta.z * d1.m32;
            let b21 = zeta.x * d2.m11 + zeta.y * d2.m21 + zeta.z * d2.m31;
            let b22 = zeta.x * d2.m12 + zeta.y * d2.m22 + zeta.z * d2.m32;
            // rhs = ξ^{k−1} − Aᵀζ.
            let r1 = xi_prev.x - (a.m11 * zeta.x + a.m21 * zeta.y + a.m31 * zeta.z);
            let r2 = xi_prev.y - (a.m12 * zeta.x + a.m22 * zeta.y + a.m32 * zeta.z);
            // u = (I − hB)⁻¹ rhs by Cramer's rule.
            let (p11, p22) = (T::one() - b11, T::one() - b22);
            let det = p11 * p22 - b12 * b21;
            if !(det.is_finite() && det.abs() > T::from_f64(1e-6)) {
                return Err(Error::Singular);
            }
            let inv = T::one() / det;
            let u = Vector2::new((p22 * r1 + b12 * r2) * inv, (p11 * r2 + b21 * r1) * inv);
            // X = −h A u.
            let x = Tangent::new(
                nha.m11 * u.x + nha.m12 * u.y,
                nha.m21 * u.x + nha.m22 * u.y,
                nha.m31 * u.x + nha.m32 * u.y,
            );
            let k = ExpCoefficients::new(x.z);
            if pass == passes {
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
