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
//! `u_k` is the root of `R(u) = (I − hB(ζ(u)))u − ξ^{k−1} + Aᵀζ(u)`, where `ζ` depends on `u`
//! only through `dexp_X`, an `O(h|A u|) ≈ 1e-3` effect. The law solves it in three parts:
//!
//! 1. **First iterate** `u⁰`: the root of `R` linearised at `u = 0`, i.e. one Newton step from
//!    `u = 0`. To first order in `X`, `ζ = m + ½ ad_Xᵀ m = m + ½K(m)X` with
//!    `K(m) = [[0, 0, m_y], [0, 0, −m_x], [−m_y, m_x, 0]]`, so `∂R/∂u(0) = M = I − hB(m) −
//!    (h/2)·AᵀK(m)A`, and `AᵀK(m)A = κ·[[0, 1], [−1, 0]]` with `κ = a₁ᵀK(m)a₂` (`a_j` the
//!    columns of `A`): `u⁰ = M⁻¹(ξ^{k−1} − Aᵀm)`. Its error is second order in `X` (measured
//!    ≤ 5e-6 of `|u|` on the paper's loops, against 6e-3 for the explicit law with `ζ = m`).
//! 2. **Passes**, a fixed number of one kind per scalar type ([`Real::PASSES`]):
//!    - [`PassKind::Plain`] (`f32`, 1 pass): `ζ ← dexp_Xᵀ m` at the last `u`, solve
//!      `(I − hB(ζ))u = ξ^{k−1} − Aᵀζ` again; contracts by about `h|A||m|` (≈ 4e-3: 5e-6 →
//!      2e-8, below f32 rounding);
//!    - [`PassKind::Newton`] (`f64`, 1 pass): `u ← u − J(u)⁻¹R(u)` with the exact Jacobian
//!      `J = I − hB(ζ) + (Aᵀ − V(u))·∂ζ/∂u`; squares the error (5e-6 → 7e-15, rounding).
//!
//!    Each pass also returns `ξ^k = ξ^{k−1} + hB(ζ)u` for its new `u`: a plain pass with the `ζ`
//!    it solved with (so the paper's `u = ξ^k − Aᵀζ` holds for it), a Newton pass
//!    with `ζ` carried to the new `u` along `∂ζ/∂u`.
//! 3. **Finish**: `X = −hAu`, `α_{k+1}`, `g_{k+1} = g_k exp(X)`, and the output checks.
//!
//! Both kinds converge to the same `u_k`, the root of the law's equations. The work per step
//! is fixed: no loop runs to a tolerance.
//!
//! **On a joint-limit arc** (MODEL.md §9; the `on` argument of [`Kinematics::law_step`]),
//! joint `i` rests: `u_{k,i} = 0` replaces row `i` of every solve (first iterate and passes
//! alike, with `X = −hAu` at that `u`), so the other row gives `u_{k,j}` alone, `ξ^k_j =
//! ξ^{k−1}_j + (hB u)_j` as above, and `ξ^k_i = (Aᵀζ^k)_i`, the value that makes row `i` hold
//! (the costate jump `η` of the limit is what row `i` leaves over). Both joints on arcs:
//! `u_k = 0`. The same code runs both (a `Rows` parameter): the free law solves all rows, an
//! arc step fewer.

use crate::kinematics::{Kinematics, State};
use crate::passes::{PassKind, Passes};
use crate::se2::{self, ExpCoefficients, Tangent};
use crate::swimmer::{Frame, Sym3, connection_mul, sym_mul_vec};
use crate::{Error, Real};
use nalgebra::{Matrix3x2, Vector2, Vector3};

/// The joints on a joint-limit arc at a step, `[joint 1, joint 2]` (MODEL.md §9): their
/// control is zero and their costate takes the value that makes the law's row hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct OnArcs(pub [bool; 2]);

