//! The power the fluid dissipates, `ℓ = h/2·uᵀG(α)u` (MODEL.md §11), in the law.
//!
//! **The metric from the step's frame.** `G = k·(R_uu − W_αᵀA)` with `R_uu = diag(w₁, w₂)`,
//! `w_i = r·L_i³/3` (an outer link turning about its hinge: `r·k·L(L/2)² + r·k·L³/12`), and
//! `W_αᵀA = W_αᵀW_ξ⁻¹W_α` symmetric. Its derivative, with the brackets `E_i = ∂W_α/∂α_i −
//! ∂W_ξ/∂α_i·A` of [`crate::swimmer`] and `∂W_α/∂α_i = σ_iρ_iτ_i e_iᵀ`, is
//! `∂G/∂α_i = −k·(∂W_α/∂α_iᵀA + AᵀE_i)`. The frame writes each bracket's column as
//! `E_ie_j = κ_it_ij·ν_i + q_ij·τ_i − η_it_ij·e₃` with `t_ij = τ_i·a_j` and
//! `q_ij = κ_iν_i·a_j − η_ia_{j,z} + δ_ijσ_iρ_i`, so `a_l·E_ie_j = t_ij(q_il − δ_ilσ_iρ_i) +
//! q_ij t_il`, and entry `(j, l)` of `∂G/∂α_i` collapses to products of the frame's `t`, `q`:
//!
//! ```text
//! ∂G/∂α_i = −k·[[2t_i1q_i1, t_i1q_i2 + t_i2q_i1], [t_i1q_i2 + t_i2q_i1, 2t_i2q_i2]]
//! ```
//!
//! (symmetric, as `G` is), with `c_i = uᵀ∂G/∂α_i u`: no trigonometry and no dot product beyond
//! the frame's, once per step (`h∂G/∂α_i`); `∂G/∂α_i u` is then a 2×2 product at each `u` the
//! step tries.
//!
//! **The law.** Step `k` solves `R(u) = (G − hB(ζ(u)))u − (h/2)c(u) − ξ^{k−1} + Aᵀζ(u) = 0`;
//! `c` is quadratic in `u` (`∂c_i/∂u = 2(∂G/∂α_i u)ᵀ`, written `2D(u)`), and enters with `h`:
//!
//! 1. **First iterate**: the effort's, with `G` in place of `I` (`c` has no linear part at
//!    `u = 0`): `M = G − hB(m) − (h/2)κJ`, `u⁰ = M⁻¹(ξ^{k−1} − Aᵀm)`; then one Newton step on
//!    `c` with `ζ` still linear: `u¹ = u⁰ + (M − hD(u⁰))⁻¹(h/2)c(u⁰)`. Without it the first
//!    iterate misses `(h/2)c`, about `5e-3` of `G u`; with it, the effort's first-iterate
//!    error is what is left (`cargo test -p purcell-core --test it power_law:: -- --nocapture`).
//! 2. **Plain pass** (`f32`): `ζ(u)`, then `c` linearised at `u`:
//!    `(G − hB(ζ) − hD(u))u' = ξ^{k−1} − Aᵀζ − (h/2)c(u)`.
//! 3. **Newton pass** (`f64`): the effort's Jacobian with `G` for `I` and `−hD(u)` added, the
//!    residual `Gu − (h/2)c(u) − ξ^{k−1} + (Aᵀ − V(u))ζ`.
//!
//! Each returns `ξ^k = ξ^{k−1} + hB(ζ)u' + (h/2)c(u')` with `(h/2)c(u') = hD(u)u' − (h/2)c(u)`
//! up to `O(|u' − u|²)`. On an arc (MODEL.md §11, "Joint limits") the resting joint's costate
//! is `ξ^k_i = (Gu)_i + (Aᵀζ^k)_i`.

use crate::cost::CostLaw;
use crate::law::{Equation, Law, Mat2, NewtonAt, Pass, Rows, Step, mul};
use crate::swimmer::Swimmer;
use crate::{Passes, Real};
use nalgebra::Vector2;

/// The power the fluid dissipates as a [`crate::cost::RunningCost`] ([`crate::Cost::Power`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct Power;

impl<T: Real> CostLaw<T> for Power {
    type Law = PowerLaw<T>;
    const PASSES: Passes = T::POWER_PASSES;
    #[inline(always)]
    fn law(swimmer: &Swimmer<T>) -> PowerLaw<T> {
        PowerLaw::new(swimmer)
    }
}

/// The power of a swimmer of drag coefficient `k` (it scales `G`, and so the costate).
#[derive(Clone, Copy, Debug)]
pub(crate) struct PowerLaw<T> {
    drag: T,
}

impl<T: Real> PowerLaw<T> {
    /// The power of `swimmer`.
    #[inline(always)]
    pub(crate) fn new(swimmer: &Swimmer<T>) -> Self {
        PowerLaw {
            drag: swimmer.drag(),
        }
    }
}

/// The power at one step: `G(α_k)` and `h·∂G/∂α_i(α_k)`, each symmetric, `(m11, m12, m12, m22)`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PowerStep<T> {
    g: Mat2<T>,
    hdg: [Mat2<T>; 2],
}

impl<T: Real> Law<T> for PowerLaw<T> {
    type Step = PowerStep<T>;

