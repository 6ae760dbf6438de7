//! The shooting map and its Newton solver.
//!
//! The unknowns are `z = (μ, ξ^{−1}) ∈ R⁵`. The shooting map runs the core's control law
//! ([`purcell_core::Kinematics::law_step`], through [`purcell_core::Replay`]) for `N` steps
//! from `(ᾱ, e)` and returns the terminal defect
//!
//! ```text
//! F(z) = (α_N − ᾱ,  log(ḡ⁻¹ g_N)) ∈ R² × R³
//! ```
//!
//! Running the same generic code on [`Dual`] numbers seeded with the identity gives `F` and
//! its exact Jacobian `∂F/∂z` in one pass (no finite differences).
//!
//! The Jacobian is badly conditioned (≈ 4e8 on the paper's problem), so the solver is
//! Levenberg–Marquardt with Moré's column scaling `D = diag(max column norms of J)`: the step
//! minimises `|J δ + F|² + λ|D δ|²`, computed from the SVD of `J D⁻¹` (no normal equations,
//! whose condition would be squared). A trial step is accepted when it lowers `|F|`;
//! otherwise, and whenever the law leaves the admissible shapes (`|α_i| ≥ π`, the core's
//! [`purcell_core::Error::ShapeLimit`]) or overflows, the step is rejected and `λ` raised.
//! Near a solution `λ → 0` and the iteration is Newton's, converging quadratically.

use crate::dual::Dual;
use crate::problem::Problem;
use nalgebra::{Matrix5, SMatrix, SVector, Vector2, Vector3, Vector5};
use purcell_core::{Costate, Real, Replay, State};

/// Shooting unknowns `(μx, μy, μθ, ξ1, ξ2)`.
pub type Unknowns = Vector5<f64>;

/// Splits `z` into a core [`Costate`].
pub fn costate<T: Real>(z: &Unknowns) -> Costate<T> {
    let c = T::from_f64;
    Costate {
        mu: Vector3::new(c(z[0]), c(z[1]), c(z[2])),
        xi: Vector2::new(c(z[3]), c(z[4])),
    }
}

/// The terminal defect `F(z)` in scalar type `T`, for a costate given in `T`.
pub fn defect<T: Real>(
    problem: &Problem,
    costate: Costate<T>,
) -> Result<SVector<T, 5>, purcell_core::Error> {
    let kin = problem.kinematics::<T>()?;
    let alpha0 = problem.alpha0.map(T::from_f64);
    let replay = Replay::new(kin, State::at_origin(alpha0), costate, problem.steps, &[])?;
    let end = replay.finish()?;
    let e = problem.target_se2::<T>().between(&end.g).log();
    Ok(SVector::<T, 5>::new(
        end.alpha.x - alpha0.x,
        end.alpha.y - alpha0.y,
        e.x,
        e.y,
        e.z,
    ))
}

/// `F(z)` in `f64`.
pub fn residual(problem: &Problem, z: &Unknowns) -> Result<Vector5<f64>, purcell_core::Error> {
    defect::<f64>(problem, costate(z))
}

/// `F(z)` and `∂F/∂z`, by one replay on [`Dual`] numbers.
pub fn residual_and_jacobian(
    problem: &Problem,
    z: &Unknowns,
) -> Result<(Vector5<f64>, Matrix5<f64>), purcell_core::Error> {
    let var = |i: usize| Dual::<5>::variable(z[i], i);
    let cs = Costate {
        mu: Vector3::new(var(0), var(1), var(2)),
        xi: Vector2::new(var(3), var(4)),
    };
    let f = defect::<Dual<5>>(problem, cs)?;
    let value = f.map(|d| d.v);
    let jac = Matrix5::from_fn(|r, c| f[r].d[c]);
    Ok((value, jac))
}

/// Largest absolute component.
pub fn max_abs(v: &Vector5<f64>) -> f64 {
    v.amax()
}

/// Settings of the Newton (Levenberg–Marquardt) iteration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonOptions {
    /// Stop when `max |F_i|` is at or below this.
    pub tolerance: f64,
    /// Most Jacobian evaluations (accepted steps).
    pub max_iterations: usize,
    /// Most residual evaluations in all (accepted and rejected trials).
    pub max_evaluations: usize,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        NewtonOptions {
            tolerance: 1e-13,
            max_iterations: 60,
            max_evaluations: 250,
        }
    }
}