impl OnArcs {
    /// No joint on an arc: the free law.
    pub const NONE: OnArcs = OnArcs([false; 2]);
}

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
    /// One step of the law with the joints `on` a joint-limit arc at rest and `passes` after
    /// the first iterate (see the [module docs](self)): a flight runs [`OnArcs::NONE`] (the
    /// free law) off the arcs and [`Real::PASSES`]; other passes measure the residual they
    /// leave. On an arc (MODEL.md §9) each joint on it has `u_{k,i}` exactly 0 and
    /// `ξ^k_i = (Aᵀζ^k)_i`.
    ///
    /// Errors: [`Error::NonFinite`] for non-finite input or result, [`Error::ShapeLimit`]
    /// if `α_k` or `α_{k+1}` is at or past `|α_i| = π`, [`Error::Singular`] if the first
    /// iterate's matrix `M` or a plain pass's `I − h B` is singular (or, on an arc, the row
    /// left), [`Error::NotRotation`] as [`State::check`].
    #[inline]
    pub fn law_step(
        &self,
        state: &State<T>,
        xi_prev: &Vector2<T>,
        mu: &Vector3<T>,
        on: OnArcs,
        passes: Passes,
    ) -> Result<LawStep<T>, Error> {
        check_inputs(state, xi_prev, mu)?;
        // Off the arcs, the free rows: the code a replay's free step runs.
        if on == OnArcs::NONE {
            self.law_step_trusted(state, xi_prev, mu, Effort, Free, passes)
        } else {
            self.law_step_trusted(state, xi_prev, mu, Effort, on, passes)
        }
    }

    /// [`Kinematics::law_step`] of the cost's law `cost` solving the law's rows `rows`
    /// ([`Free`], or the joints off their [`OnArcs`]), for inputs already known to be valid: `state` passes
    /// [`State::check`], `ξ^{k−1}` and `μ` are finite (a [`crate::Replay`] knows this from its
    /// start checks and the previous step's output checks). Still checks every output, so it
    /// cannot return a non-finite or inadmissible result. Always inlined: a replay's free step
    /// and its out-of-line arc step are each this code.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn law_step_trusted<C: Law<T>, R: Rows<T>>(
        &self,
        state: &State<T>,
        xi_prev: &Vector2<T>,
        mu: &Vector3<T>,
        cost: C,
        rows: R,
        passes: Passes,
    ) -> Result<LawStep<T>, Error> {
        let frame = self.swimmer().frame(&state.alpha)?;
        let eq = Equation::new(frame, self.h(), state.g.adjoint_transpose_mul(mu), *xi_prev);
        let step = cost.at(&eq);
        let (u0, xi0) = step.first_iterate(&eq, rows)?;
        let (u, xi) = match passes.kind {
            PassKind::Plain => {
                (0..passes.count).try_fold((u0, xi0), |(u, _), _| step.plain_pass(&eq, &u, rows))?
            }
            PassKind::Newton => (0..passes.count)
                .try_fold((u0, xi0), |(u, _), _| step.newton_pass(&eq, &u, rows))?,
        };
        self.finish(state, &eq, u, xi)
    }

    /// The end of a step from its `u_k` and `ξ^k`: `X = −hAu`, `(α_{k+1}, g_{k+1})`, all
    /// checked.
    #[inline(always)]
    fn finish(
        &self,
        state: &State<T>,
        eq: &Equation<T>,
        u: Vector2<T>,
        xi: Vector2<T>,
    ) -> Result<LawStep<T>, Error> {
        if !T::all_finite([u.x, u.y, xi.x, xi.y]) {
            return Err(Error::NonFinite);
        }
        let next = self.advance(state, &u, &se2::exp(&eq.twist(&u)))?;
        Ok(LawStep { u, next, xi })
    }
}

/// `Ok` if `ξ^{k−1}` and `μ` are finite and `state` passes [`State::check`].
pub(crate) fn check_inputs<T: Real>(
    state: &State<T>,
    xi_prev: &Vector2<T>,
    mu: &Vector3<T>,
) -> Result<(), Error> {
    if !T::all_finite([xi_prev.x, xi_prev.y, mu.x, mu.y, mu.z]) {
        return Err(Error::NonFinite);
    }
    state.check()
}

/// A step's `u_k` and `ξ^k`.
pub(crate) type Solution<T> = (Vector2<T>, Vector2<T>);
/// A pass's [`Solution`], or why the step has none.
pub(crate) type Pass<T> = Result<Solution<T>, Error>;

/// The law's equations of a cost: [`Law::at`] takes what the cost needs at a step's shape.
pub(crate) trait Law<T: Real>: Copy {
    /// The cost at one step.
    type Step: Step<T>;
    /// The cost at the step of `eq`.
    fn at(self, eq: &Equation<T>) -> Self::Step;
}

