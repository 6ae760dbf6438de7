//! A direct method on truncated Fourier loops, to find starts for the shooting method.
//!
//! Shape paths that start and end at `ᾱ` are parametrised by `K` harmonics per joint,
//!
//! ```text
//! α(t) = ᾱ + Σ_{j=1..K} a_j (cos jωt − 1) + b_j sin jωt,   ω = 2π/T,   a_j, b_j ∈ R²
//! ```
//!
//! so `p = (a, b) ∈ R^{4K}` is unconstrained, `u_k = (α_{k+1} − α_k)/h` and
//! `J(p) = ½ pᵀQp` exactly (Q from the discrete differences). The terminal constraint
//! `c(p) = log(ḡ⁻¹ g_N(p)) = 0` is evaluated by the core's exact kinematics, and its
//! Jacobian `C = ∂c/∂p` exactly in the same forward pass ([`constraint`]).
//!
//! The iteration `p ← argmin ½ qᵀQq  s.t.  c(p) + C (q − p) = 0`, i.e.
//! `q = Q⁻¹Cᵀ (C Q⁻¹ Cᵀ)⁻¹ (C p − c)`, has the KKT points `Qp = Cᵀλ, c(p) = 0` as fixed
//! points; steps are damped on the merit `J + ρ|c|₁`. Its result is an approximate
//! extremal (exact up to the truncation of the loop to `K` harmonics), which
//! [`crate::seed::fit`] turns into `(μ, ξ^{−1})` for Newton.

use crate::problem::Problem;
use nalgebra::{DMatrix, DVector, Matrix3x2, SMatrix, SVector, Vector2, Vector3};
use purcell_core::{State, se2};

/// Harmonics per joint.
pub const HARMONICS: usize = 6;
/// Loop coefficients `4K`.
pub const COEFFS: usize = 4 * HARMONICS;

/// Loop coefficients, ordered `(a₁, b₁)` for joint 1 then joint 2, harmonics `1..=K`
/// within each: `[a1_1..a1_K, b1_1..b1_K, a2_1..a2_K, b2_1..b2_K]`.
pub type Coefficients = SVector<f64, COEFFS>;

/// The Fourier basis on the time grid: `α_k = ᾱ + Φ_k p`.
#[derive(Clone, Debug)]
pub struct Basis {
    /// `(cos jωt_k − 1, sin jωt_k)` for `j = 1..K`, per step `k = 0..=N`.
    rows: Vec<[f64; 2 * HARMONICS]>,
    /// `Q` of `J = ½ pᵀQp`.
    q: DMatrix<f64>,
}

impl Basis {
    /// The basis for a problem's grid.
    pub fn new(problem: &Problem) -> Self {
        let n = problem.steps as usize;
        let w = 2.0 * core::f64::consts::PI / n as f64;
        let rows: Vec<[f64; 2 * HARMONICS]> = (0..=n)
            .map(|k| {
                let mut r = [0.0; 2 * HARMONICS];
                for j in 0..HARMONICS {
                    let (s, c) = ((j + 1) as f64 * w * k as f64).sin_cos();
                    r[j] = c - 1.0;
                    r[HARMONICS + j] = s;
                }
                r
            })
            .collect();
        // Per joint: Q_c = Σ_k Δφ_k Δφ_kᵀ / h; the two joints share it.
        let m = 2 * HARMONICS;
        let mut qc = DMatrix::<f64>::zeros(m, m);
        for pair in rows.windows(2) {
            let d: Vec<f64> = (0..m).map(|i| pair[1][i] - pair[0][i]).collect();
            for i in 0..m {
                for j in 0..m {
                    qc[(i, j)] += d[i] * d[j];
                }
            }
        }
        qc /= problem.h;
        let mut q = DMatrix::<f64>::zeros(COEFFS, COEFFS);
        q.view_mut((0, 0), (m, m)).copy_from(&qc);
        q.view_mut((m, m), (m, m)).copy_from(&qc);
        Basis { rows, q }
    }

    /// `α_k` for `k = 0..=N`.
    pub fn shapes(&self, problem: &Problem, p: &Coefficients) -> Vec<Vector2<f64>> {
        let m = 2 * HARMONICS;
        self.rows
            .iter()
            .map(|r| {
                let (mut a1, mut a2) = (problem.alpha0.x, problem.alpha0.y);
                for i in 0..m {
                    a1 += r[i] * p[i];
                    a2 += r[i] * p[m + i];
                }
                Vector2::new(a1, a2)
            })
            .collect()
    }

