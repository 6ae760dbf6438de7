//! The power the fluid dissipates (MODEL.md §11): `ℓ(α, u) = h/2·uᵀG(α)u`, `G` the Schur
//! complement of the swimmer's 5×5 resistance matrix `R(α) = Σ_links JᵀDJ` in `z = (ξ, u)`,
//! `G = R_uu − R_uξR_ξξ⁻¹R_ξu`.
//!
//! `G` is built here from the links' velocities (not from the core's closed forms of `A`),
//! generic in the scalar: on 2-tangent [`Dual`]s it gives `∂G/∂α_i` exactly; `∂²G/∂α_i∂α_j`
//! (only in `∇²_αα ℓ`, the Newton step's and the inertia test's Hessian) is the central
//! difference of the exact `∂G/∂α_i` with step [`SECOND`] (relative error about `1e-10`).

use super::{OfSwimmer, ShapeTerms, StageCost};
use crate::dual::Dual;
use crate::solver::stage::StageState;
use nalgebra::{Matrix2, Vector2};
use purcell_core::{Real, Swimmer};

/// Step of the central difference for `∂²G/∂α²`, radians.
pub const SECOND: f64 = 1e-5;

/// The dissipated power `ℓ = h/2·uᵀG(α)u` of a swimmer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Power {
    /// `(L0, L1, L2)`.
    links: [f64; 3],
    /// `k`.
    drag: f64,
    /// `r`.
    ratio: f64,
}

/// `G` and `∂G/∂α_1`, `∂G/∂α_2` at one shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metric {
    /// `G(α)`.
    pub g: Matrix2<f64>,
    /// `∂G/∂α_i`.
    pub dg: [Matrix2<f64>; 2],
}

impl Power {
    /// The power of `swimmer`.
    pub fn new(swimmer: &Swimmer<f64>) -> Self {
        Power {
            links: swimmer.lengths(),
            drag: swimmer.drag(),
            ratio: swimmer.ratio(),
        }
    }

    /// `G(α)` in scalar `T`.
    fn g<T: Real>(&self, a1: T, a2: T) -> [[T; 2]; 2] {
        let c = T::from_f64;
        let [l0, l1, l2] = self.links.map(c);
        let (k, r) = (c(self.drag), c(self.ratio));
        let half = T::half();
        let ((s1, c1), (s2, c2)) = (a1.sin_cos(), a2.sin_cos());
        // Per link: centre c, direction (cos φ, sin φ), ∂c/∂α_j, which joint turns it.
        let links = [
            (
                l0,
                (T::zero(), T::zero()),
                (T::zero(), T::one()),
                (T::zero(), T::zero()),
                None,
            ),
            (
                l1,
                (half * l0 + half * l1 * c1, half * l1 * s1),
                (s1, c1),
                (-(half * l1 * s1), half * l1 * c1),
                Some(3),
            ),
            (
                l2,
                (-(half * l0) - half * l2 * c2, -(half * l2 * s2)),
                (s2, c2),
                (half * l2 * s2, -(half * l2 * c2)),
                Some(4),
            ),
        ];
        let mut rm = [[T::zero(); 5]; 5];
        for (l, (cx, cy), (sn, cs), (dx, dy), joint) in links {
            // v = (vx − ω c_y, vy + ω c_x) + ∂c/∂α_j u_j, rows of (vx, vy, ω, u1, u2).
            let mut vx = [T::one(), T::zero(), -cy, T::zero(), T::zero()];
            let mut vy = [T::zero(), T::one(), cx, T::zero(), T::zero()];
            let mut w = [T::zero(), T::zero(), T::one(), T::zero(), T::zero()];
            if let Some(j) = joint {
                vx[j] = dx;
                vy[j] = dy;
                w[j] = T::one();
            }
            let par: [T; 5] = core::array::from_fn(|i| cs * vx[i] + sn * vy[i]);
            let perp: [T; 5] = core::array::from_fn(|i| cs * vy[i] - sn * vx[i]);
            let (dp, dn, dw) = (k * l, r * k * l, r * k * l * l * l / c(12.0));
            for i in 0..5 {
                for j in 0..5 {
                    rm[i][j] += dp * par[i] * par[j] + dn * perp[i] * perp[j] + dw * w[i] * w[j];
                }
            }
        }
        schur(&rm)
    }