/// The three parts of a step's solve (see [`crate::law`]), each solving `rows`.
pub(crate) trait Step<T: Real>: Sized {
    /// The root of the law's equation linearised at `u = 0` (and, for a cost whose shape
    /// gradient is not zero, its quadratic term taken in by a Newton step), with its `ξ^k`.
    fn first_iterate<R: Rows<T>>(&self, eq: &Equation<T>, rows: R) -> Pass<T>;
    /// A plain pass from `u` ([`crate::PassKind::Plain`]).
    fn plain_pass<R: Rows<T>>(&self, eq: &Equation<T>, u: &Vector2<T>, rows: R) -> Pass<T>;
    /// The Jacobian of a Newton pass ([`Equation::newton_pass`]) less `(Aᵀ − V(u))·∂ζ/∂u`:
    /// the effort's `I − hB`.
    fn newton_jacobian(&self, at: &NewtonAt<T>) -> Mat2<T>;
    /// Its residual `R(u)` less `(Aᵀ − V(u))ζ`: the effort's `u − ξ^{k−1}`.
    fn newton_residual(&self, at: &NewtonAt<T>) -> Vector2<T>;
    /// Its `ξ^k` (of the free rows) from `V(u)ζ'` (`vz`) and `δu`: the effort's
    /// `ξ^{k−1} + vz + hB·δu`.
    fn newton_xi(&self, at: &NewtonAt<T>, vz: Vector2<T>, du: &Vector2<T>) -> Vector2<T>;
    /// `ξ^k` of a step solving `rows` from the rows' own ([`Rows::costate`]) at the step's `u`:
    /// the effort's is `xi`; a cost whose `∇_uℓ` is not `hu` corrects its resting joints.
    fn rest_costate<R: Rows<T>>(&self, rows: R, xi: Vector2<T>, u: &Vector2<T>) -> Vector2<T>;
    /// A Newton pass from `u` ([`crate::PassKind::Newton`]): [`Equation::newton_pass`] with
    /// the cost's terms.
    #[inline(always)]
    fn newton_pass<R: Rows<T>>(&self, eq: &Equation<T>, u: &Vector2<T>, rows: R) -> Pass<T> {
        eq.newton_pass(self, u, rows)
    }
}

/// What a cost's terms of a Newton pass from `u` are made of ([`Equation::newton_pass`]).
pub(crate) struct NewtonAt<'a, T: Real> {
    /// The law's equation.
    pub(crate) eq: &'a Equation<T>,
    /// The pass's `u`.
    pub(crate) u: &'a Vector2<T>,
    /// `hB(ζ(u))`.
    pub(crate) hb: Mat2<T>,
}

/// The effort `ℓ = h/2·|u|²`: the law of [`crate::law`] as it is ([`crate::Cost::Effort`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct Effort;

impl<T: Real> Law<T> for Effort {
    type Step = Effort;
    #[inline(always)]
    fn at(self, _: &Equation<T>) -> Effort {
        Effort
    }
}

impl<T: Real> Step<T> for Effort {
    #[inline(always)]
    fn first_iterate<R: Rows<T>>(&self, eq: &Equation<T>, rows: R) -> Pass<T> {
        eq.first_iterate(rows)
    }

    #[inline(always)]
    fn plain_pass<R: Rows<T>>(&self, eq: &Equation<T>, u: &Vector2<T>, rows: R) -> Pass<T> {
        eq.plain_pass(u, rows)
    }

    #[inline(always)]
    fn newton_jacobian(&self, at: &NewtonAt<T>) -> Mat2<T> {
        let (b11, b12, b21, b22) = at.hb;
        (T::one() - b11, -b12, -b21, T::one() - b22)
    }

    #[inline(always)]
    fn newton_residual(&self, at: &NewtonAt<T>) -> Vector2<T> {
        at.u - at.eq.xi_prev
    }

    #[inline(always)]
    fn newton_xi(&self, at: &NewtonAt<T>, vz: Vector2<T>, du: &Vector2<T>) -> Vector2<T> {
        at.eq.xi_prev + vz + mul(&at.hb, du)
    }

    #[inline(always)]
    fn rest_costate<R: Rows<T>>(&self, _: R, xi: Vector2<T>, _: &Vector2<T>) -> Vector2<T> {
        xi
    }
}

/// A 2×2 matrix `(m11, m12, m21, m22)`.
pub(crate) type Mat2<T> = (T, T, T, T);

