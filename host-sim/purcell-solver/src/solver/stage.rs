//! The discrete problem stage by stage, in coordinates, with exact first and second
//! derivatives.
//!
//! State `s = (α1, α2, x, y, θ)` (θ unwrapped: coordinates of the universal cover of SE(2)),
//! control `u ∈ R²`. One step of the exact kinematics (MODEL.md §4, the same step as
//! [`purcell_core::Kinematics::step`]):
//!
//! ```text
//! f(s, u) = (α + h·u,  p + R(θ)·w,  θ + ω),    X = (v, ω) = −h·A(β)·u,    w = V(ω)·v
//! ```
//!
//! with `β = α + c·h·u` ([`Rule`]: `c = 0` for the problem itself, `0 < c ≤ ½` on coarse
//! grids),
//!
//! `V(ω) = [[a, −b], [b, a]]`, `a = sin ω/ω`, `b = (1 − cos ω)/ω` (the translation and
//! rotation of `exp(X)`, MODEL.md §3).
//!
//! [`StageModel::linearise`] returns `∂f/∂s`, `∂f/∂u` and the Hessian of `λᵀf` for a multiplier `λ`
//! (the next stage's costate), by the chain rule through `X(α, u)`:
//!
//! ```text
//! φ(θ, X) = μ_bᵀ w(X) + λ_θ ω,   μ_b = R(θ)ᵀ λ_p              (λᵀf = λ_αᵀ(α + hu) + λ_pᵀp + λ_θθ + φ)
//! φ_X = (μ_bᵀV, μ_bᵀV′v + λ_θ),   φ_vv = 0,  φ_vω = μ_bᵀV′,  φ_ωω = μ_bᵀV″v
//! ∂²(λᵀf)/∂z² = X_zᵀ φ_XX X_z + Σ_m φ_{X_m} ∂²X_m/∂z²,   z = (α, u)
//! X_α = −h [∂_1A u, ∂_2A u],   X_u = −h A − c h² [∂_1A u, ∂_2A u]            (at β = α + c·h·u)
//! ∂²X/∂α_i∂α_j = −h ∂_i∂_jA u,   ∂²X/∂α_i∂u_j = −h ∂_iA e_j − c h² ∂_i∂_jA u
//! ∂²X/∂u_i∂u_j = −c h² (∂_jA e_i + ∂_iA e_j) − c² h³ ∂_i∂_jA u
//! ∂φ/∂θ = (Jᵀμ_b)ᵀw,   ∂²φ/∂θ² = −μ_bᵀw,   ∂²φ/∂θ∂z = (Jᵀμ_b)ᵀ ∂w/∂X X_z,   J = [[0, −1], [1, 0]]
//! ```
//!
//! `∂²A/∂α²` comes from the core's closed-form `∂A/∂α` run on 2-tangent dual numbers; the
//! derivatives of `a` and `b` from [`sinc_jets`]. The tests check every block against the
//! stage function [`step`] on dual numbers.

use crate::dual::Dual;
use nalgebra::{Matrix2, Matrix2x3, Matrix3x2, Matrix5, Matrix5x2, Vector2, Vector3, Vector5};
use purcell_core::{Error, Kinematics, Real, State, Swimmer};

/// A state `(α1, α2, x, y, θ)`.
pub type StageState = Vector5<f64>;

/// One step `f(s, u)` in any scalar type (for the tests' dual numbers and the rollouts).
///
/// Errors as [`Kinematics::step`]: a shape at or past the link-overlap limit, non-finite
/// numbers, a singular connection.
pub fn step<T: Real>(
    kin: &Kinematics<T>,
    rule: Rule,
    s: &[T; 5],
    u: &Vector2<T>,
) -> Result<[T; 5], Error> {
    let h = kin.h();
    let c = T::from_f64(rule.c());
    let beta = Vector2::new(wrap(s[0] + c * h * u.x), wrap(s[1] + c * h * u.y));
    let a = kin.swimmer().connection(&beta)?;
    let x = kin.twist(&a, u);
    let e = purcell_core::se2::exp(&x);
    let (sin, cos) = s[4].sin_cos();
    let (tx, ty) = (e.x(), e.y());
    let next = [
        s[0] + h * u.x,
        s[1] + h * u.y,
        s[2] + (cos * tx - sin * ty),
        s[3] + (sin * tx + cos * ty),
        s[4] + x.z,
    ];
    if T::all_finite(next) {
        Ok(next)
    } else {
        Err(Error::NonFinite)
    }
}