    /// `J(p) = ½ pᵀQp`.
    pub fn cost(&self, p: &Coefficients) -> f64 {
        let v = DVector::from_column_slice(p.as_slice());
        0.5 * v.dot(&(&self.q * &v))
    }
}

/// Loop coefficients of an ellipse `ᾱ + E(φ₀ + 2πn t/T) − E(φ₀)`, `E(φ) = R(ψ)(a cos φ,
/// b sin φ)` (see [`crate::seed::Ellipse`]); `None` if `n` is not in `1..=K`.
pub fn ellipse_coefficients(e: &crate::seed::Ellipse) -> Option<Coefficients> {
    let j = (e.turns as usize)
        .checked_sub(1)
        .filter(|&j| j < HARMONICS)?;
    let (sp, cp) = e.psi.sin_cos();
    let (s0, c0) = e.phase.sin_cos();
    let rot = |x: f64, y: f64| (cp * x - sp * y, sp * x + cp * y);
    let (ca1, ca2) = rot(e.a * c0, e.b * s0);
    let (sa1, sa2) = rot(-e.a * s0, e.b * c0);
    let mut p = Coefficients::zeros();
    let m = 2 * HARMONICS;
    p[j] = ca1;
    p[HARMONICS + j] = sa1;
    p[m + j] = ca2;
    p[m + HARMONICS + j] = sa2;
    Some(p)
}

/// `c(p) = log(ḡ⁻¹ g_N)` and `∂c/∂p`, exactly, in one forward pass.
///
/// With `g_{k+1} = g_k exp(X_k)` and the left Jacobian (`exp(X + δ) = exp(dexp_X δ) exp(X)`),
/// a change `δX_k` moves the end by `g_N ← exp(Ad_{g_k} dexp_{X_k} δX_k) g_N`, so
///
/// ```text
/// δc = dexp_c⁻¹ Ad_{ḡ⁻¹} Σ_k W_k δX_k,     W_k = Ad_{g_k} dexp_{X_k},
/// δX_k = −h Σ_i (∂A/∂α_i u_k) δα_{k,i} − A(α_k) (δα_{k+1} − δα_k),   δα_k = Φ_k δp.
/// ```
///
/// The coefficient of `δα_k` collects `W_k (A_k − h [∂A/∂α_1 u_k, ∂A/∂α_2 u_k])` from step
/// `k` and `−W_{k−1} A_{k−1}` from step `k − 1`. Errors if the loop leaves the admissible
/// shapes. (The tests check it against the same kinematics run on dual numbers.)
pub fn constraint(
    problem: &Problem,
    basis: &Basis,
    p: &Coefficients,
) -> Result<(Vector3<f64>, SMatrix<f64, 3, COEFFS>), purcell_core::Error> {
    let kin = problem.kinematics::<f64>()?;
    let h = problem.h;
    let alphas = basis.shapes(problem, p);
    // Σ_k (∂σ/∂α_k)_i r_kᵀ for joint i, as 3 × 2K blocks.
    let m = 2 * HARMONICS;
    let mut jac = SMatrix::<f64, 3, COEFFS>::zeros();
    let mut accumulate = |v: &Matrix3x2<f64>, r: &[f64; 2 * HARMONICS]| {
        for row in 0..3 {
            let (v1, v2) = (v[(row, 0)], v[(row, 1)]);
            for (j, &rj) in r.iter().enumerate() {
                jac[(row, j)] += v1 * rj;
                jac[(row, m + j)] += v2 * rj;
            }
        }
    };
    let mut state = State::at_origin(alphas[0]);
    let mut carry = Matrix3x2::<f64>::zeros();
    for (k, pair) in alphas.windows(2).enumerate() {
        let u = (pair[1] - pair[0]) / h;
        let conn = kin.swimmer().connection_with_derivatives(&state.alpha)?;
        let x = kin.twist(&conn.a, &u);
        let w = state.g.adjoint() * se2::dexp(&x);
        let mut dx_dalpha = conn.a;
        dx_dalpha.set_column(0, &(conn.a.column(0) - conn.da[0] * u * h));
        dx_dalpha.set_column(1, &(conn.a.column(1) - conn.da[1] * u * h));
        accumulate(&(w * dx_dalpha + carry), &basis.rows[k]);
        carry = -(w * conn.a);
        // α stays on the basis exactly (α + h·u would differ by rounding only).
        state = State {
            alpha: pair[1],
            g: state.g.compose(&se2::exp(&x)),
        };
        state.check()?;
    }
    if let Some(last) = basis.rows.last() {
        accumulate(&carry, last);
    }
    let target = problem.target_se2::<f64>();
    let c = target.between(&state.g).log();
    let dexp_inv = se2::dexp(&c)
        .try_inverse()
        .ok_or(purcell_core::Error::Singular)?;
    Ok((c, dexp_inv * target.inverse().adjoint() * jac))
}