/// Which rows of the law's equation a step solves: all ([`Free`]), or those of the joints off
/// their limit ([`OnArcs`]: `u_i = 0` in place of row `i`, and `ξ^k_i = (Aᵀζ)_i`).
pub(crate) trait Rows<T: Real>: Copy {
    /// The solution of `P·u = r` with the rows of the joints on an arc replaced by `u_i = 0`.
    fn solve(self, p: &Mat2<T>, r: &Vector2<T>) -> Result<Vector2<T>, Error>;
    /// `ξ^k` from the free rows' `ξ` and the `ζ` it goes with: the components of the joints
    /// on an arc replaced by `(Aᵀζ)_i`.
    fn costate(self, xi: Vector2<T>, a: &Matrix3x2<T>, z: &Vector3<T>) -> Vector2<T>;
    /// The joints on an arc, `[joint 1, joint 2]`.
    fn resting(self) -> [bool; 2];
}

/// Every row: the free law.
#[derive(Clone, Copy)]
pub(crate) struct Free;

impl<T: Real> Rows<T> for Free {
    #[inline(always)]
    fn solve(self, p: &Mat2<T>, r: &Vector2<T>) -> Result<Vector2<T>, Error> {
        solve(p, r)
    }

    #[inline(always)]
    fn costate(self, xi: Vector2<T>, _: &Matrix3x2<T>, _: &Vector3<T>) -> Vector2<T> {
        xi
    }

    #[inline(always)]
    fn resting(self) -> [bool; 2] {
        [false; 2]
    }
}

impl<T: Real> Rows<T> for OnArcs {
    #[inline(always)]
    fn solve(self, p: &Mat2<T>, r: &Vector2<T>) -> Result<Vector2<T>, Error> {
        match self.0 {
            [false, false] => solve(p, r),
            [true, false] => Ok(Vector2::new(T::zero(), r.y * inverse_det(p.3)?)),
            [false, true] => Ok(Vector2::new(r.x * inverse_det(p.0)?, T::zero())),
            [true, true] => Ok(Vector2::zeros()),
        }
    }

    #[inline(always)]
    fn costate(self, xi: Vector2<T>, a: &Matrix3x2<T>, z: &Vector3<T>) -> Vector2<T> {
        let [on1, on2] = self.0;
        Vector2::new(
            if on1 {
                a.m11 * z.x + a.m21 * z.y + a.m31 * z.z
            } else {
                xi.x
            },
            if on2 {
                a.m12 * z.x + a.m22 * z.y + a.m32 * z.z
            } else {
                xi.y
            },
        )
    }

    #[inline(always)]
    fn resting(self) -> [bool; 2] {
        self.0
    }
}

/// The law's equation `R(u) = 0` at one step: the connection's [`Frame`] at `α_k`, with
/// `h·W_ξ⁻¹` so that `hB(ζ)` comes from `λ = h·W_ξ⁻¹ζ` against the brackets' columns (see
/// [`crate::swimmer`]), `m_k` and `ξ^{k−1}`.
pub(crate) struct Equation<T: Real> {
    pub(crate) frame: Frame<T>,
    pub(crate) hw_inv: Sym3<T>,
    pub(crate) h: T,
    pub(crate) m: Vector3<T>,
    pub(crate) xi_prev: Vector2<T>,
}

impl<T: Real> Equation<T> {
    #[inline(always)]
    pub(crate) fn new(frame: Frame<T>, h: T, m: Vector3<T>, xi_prev: Vector2<T>) -> Self {
        Equation {
            hw_inv: frame.w_inv.map(|v| v * h),
            frame,
            h,
            m,
            xi_prev,
        }
    }

    /// `hB(ζ)_ij = ζᵀ h∂A/∂α_i e_j = λ·E_i e_j` with `λ = h·W_ξ⁻¹ζ`.
    #[inline(always)]
    pub(crate) fn hb(&self, z: &Vector3<T>) -> Mat2<T> {
        let lam = sym_mul_vec(&self.hw_inv, z);
        let [[e11, e12], [e21, e22]] = &self.frame.e;
        (lam.dot(e11), lam.dot(e12), lam.dot(e21), lam.dot(e22))
    }

    /// `ξ^{k−1} + hB·u`.
    #[inline(always)]
    fn xi(&self, hb: &Mat2<T>, u: &Vector2<T>) -> Vector2<T> {
        self.xi_prev + mul(hb, u)
    }