    /// `G` and its first derivatives at `α = (a1, a2)` (exact, on duals).
    pub fn metric(&self, a1: f64, a2: f64) -> Metric {
        let g = self.g(Dual::<2>::variable(a1, 0), Dual::<2>::variable(a2, 1));
        let m = |f: &dyn Fn(&Dual<2>) -> f64| Matrix2::from_fn(|i, j| f(&g[i][j]));
        Metric {
            g: m(&|d| d.v),
            dg: [m(&|d| d.d[0]), m(&|d| d.d[1])],
        }
    }

    /// `G(α)` in `f64`.
    pub fn metric_at(&self, alpha: &Vector2<f64>) -> Matrix2<f64> {
        let g = self.g(alpha.x, alpha.y);
        Matrix2::new(g[0][0], g[0][1], g[1][0], g[1][1])
    }
}

/// `R_uu − R_uξ R_ξξ⁻¹ R_ξu` of a 5×5 `R` (ξ the first three), `R_ξξ⁻¹` by its adjugate.
fn schur<T: Real>(r: &[[T; 5]; 5]) -> [[T; 2]; 2] {
    let m = |i: usize, j: usize| r[i][j];
    let cof = |i: usize, j: usize| {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
        m(i1, j1) * m(i2, j2) - m(i1, j2) * m(i2, j1)
    };
    let det = m(0, 0) * cof(0, 0) + m(0, 1) * cof(0, 1) + m(0, 2) * cof(0, 2);
    // X = R_ξξ⁻¹ R_ξu, (R_ξξ⁻¹)_ij = cof(j, i)/det.
    let x =
        |i: usize, c: usize| (0..3).fold(T::zero(), |acc, j| acc + cof(j, i) * m(j, 3 + c)) / det;
    let xs = [[x(0, 0), x(0, 1)], [x(1, 0), x(1, 1)], [x(2, 0), x(2, 1)]];
    core::array::from_fn(|a| {
        core::array::from_fn(|b| {
            (0..3).fold(m(3 + a, 3 + b), |acc, i| acc - m(3 + a, i) * xs[i][b])
        })
    })
}

impl OfSwimmer for Power {
    fn of(swimmer: &Swimmer<f64>) -> Power {
        Power::new(swimmer)
    }
}

impl StageCost for Power {
    /// `h/2·Σ_k u_kᵀG(α_k)u_k`.
    fn value(&self, h: f64, states: &[StageState], u: &[Vector2<f64>]) -> f64 {
        let sum: f64 = states
            .iter()
            .zip(u)
            .map(|(s, u)| u.dot(&(self.metric_at(&Vector2::new(s[0], s[1])) * u)))
            .sum();
        0.5 * h * sum
    }

    /// `Σ_k (h·G u_k·du_k + (h/2)·c_k·δα_k)`, `c_{k,i} = u_kᵀ∂G/∂α_i u_k`.
    fn slope(&self, h: f64, states: &[StageState], u: &[Vector2<f64>], du: &[Vector2<f64>]) -> f64 {
        let mut da = Vector2::zeros();
        let mut sum = 0.0;
        for ((s, u), du) in states.iter().zip(u).zip(du) {
            let m = self.metric(s[0], s[1]);
            let c = Vector2::new(u.dot(&(m.dg[0] * u)), u.dot(&(m.dg[1] * u)));
            sum += h * (m.g * u).dot(du) + 0.5 * h * c.dot(&da);
            da += du * h;
        }
        sum
    }

    /// `h·G(α_k)u_k`.
    fn gradient(&self, h: f64, s: &StageState, u: &Vector2<f64>) -> Vector2<f64> {
        self.metric_at(&Vector2::new(s[0], s[1])) * u * h
    }

    /// `h·G(α_k)`.
    fn hessian(&self, h: f64, s: &StageState, _: &Vector2<f64>) -> Matrix2<f64> {
        self.metric_at(&Vector2::new(s[0], s[1])) * h
    }