/// The outcome of one Newton run (converged or not).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonRun {
    /// Best unknowns reached.
    pub z: Unknowns,
    /// `max |F_i|` there.
    pub residual: f64,
    /// Accepted steps (Jacobian evaluations less one).
    pub iterations: usize,
    /// Residual evaluations, including rejected trials.
    pub evaluations: usize,
    /// Whether `residual ≤ tolerance`.
    pub converged: bool,
}

/// Levenberg–Marquardt on `F(z) = 0` from `z0` (see the module docs).
///
/// Never fails: a start where the law cannot even be run returns `residual = ∞`.
pub fn newton(problem: &Problem, z0: &Unknowns, opts: &NewtonOptions) -> NewtonRun {
    let mut run = NewtonRun {
        z: *z0,
        residual: f64::INFINITY,
        iterations: 0,
        evaluations: 1,
        converged: false,
    };
    let Ok((mut f, mut jac)) = residual_and_jacobian(problem, z0) else {
        return run;
    };
    let mut z = *z0;
    run.residual = max_abs(&f);
    let mut scale = Vector5::<f64>::zeros();
    // λ relative to the largest squared singular value of the scaled Jacobian; 0 = Newton.
    let mut lambda = 0.0f64;
    while run.residual > opts.tolerance
        && run.iterations < opts.max_iterations
        && run.evaluations < opts.max_evaluations
    {
        for (s, col) in scale.iter_mut().zip(jac.column_iter()) {
            *s = s.max(col.norm());
        }
        if scale.iter().any(|&s| !(s > 0.0 && s.is_finite())) {
            break;
        }
        let scaled = Matrix5::from_fn(|r, c| jac[(r, c)] / scale[c]);
        let svd = scaled.svd(true, true);
        let (Some(u), Some(vt)) = (svd.u, svd.v_t) else {
            break;
        };
        let s = svd.singular_values;
        let smax = s.max();
        let utf = u.transpose() * f;
        let norm_f = f.norm();
        let mut accepted = false;
        while run.evaluations < opts.max_evaluations {
            let mu = lambda * smax * smax;
            // δ' = −V diag(s/(s² + μ)) Uᵀ F, δ = D⁻¹ δ'.
            let coeff = Vector5::from_fn(|i, _| {
                let si = s[i];
                if si > 1e-15 * smax {
                    -si / (si * si + mu) * utf[i]
                } else {
                    0.0
                }
            });
            let step = (vt.transpose() * coeff).component_div(&scale);
            let trial = z + step;
            run.evaluations += 1;
            match residual(problem, &trial) {
                Ok(ft) if ft.norm() < norm_f => {
                    z = trial;
                    accepted = true;
                    lambda = if lambda < 1e-12 { 0.0 } else { lambda * 0.1 };
                    break;
                }
                _ => {
                    lambda = if lambda == 0.0 { 1e-8 } else { lambda * 10.0 };
                    if lambda > 1e6 {
                        break;
                    }
                }
            }
        }
        if !accepted {
            break;
        }
        run.evaluations += 1;
        match residual_and_jacobian(problem, &z) {
            Ok((fz, jz)) => {
                f = fz;
                jac = jz;
            }
            Err(_) => break,
        }
        run.iterations += 1;
        let r = max_abs(&f);
        if r < run.residual {
            run.residual = r;
            run.z = z;
        }
    }
    run.converged = run.residual <= opts.tolerance;
    run
}

/// A convenience alias for 5×5 matrices in other modules.
pub type Jacobian = SMatrix<f64, 5, 5>;

/// Settings of the homotopy that carries a fitted start to the target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HomotopyOptions {
    /// First step in `s`.
    pub initial_step: f64,
    /// Smallest step in `s` before giving up.
    pub min_step: f64,
    /// Chord-Newton corrections per step before the step is halved.
    pub corrector_iterations: usize,
    /// Jacobian evaluations allowed over the whole path.
    pub max_jacobians: usize,
}

impl Default for HomotopyOptions {
    fn default() -> Self {
        HomotopyOptions {
            initial_step: 0.25,
            min_step: 1e-3,
            corrector_iterations: 6,
            max_jacobians: 60,
        }
    }
}