    /// `X = −hAu`.
    #[inline(always)]
    pub(crate) fn twist(&self, u: &Vector2<T>) -> Tangent<T> {
        connection_mul(
            &self.frame.a,
            &Vector2::new(-(self.h * u.x), -(self.h * u.y)),
        )
    }

    /// `ξ^{k−1} − Aᵀζ`.
    #[inline(always)]
    pub(crate) fn rhs(&self, z: &Vector3<T>) -> Vector2<T> {
        let a = &self.frame.a;
        Vector2::new(
            self.xi_prev.x - (a.m11 * z.x + a.m21 * z.y + a.m31 * z.z),
            self.xi_prev.y - (a.m12 * z.x + a.m22 * z.y + a.m32 * z.z),
        )
    }

    /// `ζ(u) = dexp_Xᵀ m_k` at `X = −hAu`.
    #[inline(always)]
    pub(crate) fn zeta(&self, u: &Vector2<T>) -> Vector3<T> {
        let x = self.twist(u);
        ExpCoefficients::new(x.z).dexp_transpose_mul(&x, &self.m)
    }

    /// The first iterate `u⁰ = M⁻¹(ξ^{k−1} − Aᵀm)` and its `ξ = ξ^{k−1} + hB(m)u⁰` (see the
    /// module docs), solving `rows`.
    #[inline(always)]
    pub(crate) fn first_iterate<R: Rows<T>>(
        &self,
        rows: R,
    ) -> Result<(Vector2<T>, Vector2<T>), Error> {
        let (a, m) = (&self.frame.a, &self.m);
        let hb = self.hb(m);
        let (b11, b12, b21, b22) = hb;
        let hk = self.half_h_kappa();
        let u = rows.solve(
            &(T::one() - b11, -(b12 + hk), hk - b21, T::one() - b22),
            &self.rhs(m),
        )?;
        Ok((u, rows.costate(self.xi(&hb, &u), a, m)))
    }

    /// `(h/2)κ` of the first iterate's matrix: `κ = a₁ᵀK(m)a₂ = m_x (a₁z a₂y − a₁y a₂z) +
    /// m_y (a₁x a₂z − a₁z a₂x)`.
    #[inline(always)]
    pub(crate) fn half_h_kappa(&self) -> T {
        let (a, m) = (&self.frame.a, &self.m);
        let kappa = m.x * (a.m31 * a.m22 - a.m21 * a.m32) + m.y * (a.m11 * a.m32 - a.m31 * a.m12);
        T::half() * self.h * kappa
    }

    /// A plain pass from `u`: `ζ(u)`, then `u' = (I − hB(ζ))⁻¹(ξ^{k−1} − Aᵀζ)`; returns `u'`
    /// and `ξ^{k−1} + hB(ζ)u'` (solving `rows`).
    #[inline(always)]
    pub(crate) fn plain_pass<R: Rows<T>>(
        &self,
        u: &Vector2<T>,
        rows: R,
    ) -> Result<(Vector2<T>, Vector2<T>), Error> {
        let z = self.zeta(u);
        let hb = self.hb(&z);
        let (b11, b12, b21, b22) = hb;
        let u = rows.solve(&(T::one() - b11, -b12, -b21, T::one() - b22), &self.rhs(&z))?;
        Ok((u, rows.costate(self.xi(&hb, &u), &self.frame.a, &z)))
    }

    /// What a Newton pass from `u` needs besides the cost (see [`Equation::newton_pass`]).
    #[inline(always)]
    fn newton_terms(&self, u: &Vector2<T>) -> NewtonTerms<T> {
        // `−h` first: where it stands decides the M7's f64 registers (985.2 instructions a
        // step on the paper's gait, 990.2 with it after `dz`).
        let (a, m, mh) = (&self.frame.a, &self.m, -self.h);
        let x = self.twist(u);
        let k = ExpCoefficients::new(x.z);
        let z = k.dexp_transpose_mul(&x, m);
        let dz = k.dexp_transpose_mul_jacobian(&x, m);
        let (d1, d2) = (dz.mul(&(a.column(0) * mh)), dz.mul(&(a.column(1) * mh)));
        let [[e11, e12], [e21, e22]] = &self.frame.e;
        let v1 = sym_mul_vec(&self.hw_inv, &(e11 * u.x + e12 * u.y));
        let v2 = sym_mul_vec(&self.hw_inv, &(e21 * u.x + e22 * u.y));
        NewtonTerms {
            z,
            d: [d1, d2],
            v: [v1, v2],
            g: [a.column(0) - v1, a.column(1) - v2],
        }
    }