/// `c(p)` only, in `f64`.
pub fn constraint_value(
    problem: &Problem,
    basis: &Basis,
    p: &Coefficients,
) -> Result<Vector3<f64>, purcell_core::Error> {
    let kin = problem.kinematics::<f64>()?;
    let alphas = basis.shapes(problem, p);
    let mut state = State::at_origin(alphas[0]);
    for pair in alphas.windows(2) {
        let u = (pair[1] - pair[0]) / problem.h;
        state = kin.step(&state, &u)?;
        state.alpha = pair[1];
    }
    Ok(problem.target_se2::<f64>().between(&state.g).log())
}

/// Outcome of the direct method.
#[derive(Clone, Debug, PartialEq)]
pub struct DirectRun {
    /// Final coefficients.
    pub p: Coefficients,
    /// `max |c_i|` there.
    pub violation: f64,
    /// Iterations used.
    pub iterations: usize,
    /// Whether the iteration settled (`|c| ≤ 1e-9` and a step below `1e-7`).
    pub converged: bool,
}

/// Runs SQP with a damped-BFGS Lagrangian Hessian from `p0` (see the module docs).
///
/// Each step solves the QP `min ½dᵀWd + (Qp)ᵀd  s.t.  c + C d = 0` through its KKT system,
/// takes the largest of `1, ½, ¼, …` that lowers the merit `J + ρ|c|₁`, and updates `W`
/// (initially `Q`) by Powell-damped BFGS on `∇L = Qp − Cᵀλ`.
pub fn solve(
    problem: &Problem,
    basis: &Basis,
    p0: &Coefficients,
    max_iterations: usize,
) -> DirectRun {
    let mut run = DirectRun {
        p: *p0,
        violation: f64::INFINITY,
        iterations: 0,
        converged: false,
    };
    let q = SMatrix::<f64, COEFFS, COEFFS>::from_fn(|i, j| basis.q[(i, j)]);
    let mut w = q;
    let mut p = *p0;
    let Ok((mut c, mut cj)) = constraint(problem, basis, &p) else {
        return run;
    };
    run.violation = c.amax();
    let merit = |p: &Coefficients, c: &Vector3<f64>, rho: f64| basis.cost(p) + rho * c.lp_norm(1);
    let mut rho = 1.0f64;
    let mut t_last = 1.0f64;
    const K: usize = COEFFS + 3;
    while run.iterations < max_iterations {
        run.iterations += 1;
        let grad = q * p;
        let kkt = SMatrix::<f64, K, K>::from_fn(|r, col| match (r < COEFFS, col < COEFFS) {
            (true, true) => w[(r, col)],
            (true, false) => cj[(col - COEFFS, r)],
            (false, true) => cj[(r - COEFFS, col)],
            (false, false) => 0.0,
        });
        let rhs =
            SVector::<f64, K>::from_fn(|r, _| if r < COEFFS { -grad[r] } else { -c[r - COEFFS] });
        let Some(sol) = kkt.lu().solve(&rhs) else {
            break;
        };
        let d = Coefficients::from_fn(|i, _| sol[i]);
        // KKT rows read W d + Cᵀν = −Qp, so λ (with ∇L = Qp − Cᵀλ) is −ν.
        let lambda = Vector3::new(-sol[COEFFS], -sol[COEFFS + 1], -sol[COEFFS + 2]);
        rho = rho.max(2.0 * lambda.amax() + 1e-3);
        let m0 = merit(&p, &c, rho);
        // Directional derivative of the merit along d: ∇Jᵀd − ρ|c|₁.
        let slope = grad.dot(&d) - rho * c.lp_norm(1);
        let sufficient = |trial: &Coefficients, ct: &Vector3<f64>, t: f64| {
            merit(trial, ct, rho) <= m0 + 1e-4 * t * slope.min(0.0) + 1e-15 * m0.abs()
        };
        // Backtracking from 4× the last accepted step (at most 1): far from a solution the
        // merit accepts only short steps, often the same length many iterations in a row.
        let mut t = (4.0 * t_last).min(1.0);
        let mut accepted = None;
        while t > 1e-6 {
            let trial = p + d * t;
            if let Ok(ct) = constraint_value(problem, basis, &trial)
                && sufficient(&trial, &ct, t)
            {
                accepted = Some(trial);
                break;
            }
            t *= 0.5;
        }
        let Some(p_new) = accepted else { break };
        t_last = t;
        let Ok((c_new, cj_new)) = constraint(problem, basis, &p_new) else {
            break;
        };
        // Damped BFGS on the Lagrangian gradient with the new multipliers.
        let sv = p_new - p;
        let yv = (q * p_new - cj_new.transpose() * lambda) - (grad - cj.transpose() * lambda);
        let ws = w * sv;
        let sws = sv.dot(&ws);
        let sy = sv.dot(&yv);
        if sws > 0.0 {
            let theta = if sy >= 0.2 * sws {
                1.0
            } else {
                0.8 * sws / (sws - sy)
            };
            let r = yv * theta + ws * (1.0 - theta);
            let sr = sv.dot(&r);
            if sr > 0.0 {
                w = w - ws * ws.transpose() / sws + r * r.transpose() / sr;
            }
        }
        p = p_new;
        c = c_new;
        cj = cj_new;
        run.p = p;
        run.violation = c.amax();
        // Stationarity: |Qp − Cᵀλ| relative to |Qp|.
        let stat = (q * p - cj.transpose() * lambda).amax() / (q * p).amax().max(1e-12);
        if run.violation <= 1e-11 && stat <= 1e-9 {
            run.converged = true;
            break;
        }
    }
    run
}