    /// `∇_α ℓ = (h/2)c`, `∇²_αu ℓ` rows `h(∂G/∂α_i u)ᵀ`, `∇²_αα ℓ = (h/2)uᵀ∂²G/∂α_i∂α_j u`.
    fn shape_terms(&self, h: f64, s: &StageState, u: &Vector2<f64>) -> Option<ShapeTerms> {
        let m = self.metric(s[0], s[1]);
        let gu = [m.dg[0] * u, m.dg[1] * u];
        let mut haa = Matrix2::zeros();
        for j in 0..2 {
            let mut p = [s[0], s[1]];
            let mut q = p;
            p[j] += SECOND;
            q[j] -= SECOND;
            let (mp, mq) = (self.metric(p[0], p[1]), self.metric(q[0], q[1]));
            for i in 0..2 {
                let d2 = (mp.dg[i] - mq.dg[i]) / (2.0 * SECOND);
                haa[(i, j)] = 0.5 * h * u.dot(&(d2 * u));
            }
        }
        let haa = (haa + haa.transpose()) * 0.5;
        Some(ShapeTerms {
            gradient: Vector2::new(u.dot(&gu[0]), u.dot(&gu[1])) * (0.5 * h),
            haa,
            hau: Matrix2::new(gu[0].x, gu[0].y, gu[1].x, gu[1].y) * h,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testkit::dissipated;
    use approx::assert_relative_eq;

    #[test]
    fn metric_matches_the_model_s_test_vectors() {
        let p = Power::new(&Swimmer::purcell());
        let g = p.metric_at(&Vector2::zeros());
        let want = Matrix2::new(16.0, -11.0, -11.0, 16.0) / 81.0;
        assert_relative_eq!(g, want, epsilon = 1e-15);
        // MODEL.md §11's vectors, from the CasADi peer's own drag matrices
        // (peers/casadi_ipopt.py, `metric`).
        for (a, want) in [
            (
                (0.5, -0.3),
                Matrix2::new(
                    0.2232094378997902,
                    -0.15079310098990872,
                    -0.15079310098990872,
                    0.21112142840784293,
                ),
            ),
            (
                (2.5, -2.9),
                Matrix2::new(
                    0.39429893291851664,
                    0.04572239362945119,
                    0.04572239362945119,
                    0.44027145297025383,
                ),
            ),
        ] {
            let g = p.metric_at(&Vector2::new(a.0, a.1));
            assert_relative_eq!(g, want, epsilon = 1e-14);
        }
    }

    #[test]
    fn power_is_the_links_dissipation_for_several_swimmers_and_shapes() {
        for sw in [
            Swimmer::purcell(),
            Swimmer::new([1.0, 0.7, 1.3], 2.5, 3.0).unwrap(),
        ] {
            let p = Power::new(&sw);
            for (a, u) in [
                ((0.5, -0.3), (1.0, 0.4)),
                ((2.5, -2.9), (-0.3, 0.8)),
                ((-1.2, 0.1), (0.2, -1.7)),
            ] {
                let (a, u) = (Vector2::new(a.0, a.1), Vector2::new(u.0, u.1));
                let mine = u.dot(&(p.metric_at(&a) * u));
                let direct = dissipated(&sw, &a, &u);
                assert_relative_eq!(mine, direct, max_relative = 1e-12);
                assert!(direct > 0.0);
            }
        }
    }

    #[test]
    fn derivatives_match_finite_differences_of_the_value() {
        let p = Power::new(&Swimmer::purcell());
        let (h, u) = (0.01, Vector2::new(0.7, -1.1));
        let s = StageState::new(0.4, -0.8, 0.0, 0.0, 0.0);
        let ell =
            |a: [f64; 2], u: Vector2<f64>| 0.5 * h * u.dot(&(p.metric_at(&Vector2::from(a)) * u));
        let t = p.shape_terms(h, &s, &u).unwrap();
        let e = 1e-6;
        for i in 0..2 {
            let (mut ap, mut am) = ([s[0], s[1]], [s[0], s[1]]);
            ap[i] += e;
            am[i] -= e;
            let fd = (ell(ap, u) - ell(am, u)) / (2.0 * e);
            assert_relative_eq!(t.gradient[i], fd, max_relative = 1e-7);
            // ∇²_αu: the control gradient's change with α_i.
            let gp = p.gradient(h, &StageState::new(ap[0], ap[1], 0.0, 0.0, 0.0), &u);
            let gm = p.gradient(h, &StageState::new(am[0], am[1], 0.0, 0.0, 0.0), &u);
            let fd_u = (gp - gm) / (2.0 * e);
            assert_relative_eq!(t.hau.row(i).transpose(), fd_u, max_relative = 1e-6);
            // ∇²_αα: the shape gradient's change with α_i.
            let tp = p.shape_terms(h, &StageState::new(ap[0], ap[1], 0.0, 0.0, 0.0), &u);
            let tm = p.shape_terms(h, &StageState::new(am[0], am[1], 0.0, 0.0, 0.0), &u);
            let fd_a = (tp.unwrap().gradient - tm.unwrap().gradient) / (2.0 * e);
            assert_relative_eq!(t.haa.column(i).into_owned(), fd_a, max_relative = 1e-5);
        }
    }
}
