//! Starting guesses for Newton: shape loops and a linear least-squares fit of `(μ, ξ^{−1})`.
//!
//! Along any trajectory `(α_k, g_k, u_k)` the law's quantities are linear in the unknowns
//! (MODEL.md §5, "Seeding"): with `Ad_{g}ᵀ μ = M_k μ` and `Z_k = dexp_{X_k}ᵀ M_k`,
//!
//! ```text
//! ζ^k = Z_k μ,   (B_k u_k)_i = ((∂A/∂α_i) u_k)ᵀ Z_k μ,   ξ^k = ξ^{−1} + P_k μ,
//! P_k = Σ_{j≤k} h·[((∂A/∂α_1) u_j)ᵀ; ((∂A/∂α_2) u_j)ᵀ] Z_j,
//! u_k = ξ^k − A_kᵀ ζ^k = [P_k − A_kᵀ Z_k | I₂] (μ, ξ^{−1})
//! ```
//!
//! Stacking the last line over all `k` gives `2N` equations in five unknowns; their
//! least-squares solution (by SVD, columns scaled) reproduces an extremal exactly and is a
//! starting guess for any other loop.
//!
//! The loops are ellipses through `ᾱ` run `n` times over the horizon:
//! `α(t) = ᾱ + E(φ₀ + 2π n t/T) − E(φ₀)`, `E(φ) = R(ψ)·(a cos φ, b sin φ)`.

use crate::problem::Problem;
use crate::shooting::Unknowns;
use nalgebra::{DMatrix, DVector, Matrix2x3, Matrix3, Vector2, Vector3};
use purcell_core::{Connection, Se2, State, se2};

/// A closed elliptic loop in the shape plane through `ᾱ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipse {
    /// Semi-axis along `ψ`, radians.
    pub a: f64,
    /// Semi-axis across `ψ`, radians; its sign sets the direction of travel.
    pub b: f64,
    /// Orientation `ψ` of the first axis, radians.
    pub psi: f64,
    /// Phase `φ₀` of `ᾱ` on the ellipse, radians.
    pub phase: f64,
    /// Turns over the horizon (the turning number).
    pub turns: u32,
}

impl Ellipse {
    /// `α_k` for `k = 0..=N`; the last equals `ᾱ` up to rounding and is set to it exactly.
    pub fn shapes(&self, problem: &Problem) -> Vec<Vector2<f64>> {
        let n = problem.steps as usize;
        let (sp, cp) = self.psi.sin_cos();
        let e = |phi: f64| {
            let (s, c) = phi.sin_cos();
            let (p, q) = (self.a * c, self.b * s);
            Vector2::new(cp * p - sp * q, sp * p + cp * q)
        };
        let e0 = e(self.phase);
        let w = 2.0 * core::f64::consts::PI * f64::from(self.turns) / n as f64;
        let mut out: Vec<_> = (0..=n)
            .map(|k| problem.alpha0 + e(self.phase + w * k as f64) - e0)
            .collect();
        if let Some(last) = out.last_mut() {
            *last = problem.alpha0;
        }
        out
    }

    /// Largest `|α_i|` on the loop.
    pub fn max_abs_alpha(&self, problem: &Problem) -> f64 {
        self.shapes(problem)
            .iter()
            .map(|a| a.amax())
            .fold(0.0, f64::max)
    }
}

/// Runs the kinematics along the shape path `alphas` (`α_k` kept on the path) and calls
/// `visit(k, u_k, connection at α_k, dexp_{X_k}ᵀ, g_k)` for each step; `None` if the path
/// leaves the admissible shapes.
fn along_path(
    problem: &Problem,
    alphas: &[Vector2<f64>],
    mut visit: impl FnMut(usize, &Vector2<f64>, &Connection<f64>, &Matrix3<f64>, &Se2<f64>),
) -> Option<()> {
    let kin = problem.kinematics::<f64>().ok()?;
    let mut state = State::at_origin(*alphas.first()?);
    for (k, pair) in alphas.windows(2).enumerate() {
        let u = (pair[1] - pair[0]) / problem.h;
        let conn = problem
            .swimmer
            .connection_with_derivatives(&state.alpha)
            .ok()?;
        let dexp_t = se2::dexp(&kin.twist(&conn.a, &u)).transpose();
        visit(k, &u, &conn, &dexp_t, &state.g);
        state = kin.step(&state, &u).ok()?;
        state.alpha = pair[1];
    }
    Some(())
}