/// Largest `|α_i|` along the loop.
pub fn max_abs_alpha(shapes: &[Vector2<f64>]) -> f64 {
    shapes.iter().map(|a| a.amax()).fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dual::Dual;
    use crate::seed::Ellipse;

    /// The reference route for `∂c/∂p`: the core's kinematics on dual numbers with one
    /// tangent per loop coefficient.
    fn constraint_by_duals(
        problem: &Problem,
        basis: &Basis,
        p: &Coefficients,
    ) -> (Vector3<f64>, SMatrix<f64, 3, COEFFS>) {
        type D = Dual<COEFFS>;
        let kin = problem.kinematics::<D>().unwrap();
        let m = 2 * HARMONICS;
        let alpha_of = |r: &[f64; 2 * HARMONICS]| {
            let mut a = [D::constant(problem.alpha0.x), D::constant(problem.alpha0.y)];
            let dot = |c: &[f64]| r.iter().zip(c).map(|(x, y)| x * y).sum::<f64>();
            a[0].v += dot(&p.as_slice()[..m]);
            a[1].v += dot(&p.as_slice()[m..]);
            a[0].d[..m].copy_from_slice(r);
            a[1].d[m..].copy_from_slice(r);
            Vector2::new(a[0], a[1])
        };
        let inv_h = D::constant(1.0 / problem.h);
        let mut state = State::at_origin(alpha_of(&basis.rows[0]));
        for pair in basis.rows.windows(2) {
            let next = alpha_of(&pair[1]);
            let u = (next - state.alpha) * inv_h;
            state = kin.step(&state, &u).unwrap();
            state.alpha = next;
        }
        let e = problem.target_se2::<D>().between(&state.g).log();
        (
            Vector3::new(e.x.v, e.y.v, e.z.v),
            SMatrix::<f64, 3, COEFFS>::from_fn(|r, c| e[r].d[c]),
        )
    }

    #[test]
    fn constraint_jacobian_matches_dual_numbers() {
        let mut problem = Problem::paper();
        problem.steps = 2_000;
        problem.h = 0.05;
        let basis = Basis::new(&problem);
        for (turns, phase, psi) in [(1, 0.3, 0.0), (2, 1.1, 0.7), (3, 2.0, -0.4)] {
            let e = Ellipse {
                a: 0.6,
                b: -0.4,
                psi,
                phase,
                turns,
            };
            let mut p = ellipse_coefficients(&e).unwrap();
            // Every harmonic active, so every column of the Jacobian is exercised.
            for (i, x) in p.iter_mut().enumerate() {
                *x += 0.02 * ((i * 7 % 5) as f64 - 2.0);
            }
            let (c, jac) = constraint(&problem, &basis, &p).unwrap();
            let (c_ref, jac_ref) = constraint_by_duals(&problem, &basis, &p);
            assert!((c - c_ref).amax() <= 1e-13, "c {c} vs {c_ref}");
            let scale = jac_ref.amax();
            assert!(scale > 1e-3);
            assert!(
                (jac - jac_ref).amax() <= 1e-11 * scale,
                "Jacobian off by {:e} (scale {scale:e})",
                (jac - jac_ref).amax()
            );
            assert_eq!(c, constraint_value(&problem, &basis, &p).unwrap());
        }
    }
}