/// Where in the step the connection is evaluated: `β = α + c·h·u`.
///
/// `c = 0` is the problem's own discretisation (MODEL.md §4). Its holonomy differs from the
/// continuous one by a term proportional to `(c − ½)·h` (plus `O(h²)`), so a coarse grid with
/// `c = ½ − h_fine/(2h)` ([`Rule::matching`]) has, to first order, the same discretisation
/// error as the fine problem: its extremals approximate the fine problem's far better than
/// those of the coarse left-point rule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rule {
    c: f64,
}

impl Rule {
    /// `c = 0`: the problem itself.
    pub const LEFT_POINT: Rule = Rule { c: 0.0 };
    /// `c = ½`: second order in `h`.
    pub const MIDPOINT: Rule = Rule { c: 0.5 };

    /// The rule for a grid of step `h` that mimics the left-point rule at step `h_fine`.
    pub fn matching(h: f64, h_fine: f64) -> Rule {
        Rule {
            c: (0.5 - 0.5 * h_fine / h).clamp(0.0, 0.5),
        }
    }

    /// `c` of `β = α + c·h·u`.
    pub fn c(self) -> f64 {
        self.c
    }
}

/// `x − 2πm` in `[−π, π[` (`m` an integer): `A(α)` is `2π`-periodic in each angle (it
/// depends on `cos α_i`, `sin α_i` only), so the direct method, like a direct transcription
/// in IPOPT, lets a joint swing past `±π` (links overlap) during the iteration; whether an
/// extremal is admissible is decided afterwards.
pub fn wrap<T: Real>(x: T) -> T {
    let two_pi = T::from_f64(2.0 * core::f64::consts::PI);
    let pi = T::pi();
    if x < -pi || x >= pi {
        let turns = ((x + pi).to_f64() / (2.0 * core::f64::consts::PI)).floor();
        let wrapped = x - two_pi * T::from_f64(turns);
        // Rounding can land exactly on π; the core refuses ±π, so step off it.
        if wrapped >= pi {
            wrapped - two_pi
        } else {
            wrapped
        }
    } else {
        x
    }
}

/// `(a, a′, a″)` and `(b, b′, b″)` for `a = sin ω/ω`, `b = (1 − cos ω)/ω`.
///
/// Taylor series in `ω` below `|ω| = 0.5` (terms to `ω¹⁸`, truncation below 1e-17 relative),
/// closed forms above.
pub fn sinc_jets(w: f64) -> ([f64; 3], [f64; 3]) {
    if w.abs() < 0.5 {
        // a = Σ αₙ ω²ⁿ, αₙ = (−1)ⁿ/(2n+1)!;  b = Σ βₙ ω²ⁿ⁺¹, βₙ = (−1)ⁿ/(2n+2)!; n < 10.
        const FACT: [f64; 22] = {
            let mut f = [1.0; 22];
            let mut i = 1;
            while i < 22 {
                f[i] = f[i - 1] * i as f64;
                i += 1;
            }
            f
        };
        let z = w * w;
        let (mut a, mut a1, mut a2) = (0.0, 0.0, 0.0);
        let (mut b, mut b1, mut b2) = (0.0, 0.0, 0.0);
        // Horner in z from the highest term down; a₁ = Σ αₙ 2n z^{n−1} (= a′/ω),
        // a₂ = Σ αₙ 2n(2n−1) z^{n−1} (= a″), b = Σ βₙ zⁿ (= b/ω), b₁ = Σ βₙ(2n+1) zⁿ (= b′),
        // b₂ = Σ βₙ(2n+1)2n z^{n−1} (= b″/ω).
        for n in (0..10).rev() {
            let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
            let (an, bn) = (sign / FACT[2 * n + 1], sign / FACT[2 * n + 2]);
            let m = 2.0 * n as f64;
            a = a * z + an;
            b = b * z + bn;
            b1 = b1 * z + bn * (m + 1.0);
            if n >= 1 {
                a1 = a1 * z + an * m;
                a2 = a2 * z + an * m * (m - 1.0);
                b2 = b2 * z + bn * (m + 1.0) * m;
            }
        }
        return ([a, a1 * w, a2], [b * w, b1, b2 * w]);
    }
    sinc_closed_forms(w)
}