/// Fits `(μ, ξ^{−1})` to the shape path `alphas` (length `N + 1`); `None` if the path is
/// not admissible or the fit is degenerate.
pub fn fit(problem: &Problem, alphas: &[Vector2<f64>]) -> Option<Unknowns> {
    let n = problem.steps as usize;
    if alphas.len() != n + 1 {
        return None;
    }
    let h = problem.h;
    let mut rows = DMatrix::<f64>::zeros(2 * n, 5);
    let mut rhs = DVector::<f64>::zeros(2 * n);
    let mut p = Matrix2x3::<f64>::zeros();
    along_path(problem, alphas, |k, u, conn, dexp_t, g| {
        // Z_k = dexp_{X_k}ᵀ Ad_{g_k}ᵀ, so that ζ^k = Z_k μ.
        let z = dexp_t * g.adjoint().transpose();
        let c1 = (conn.da[0] * u).transpose() * z;
        let c2 = (conn.da[1] * u).transpose() * z;
        p += Matrix2x3::from_rows(&[c1, c2]) * h;
        let coef = p - conn.a.transpose() * z;
        for i in 0..2 {
            let r = 2 * k + i;
            for j in 0..3 {
                rows[(r, j)] = coef[(i, j)];
            }
            rows[(r, 3 + i)] = 1.0;
            rhs[r] = u[i];
        }
    })?;
    // Column scaling, then SVD least squares.
    let scale: Vec<f64> = (0..5).map(|j| rows.column(j).norm().max(1e-300)).collect();
    for (j, s) in scale.iter().enumerate() {
        rows.column_mut(j).scale_mut(1.0 / s);
    }
    let sol = rows.svd(true, true).solve(&rhs, 1e-12).ok()?;
    let z = Unknowns::from_fn(|j, _| sol[j] / scale[j]);
    z.iter().all(|v| v.is_finite()).then_some(z)
}

/// The costates `ξ^{k−1}` (`k = 0..=N`) that the linear law of [`fit`] assigns along the
/// path for the unknowns `z` (`ξ^{−1}` first).
pub fn fitted_costates(
    problem: &Problem,
    alphas: &[Vector2<f64>],
    z: &Unknowns,
) -> Option<Vec<Vector2<f64>>> {
    let h = problem.h;
    let mu = Vector3::new(z[0], z[1], z[2]);
    let mut xi = Vector2::new(z[3], z[4]);
    let mut out = vec![xi];
    along_path(problem, alphas, |_, u, conn, dexp_t, g| {
        let zeta = dexp_t * g.adjoint_transpose_mul(&mu);
        xi += Vector2::new((conn.da[0] * u).dot(&zeta), (conn.da[1] * u).dot(&zeta)) * h;
        out.push(xi);
    })?;
    Some(out)
}

/// The default family of seed loops: sizes, aspect ratios, orientations, phases, directions
/// and turning numbers, keeping `|α_i| ≤ 0.9·α_max` on the loop.
pub fn default_loops(problem: &Problem, count: usize) -> Vec<Ellipse> {
    let pi = core::f64::consts::PI;
    let mut all = Vec::new();
    for turns in [1u32, 2, 3] {
        for size in [0.6, 1.0, 1.4] {
            for aspect in [1.0, 0.6] {
                for psi in [0.0, 0.25 * pi, 0.5 * pi, 0.75 * pi] {
                    for phase in [0.0, 0.5 * pi, pi, 1.5 * pi] {
                        for dir in [1.0, -1.0] {
                            let e = Ellipse {
                                a: size,
                                b: dir * aspect * size,
                                psi,
                                phase,
                                turns,
                            };
                            all.push(e);
                        }
                    }
                }
            }
        }
    }
    all.retain(|e| e.max_abs_alpha(problem) <= 0.9 * problem.alpha_max);
    all.truncate(count);
    all
}