    /// A Newton pass from `u`: `u' = u − J⁻¹R(u)` with `R(u) = (I − hB(ζ))u − ξ^{k−1} + Aᵀζ`
    /// and its Jacobian `J = I − hB(ζ) + (Aᵀ − V(u))·∂ζ/∂u`, where `V(u) = [(h∂A/∂α_i u)ᵀ]_i`
    /// (so that `hB(ζ)u = V(u)ζ`) and `∂ζ/∂u = ∂(dexp_Xᵀm)/∂X·(−hA)`. Returns `u'` and
    /// `ξ^{k−1} + hB(ζ')u'` at `ζ' = ζ(u')`, which is `ξ^{k−1} + V(u)ζ' + hB(ζ)δu` with
    /// `δu = u' − u` and `ζ' = ζ + ∂ζ/∂u·δu` up to `O(|δu|²)`, below rounding after a Newton
    /// step from the first iterate (`|δu| ≈ 5e-6·|u|`). Solving `rows`, `δu_i = 0` for a
    /// joint on an arc. The cost (`step`) gives `J`, `R(u)` and `ξ^k` from these terms
    /// ([`Step::newton_jacobian`] …): the above for the effort, its `ℓ`'s added for another.
    #[inline(always)]
    pub(crate) fn newton_pass<S: Step<T>, R: Rows<T>>(
        &self,
        step: &S,
        u: &Vector2<T>,
        rows: R,
    ) -> Pass<T> {
        let NewtonTerms {
            z,
            d: [d1, d2],
            v: [v1, v2],
            g: [g1, g2],
        } = self.newton_terms(u);
        let at = NewtonAt {
            eq: self,
            u,
            hb: self.hb(&z),
        };
        let (lead, r) = (step.newton_jacobian(&at), step.newton_residual(&at));
        let jac = (
            lead.0 + g1.dot(&d1),
            lead.1 + g1.dot(&d2),
            lead.2 + g2.dot(&d1),
            lead.3 + g2.dot(&d2),
        );
        let du = -rows.solve(&jac, &Vector2::new(r.x + g1.dot(&z), r.y + g2.dot(&z)))?;
        let z1 = z + d1 * du.x + d2 * du.y;
        let xi = step.newton_xi(&at, Vector2::new(v1.dot(&z1), v2.dot(&z1)), &du);
        let u = u + du;
        Ok((
            u,
            step.rest_costate(rows, rows.costate(xi, &self.frame.a, &z1), &u),
        ))
    }
}

/// The terms of a Newton pass at `u`: `ζ(u)`, `∂ζ/∂u_j`, the rows `v_i` of `V(u)` and
/// `g_i = a_i − v_i` (the columns of `Aᵀ − V(u)`, transposed).
struct NewtonTerms<T: Real> {
    z: Vector3<T>,
    d: [Vector3<T>; 2],
    v: [Vector3<T>; 2],
    g: [Vector3<T>; 2],
}

/// `P·v` for a 2×2 `P`.
#[inline(always)]
pub(crate) fn mul<T: Real>(p: &Mat2<T>, v: &Vector2<T>) -> Vector2<T> {
    Vector2::new(p.0 * v.x + p.1 * v.y, p.2 * v.x + p.3 * v.y)
}

/// `P⁻¹r` by Cramer's rule, or `Err(Singular)` (see [`inverse_det`]).
#[inline(always)]
pub(crate) fn solve<T: Real>(p: &Mat2<T>, r: &Vector2<T>) -> Result<Vector2<T>, Error> {
    let inv = inverse_det(p.0 * p.3 - p.1 * p.2)?;
    Ok(Vector2::new(
        (p.3 * r.x - p.1 * r.y) * inv,
        (p.0 * r.y - p.2 * r.x) * inv,
    ))
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
    use crate::{Kinematics, OnArcs, Real, Se2, State, Swimmer};
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
            .law_step(
                &state,
                &Vector2::new(0.01, -0.03),
                &mu,
                OnArcs::NONE,
                f64::PASSES,
            )
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