/// [`sinc_jets`] by their closed forms (which lose about `−log₁₀(ω³)` digits to cancellation
/// at small `ω`).
fn sinc_closed_forms(w: f64) -> ([f64; 3], [f64; 3]) {
    let (s, c) = w.sin_cos();
    let (w2, w3) = (w * w, w * w * w);
    let omc = 1.0 - c;
    (
        [
            s / w,
            (w * c - s) / w2,
            (-w2 * s - 2.0 * w * c + 2.0 * s) / w3,
        ],
        [
            omc / w,
            (w * s - omc) / w2,
            (w2 * c - 2.0 * w * s + 2.0 * omc) / w3,
        ],
    )
}

/// `∂f/∂s`, `∂f/∂u` and the Hessian of `λᵀf` at one stage.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Linearised {
    /// `∂f/∂s` (5×5).
    pub a: Matrix5<f64>,
    /// `∂f/∂u` (5×2).
    pub b: Matrix5x2<f64>,
    /// `∂²(λᵀf)/∂s²`.
    pub hss: Matrix5<f64>,
    /// `∂²(λᵀf)/∂s∂u`.
    pub hsu: Matrix5x2<f64>,
    /// `∂²(λᵀf)/∂u²`.
    pub huu: Matrix2<f64>,
}

/// The swimmer in `f64` and on 2-tangent duals (for `∂²A/∂α²`), with the step `h`.
#[derive(Clone, Copy, Debug)]
pub struct StageModel {
    /// The kinematics in `f64`.
    pub kin: Kinematics<f64>,
    /// Where the connection is evaluated.
    pub rule: Rule,
    swimmer2: Swimmer<Dual<2>>,
}

impl StageModel {
    /// The model of a swimmer with step `h`.
    pub fn new(kin: Kinematics<f64>, rule: Rule) -> Result<Self, Error> {
        let sw = kin.swimmer();
        let c = Dual::<2>::constant;
        let [l0, l1, l2] = sw.lengths();
        let swimmer2 = Swimmer::new([c(l0), c(l1), c(l2)], c(sw.drag()), c(sw.ratio()))?;
        Ok(StageModel {
            kin,
            rule,
            swimmer2,
        })
    }

    /// The step `h`.
    pub fn h(&self) -> f64 {
        self.kin.h()
    }

    /// `f(s, u)` in `f64`.
    pub fn step(&self, s: &StageState, u: &Vector2<f64>) -> Result<StageState, Error> {
        step(&self.kin, self.rule, &[s[0], s[1], s[2], s[3], s[4]], u).map(StageState::from)
    }

    /// Derivatives at `(s, u)` with the next stage's multiplier `lambda` (see the module docs).
    pub fn linearise(
        &self,
        s: &StageState,
        u: &Vector2<f64>,
        lambda: &StageState,
    ) -> Result<Linearised, Error> {
        let t = self.twist(s, u)?;
        let (a, b) = t.jacobians();
        let (hss, hsu, huu) = t.hessians(lambda);
        let finite = |m: &[f64]| m.iter().all(|v| v.is_finite());
        if finite(a.as_slice())
            && finite(b.as_slice())
            && finite(hss.as_slice())
            && finite(hsu.as_slice())
            && finite(huu.as_slice())
        {
            Ok(Linearised {
                a,
                b,
                hss,
                hsu,
                huu,
            })
        } else {
            Err(Error::NonFinite)
        }
    }

    /// The twist of the step at `(s, u)` and its derivatives (see [`Twist`]).
    fn twist(&self, s: &StageState, u: &Vector2<f64>) -> Result<Twist, Error> {
        let h = self.h();
        let c = self.rule.c();
        let alpha = Vector2::new(
            Dual::variable(wrap(s[0] + c * h * u.x), 0),
            Dual::variable(wrap(s[1] + c * h * u.y), 1),
        );
        let conn = self.swimmer2.connection_with_derivatives(&alpha)?;
        let val = |m: &Matrix3x2<Dual<2>>| m.map(|d| d.v);
        let a = val(&conn.a);
        let da = [val(&conn.da[0]), val(&conn.da[1])];
        // ∂²A/∂α_i∂α_j = ∂(∂A/∂α_i)/∂α_j.
        let dda = |i: usize| [0, 1].map(|j| conn.da[i].map(|d| d.d[j]));

        let x: Vector3<f64> = -(a * u) * h;
        let (dau0, dau1) = (da[0] * u, da[1] * u);
        let xa = Matrix3x2::from_columns(&[-dau0 * h, -dau1 * h]);
        let xu = -a * h - Matrix3x2::from_columns(&[dau0, dau1]) * (c * h * h);
        let ([ca, ca1, ca2], [cb, cb1, cb2]) = sinc_jets(x.z);
        let vmat = |p: f64, q: f64| Matrix2::new(p, -q, q, p);
        let (v0, v1, v2) = (vmat(ca, cb), vmat(ca1, cb1), vmat(ca2, cb2));
        let v = Vector2::new(x.x, x.y);
        let w = v0 * v;
        // ∂w/∂X = [V | V′v] (2×3).
        let v1v = v1 * v;
        let dw = Matrix2x3::new(v0.m11, v0.m12, v1v.x, v0.m21, v0.m22, v1v.y);
        let (sin, cos) = s[4].sin_cos();
        Ok(Twist {
            h,
            c,
            u: *u,
            da,
            dda: [dda(0), dda(1)],
            xa,
            xu,
            v: [v0, v1, v2],
            vel: v,
            v1v,
            w,
            dw,
            rot: Matrix2::new(cos, -sin, sin, cos),
        })
    }
}