    #[inline(always)]
    fn at(self, eq: &Equation<T>) -> PowerStep<T> {
        let f = &eq.frame;
        let (a1, a2) = (f.a.column(0), f.a.column(1));
        let k = self.drag;
        let g12 = -(k * f.wa[0].dot(&a2));
        // h∂G/∂α_i = −hk·[[2t_i1q_i1, t_i1q_i2 + t_i2q_i1], [·, 2t_i2q_i2]] (module docs).
        let m = -(eq.h * k);
        let m2 = m + m;
        let hdg = f.tq.map(|[(t1, q1), (t2, q2)]| {
            let d12 = m * (t1 * q2 + t2 * q1);
            (m2 * (t1 * q1), d12, d12, m2 * (t2 * q2))
        });
        PowerStep {
            g: (
                k * (f.w[0] - f.wa[0].dot(&a1)),
                g12,
                g12,
                k * (f.w[1] - f.wa[1].dot(&a2)),
            ),
            hdg,
        }
    }
}

/// The cost's shape terms at a control `u`: `hD(u)` (row `i`: `(h∂G/∂α_i u)ᵀ`) and `(h/2)c(u)`.
struct Shape<T: Real> {
    hd: Mat2<T>,
    half_hc: Vector2<T>,
}

impl<T: Real> PowerStep<T> {
    /// [`Shape`] at `u`.
    #[inline(always)]
    fn shape(&self, u: &Vector2<T>) -> Shape<T> {
        let [r1, r2] = self.hdg.map(|d| mul(&d, u));
        let half = T::half();
        Shape {
            hd: (r1.x, r1.y, r2.x, r2.y),
            half_hc: Vector2::new(half * r1.dot(u), half * r2.dot(u)),
        }
    }

    /// `G − P` for the law's other terms `P`.
    #[inline(always)]
    fn minus(&self, p: &Mat2<T>) -> Mat2<T> {
        sub(&self.g, p)
    }
}

/// `P − Q`.
#[inline(always)]
fn sub<T: Real>(p: &Mat2<T>, q: &Mat2<T>) -> Mat2<T> {
    (p.0 - q.0, p.1 - q.1, p.2 - q.2, p.3 - q.3)
}

/// `P + Q`.
#[inline(always)]
fn add<T: Real>(p: &Mat2<T>, q: &Mat2<T>) -> Mat2<T> {
    (p.0 + q.0, p.1 + q.1, p.2 + q.2, p.3 + q.3)
}

impl<T: Real> Step<T> for PowerStep<T> {
    #[inline(always)]
    fn first_iterate<R: Rows<T>>(&self, eq: &Equation<T>, rows: R) -> Pass<T> {
        let m = &eq.m;
        let hb = eq.hb(m);
        let hk = eq.half_h_kappa();
        let mm = self.minus(&(hb.0, hb.1 + hk, hb.2 - hk, hb.3));
        let u0 = rows.solve(&mm, &eq.rhs(m))?;
        let s = self.shape(&u0);
        let p = sub(&mm, &s.hd);
        let u = u0 + rows.solve(&p, &s.half_hc)?;
        let xi = eq.xi_prev + mul(&add(&hb, &s.hd), &u) - s.half_hc;
        Ok((
            u,
            self.rest_costate(rows, rows.costate(xi, &eq.frame.a, m), &u),
        ))
    }

    #[inline(always)]
    fn plain_pass<R: Rows<T>>(&self, eq: &Equation<T>, u: &Vector2<T>, rows: R) -> Pass<T> {
        let z = eq.zeta(u);
        let hb = eq.hb(&z);
        let s = self.shape(u);
        let p = add(&hb, &s.hd);
        let u = rows.solve(&self.minus(&p), &(eq.rhs(&z) - s.half_hc))?;
        let xi = eq.xi_prev + mul(&p, &u) - s.half_hc;
        Ok((
            u,
            self.rest_costate(rows, rows.costate(xi, &eq.frame.a, &z), &u),
        ))
    }

    #[inline(always)]
    fn newton_jacobian(&self, at: &NewtonAt<T>) -> Mat2<T> {
        self.minus(&add(&at.hb, &self.shape(at.u).hd))
    }

    /// `R(u) = Gu − (h/2)c(u) − ξ^{k−1} + (Aᵀ − V(u))ζ`.
    #[inline(always)]
    fn newton_residual(&self, at: &NewtonAt<T>) -> Vector2<T> {
        mul(&self.g, at.u) - self.shape(at.u).half_hc - at.eq.xi_prev
    }

    /// `ξ^{k−1} + V(u)ζ' + (hB + hD(u))δu + (h/2)c(u)`.
    #[inline(always)]
    fn newton_xi(&self, at: &NewtonAt<T>, vz: Vector2<T>, du: &Vector2<T>) -> Vector2<T> {
        let s = self.shape(at.u);
        at.eq.xi_prev + vz + mul(&add(&at.hb, &s.hd), du) + s.half_hc
    }

    /// The resting joints' `ξ^k_i = (Gu)_i + (Aᵀζ)_i`.
    #[inline(always)]
    fn rest_costate<R: Rows<T>>(&self, rows: R, xi: Vector2<T>, u: &Vector2<T>) -> Vector2<T> {
        let [r1, r2] = rows.resting();
        let gu = mul(&self.g, u);
        Vector2::new(
            if r1 { gu.x + xi.x } else { xi.x },
            if r2 { gu.y + xi.y } else { xi.y },
        )
    }
}