/// Outcome of a homotopy run: where it stopped and how far it got.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HomotopyRun {
    /// Unknowns at the last accepted point.
    pub z: Unknowns,
    /// Homotopy parameter reached (1 = the real target).
    pub s: f64,
    /// Jacobian evaluations used.
    pub jacobians: usize,
    /// Residual evaluations used.
    pub evaluations: usize,
}

/// Newton homotopy `H(z, s) = F(z) − (1 − s)·F(z₀) = 0` from `s = 0` (solved by `z₀`) to
/// `s = 1` (the problem itself), followed by pseudo-arclength continuation.
///
/// The path `y = (z, s)` is followed in arclength, so it passes folds where `s` turns back.
/// Each step predicts along the unit tangent `t` (the null vector of `[J | F(z₀)]`, oriented
/// as the previous one), then corrects by Newton on `(H(y), tᵀ(y − y_pred)) = 0` with the
/// predictor's 6×6 matrix (chord, `f64` residuals only). A failed correction, or a law that
/// leaves the admissible shapes, halves the step. The returned point is a start for
/// [`newton`] when `s = 1`.
pub fn homotopy(problem: &Problem, z0: &Unknowns, opts: &HomotopyOptions) -> HomotopyRun {
    use nalgebra::{SMatrix, SVector};
    let mut run = HomotopyRun {
        z: *z0,
        s: 0.0,
        jacobians: 0,
        evaluations: 0,
    };
    let Ok((f0, mut jac)) = residual_and_jacobian(problem, z0) else {
        return run;
    };
    run.jacobians = 1;
    let mut y = SVector::<f64, 6>::from_fn(|i, _| if i < 5 { z0[i] } else { 0.0 });
    let mut prev_t: Option<SVector<f64, 6>> = None;
    let mut ds = opts.initial_step;
    let tol = 1e-10 + 1e-7 * f0.amax();
    let ext = |j: &Matrix5<f64>| {
        SMatrix::<f64, 5, 6>::from_fn(|r, c| if c < 5 { j[(r, c)] } else { f0[r] })
    };
    while run.jacobians < opts.max_jacobians {
        // Tangent: null vector of [J | F0]: solve J v = −F0 with v_s = 1, normalise.
        let Some(v) = jac.lu().solve(&(-f0)) else {
            break;
        };
        let mut t = SVector::<f64, 6>::from_fn(|i, _| if i < 5 { v[i] } else { 1.0 });
        t /= t.norm();
        if let Some(p) = prev_t
            && p.dot(&t) < 0.0
        {
            t = -t;
        }
        let a = ext(&jac);
        let m = SMatrix::<f64, 6, 6>::from_fn(|r, c| if r < 5 { a[(r, c)] } else { t[c] });
        let Some(lu) = Some(m.lu()).filter(|lu| lu.is_invertible()) else {
            break;
        };
        let mut ok = false;
        let mut trial = y;
        // Do not overshoot s = 1 by much: shorten the step to land near it.
        let mut step = ds;
        if t[5] > 0.0 && y[5] + step * t[5] > 1.0 {
            step = (1.0 - y[5]) / t[5];
        }
        let pred = y + t * step;
        trial.copy_from(&pred);
        let mut last = f64::INFINITY;
        for _ in 0..opts.corrector_iterations {
            run.evaluations += 1;
            let z = trial.fixed_rows::<5>(0).into_owned();
            let Ok(f) = residual(problem, &z) else { break };
            let h = f - f0 * (1.0 - trial[5]);
            let r = h.amax();
            if r <= tol {
                ok = true;
                break;
            }
            if r > 0.5 * last {
                break;
            }
            last = r;
            let rhs = SVector::<f64, 6>::from_fn(|i, _| {
                if i < 5 {
                    -h[i]
                } else {
                    -(t.dot(&(trial - pred)))
                }
            });
            let Some(d) = lu.solve(&rhs) else { break };
            trial += d;
        }
        if !ok {
            ds *= 0.5;
            if ds < opts.min_step {
                break;
            }
            continue;
        }
        y = trial;
        prev_t = Some(t);
        run.z = y.fixed_rows::<5>(0).into_owned();
        run.s = y[5];
        match residual_and_jacobian(problem, &run.z) {
            Ok((_, j)) => jac = j,
            Err(_) => break,
        }
        run.jacobians += 1;
        if (run.s - 1.0).abs() <= 1e-9 {
            break;
        }
        ds *= 1.5;
    }
    run
}