/// One stage's twist `X = (v, ω) = −h·A(β)·u` and the translation `w = V(ω)·v` of its
/// exponential, with the derivatives both the Jacobians and the Hessians are made of.
struct Twist {
    /// `h`.
    h: f64,
    /// `c` of the rule.
    c: f64,
    /// `u`.
    u: Vector2<f64>,
    /// `∂A/∂α_i` at `β`.
    da: [Matrix3x2<f64>; 2],
    /// `∂²A/∂α_i∂α_j` at `β`.
    dda: [[Matrix3x2<f64>; 2]; 2],
    /// `X_α`.
    xa: Matrix3x2<f64>,
    /// `X_u`.
    xu: Matrix3x2<f64>,
    /// `V`, `V′`, `V″` at `ω`.
    v: [Matrix2<f64>; 3],
    /// The linear velocity `v` of `X`.
    vel: Vector2<f64>,
    /// `V′v`.
    v1v: Vector2<f64>,
    /// `w = Vv`.
    w: Vector2<f64>,
    /// `∂w/∂X = [V | V′v]`.
    dw: Matrix2x3<f64>,
    /// `R(θ)`.
    rot: Matrix2<f64>,
}

impl Twist {
    /// `∂f/∂s` and `∂f/∂u`.
    fn jacobians(&self) -> (Matrix5<f64>, Matrix5x2<f64>) {
        let (h, xa, xu) = (self.h, &self.xa, &self.xu);
        let jw = Vector2::new(-self.w.y, self.w.x);
        let mut jac_s = Matrix5::<f64>::identity();
        let rdw = self.rot * self.dw;
        let p_alpha = rdw * xa;
        let rjw = self.rot * jw;
        for i in 0..2 {
            for r in 0..2 {
                jac_s[(2 + r, i)] = p_alpha[(r, i)];
            }
            jac_s[(4, i)] = xa[(2, i)];
            jac_s[(2 + i, 4)] = rjw[i];
        }
        let mut jac_u = Matrix5x2::<f64>::zeros();
        let p_u = rdw * xu;
        for j in 0..2 {
            jac_u[(j, j)] = h;
            for r in 0..2 {
                jac_u[(2 + r, j)] = p_u[(r, j)];
            }
            jac_u[(4, j)] = xu[(2, j)];
        }
        (jac_s, jac_u)
    }

    /// The Hessian of `λᵀf` as `(∂²/∂s², ∂²/∂s∂u, ∂²/∂u²)`.
    fn hessians(&self, lambda: &StageState) -> (Matrix5<f64>, Matrix5x2<f64>, Matrix2<f64>) {
        let (h, c, u, da) = (self.h, self.c, &self.u, &self.da);
        let [v0, v1, v2] = &self.v;
        let (xa, xu, dw) = (&self.xa, &self.xu, &self.dw);
        let lp = Vector2::new(lambda[2], lambda[3]);
        let lt = lambda[4];
        let mb = self.rot.transpose() * lp;
        let phi_x = Vector3::new(
            mb.dot(&v0.column(0)),
            mb.dot(&v0.column(1)),
            mb.dot(&self.v1v) + lt,
        );
        let c12 = v1.transpose() * mb;
        let c3 = mb.dot(&(v2 * self.vel));
        let phi_xx = nalgebra::Matrix3::new(0.0, 0.0, c12.x, 0.0, 0.0, c12.y, c12.x, c12.y, c3);
        // z = (α1, α2, u1, u2).
        let xz = nalgebra::Matrix3x4::from_columns(&[
            xa.column(0).into_owned(),
            xa.column(1).into_owned(),
            xu.column(0).into_owned(),
            xu.column(1).into_owned(),
        ]);
        let mut hzz = xz.transpose() * phi_xx * xz;
        for i in 0..2 {
            for j in 0..2 {
                let ddu = phi_x.dot(&(self.dda[i][j] * u));
                hzz[(i, j)] -= h * ddu;
                let cross = h * phi_x.dot(&da[i].column(j)) + c * h * h * ddu;
                hzz[(i, 2 + j)] -= cross;
                hzz[(2 + j, i)] -= cross;
                hzz[(2 + i, 2 + j)] -= c
                    * h
                    * h
                    * (phi_x.dot(&da[j].column(i)) + phi_x.dot(&da[i].column(j)) + c * h * ddu);
            }
        }
        let jmb = Vector2::new(mb.y, -mb.x); // Jᵀμ_b
        let h_tt = -mb.dot(&self.w);
        let h_tz = (jmb.transpose() * dw) * xz; // 1×4

        let mut hss = Matrix5::<f64>::zeros();
        let mut hsu = Matrix5x2::<f64>::zeros();
        let mut huu = Matrix2::<f64>::zeros();
        for i in 0..2 {
            for j in 0..2 {
                hss[(i, j)] = hzz[(i, j)];
                hsu[(i, j)] = hzz[(i, 2 + j)];
                huu[(i, j)] = hzz[(2 + i, 2 + j)];
            }
            hss[(i, 4)] = h_tz[i];
            hss[(4, i)] = h_tz[i];
            hsu[(4, i)] = h_tz[2 + i];
        }
        hss[(4, 4)] = h_tt;
        (hss, hsu, huu)
    }
}

/// The stage coordinates `s = (α1, α2, x, y, θ)` of a state, for any scalar.
pub(crate) fn coordinates<T: Real>(s: &State<T>) -> [T; 5] {
    [s.alpha.x, s.alpha.y, s.g.x(), s.g.y(), s.g.theta()]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dual::Dual;

    #[test]
    fn sinc_jets_match_closed_forms_and_differences() {
        let flatten = |(a, b): ([f64; 3], [f64; 3])| [a[0], a[1], a[2], b[0], b[1], b[2]];
        let closed = |w: f64| flatten(sinc_closed_forms(w));
        let flat = |w: f64| flatten(sinc_jets(w));
        assert_eq!(flat(0.0), [1.0, 0.0, -1.0 / 3.0, 0.0, 0.5, 0.0]);
        // Series against closed forms on both sides of the switch (the closed forms lose
        // about −log₁₀(ω³) digits to cancellation, so the bound is loose at small ω).
        for w in [0.1f64, -0.2, 0.3, 0.45, 0.4999, 0.5, 0.5001, 0.7, -1.0, 2.5] {
            let tol = 1e-15 / (w * w * w).abs().min(1.0);
            for (x, y) in flat(w).iter().zip(closed(w)) {
                assert!((x - y).abs() <= tol, "{w}: {x} vs {y}");
            }
        }
        // Each derivative against central differences of the one below it.
        let e = 1e-5;
        for w in [1e-9, 1e-4, 0.003, 0.1, 0.49, 0.51, 1.3, -0.2] {
            let (p, m, v) = (flat(w + e), flat(w - e), flat(w));
            for i in [0, 1, 3, 4] {
                let fd = (p[i] - m[i]) / (2.0 * e);
                assert!((v[i + 1] - fd).abs() <= 1e-9, "{w}: derivative {i}");
            }
        }
    }

    /// States, controls and multipliers `(s, u, λ)` the linearisation is checked at.
    const CASES: [([f64; 5], [f64; 2], [f64; 5]); 4] = [
        (
            [0.4, -0.7, 0.1, -0.2, 0.3],
            [1.3, -0.6],
            [0.2, -0.5, 1.1, -0.7, 0.4],
        ),
        (
            [2.9, 0.2, -1.0, 0.5, -2.0],
            [-3.0, 4.0],
            [-1.0, 0.3, -2.0, 3.0, -0.9],
        ),
        // Past the overlap: the connection is periodic.
        (
            [3.6, -4.0, 0.2, 0.1, 7.0],
            [2.0, -1.0],
            [0.3, -0.2, 0.5, 0.7, -0.4],
        ),
        (
            [0.0, 0.0, 0.0, 0.0, 0.0],
            [1e-3, 2e-3],
            [0.1, 0.2, 0.3, 0.4, 0.5],
        ),
    ];

    /// `f(z)` and `∂f/∂z` at `z = (s, u)`, on 7-tangent duals.
    fn dual_step(kin7: &Kinematics<Dual<7>>, rule: Rule, z: [f64; 7]) -> ([f64; 5], [[f64; 7]; 5]) {
        let d: Vec<Dual<7>> = (0..7).map(|i| Dual::variable(z[i], i)).collect();
        let next = step(
            kin7,
            rule,
            &[d[0], d[1], d[2], d[3], d[4]],
            &Vector2::new(d[5], d[6]),
        )
        .unwrap();
        (next.map(|v| v.v), next.map(|v| v.d))
    }

    /// `∇_z(λᵀf)` at `z = (s, u)`, on 7-tangent duals.
    fn dual_gradient(
        kin7: &Kinematics<Dual<7>>,
        rule: Rule,
        l: &[f64; 5],
        z: [f64; 7],
    ) -> [f64; 7] {
        let (_, j) = dual_step(kin7, rule, z);
        let mut g = [0.0; 7];
        for (r, row) in j.iter().enumerate() {
            for c in 0..7 {
                g[c] += l[r] * row[c];
            }
        }
        g
    }

    /// Entry `(i, j)` of the Hessian of `λᵀf` in `z = (s, u)`.
    fn hessian_entry(lin: &Linearised, i: usize, j: usize) -> f64 {
        match (i < 5, j < 5) {
            (true, true) => lin.hss[(i, j)],
            (true, false) => lin.hsu[(i, j - 5)],
            (false, true) => lin.hsu[(j, i - 5)],
            (false, false) => lin.huu[(i - 5, j - 5)],
        }
    }

    /// `λᵀf` on 7-tangent duals differentiated once more by central differences of the
    /// exact gradient: the reference for the Hessian; the Jacobian is compared with the
    /// duals directly.
    #[test]
    fn linearisation_matches_dual_numbers() {
        let kin = Kinematics::new(Swimmer::new([1.0, 0.8, 1.3], 1.0, 2.0).unwrap(), 0.05).unwrap();
        let kin7 = Kinematics::new(
            Swimmer::new(
                [1.0, 0.8, 1.3].map(Dual::<7>::constant),
                Dual::constant(1.0),
                Dual::constant(2.0),
            )
            .unwrap(),
            Dual::constant(0.05),
        )
        .unwrap();
        for rule in [Rule::LEFT_POINT, Rule::matching(0.05, 0.01)] {
            let model = StageModel::new(kin, rule).unwrap();
            for (s, u, l) in CASES {
                let z = [s[0], s[1], s[2], s[3], s[4], u[0], u[1]];
                let (val, jac) = dual_step(&kin7, rule, z);
                let (s, u) = (StageState::from(s), Vector2::from(u));
                let lin = model.linearise(&s, &u, &StageState::from(l)).unwrap();
                let next = model.step(&s, &u).unwrap();
                for (r, row) in jac.iter().enumerate() {
                    assert!((next[r] - val[r]).abs() <= 1e-14);
                    for (c, d) in row.iter().enumerate() {
                        let an = if c < 5 {
                            lin.a[(r, c)]
                        } else {
                            lin.b[(r, c - 5)]
                        };
                        assert!((an - d).abs() <= 1e-13, "∂f_{r}/∂z_{c}");
                    }
                }
                // Hessian of λᵀf by central differences of its exact gradient.
                let e = 1e-6;
                for j in 0..7 {
                    let (mut zp, mut zm) = (z, z);
                    zp[j] += e;
                    zm[j] -= e;
                    let gp = dual_gradient(&kin7, rule, &l, zp);
                    let gm = dual_gradient(&kin7, rule, &l, zm);
                    for i in 0..7 {
                        let fd = (gp[i] - gm[i]) / (2.0 * e);
                        let an = hessian_entry(&lin, i, j);
                        assert!(
                            (fd - an).abs() <= 1e-7 * (1.0 + an.abs()),
                            "H[{i},{j}] = {an} vs {fd}"
                        );
                    }
                }
            }
        }
    }
}
