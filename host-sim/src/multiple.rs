//! Multiple shooting: the same law, split into `M` segments whose start states are unknowns.
//!
//! Unknowns: `μ`, `ξ^{−1}`, and for each interior node `j = 1..M−1` at step `k_j`:
//! `(α_{k_j}, x, y, θ of g_{k_j}, ξ^{k_j−1})` (7 numbers). Residuals: for each segment,
//! the end of its replay minus the next node (`Δα`, `log(node⁻¹ g_end)`, `Δξ`), and for the
//! last one the terminal defect of [`crate::shooting`]. Shorter segments make the map far
//! less nonlinear than the single-shooting one, so Newton converges from rougher starts
//! (a direct solution's trajectory and the costate fitted to it). The Jacobian is exact:
//! each segment runs on [`Dual`] numbers with 10 tangents (its 7 start values and `μ`).
//! Steps are damped on `|F|₂` (Levenberg–Marquardt regularisation); between exact
//! Jacobians, steps that converge well reuse the last one with Broyden updates
//! ([`MultipleShooting::solve`]).

use crate::dual::Dual;
use crate::problem::Problem;
use crate::shooting::Unknowns;
use nalgebra::{DMatrix, DVector, Vector2, Vector3};
use purcell_core::{Costate, Real, Replay, Se2, State};

/// Values per interior node.
const NODE: usize = 7;
type D = Dual<10>;

/// A multiple-shooting discretisation with `segments` segments.
#[derive(Clone, Debug)]
pub struct MultipleShooting {
    /// Segment boundaries `0 = k_0 < k_1 < … < k_M = N`.
    pub nodes: Vec<u32>,
}

impl MultipleShooting {
    /// Splits the horizon into `segments` near-equal segments (at least one step each).
    pub fn new(problem: &Problem, segments: u32) -> Self {
        let m = segments.clamp(1, problem.steps);
        let nodes = (0..=m)
            .map(|j| (u64::from(problem.steps) * u64::from(j) / u64::from(m)) as u32)
            .collect();
        MultipleShooting { nodes }
    }

    /// Number of unknowns `5 + 7(M − 1)`.
    pub fn len(&self) -> usize {
        5 + NODE * (self.nodes.len() - 2)
    }

    /// Whether there are no interior nodes (single shooting).
    pub fn is_empty(&self) -> bool {
        self.nodes.len() <= 2
    }

    /// Initial unknowns from a single-shooting `z`: replays it in `f64` and reads the nodes;
    /// if the replay fails, the nodes are filled from the given path `(α_k, g_k)` and the
    /// costate fitted along it (`xi_of(k)` gives `ξ^{k−1}`).
    pub fn from_path(
        &self,
        z: &Unknowns,
        alphas: &[Vector2<f64>],
        gs: &[Vector3<f64>],
        xi_of: impl Fn(usize) -> Vector2<f64>,
    ) -> DVector<f64> {
        let mut y = DVector::zeros(self.len());
        for i in 0..5 {
            y[i] = z[i];
        }
        for (j, &k) in self.nodes[1..self.nodes.len() - 1].iter().enumerate() {
            let k = k as usize;
            let o = 5 + NODE * j;
            let (a, g, xi) = (alphas[k], gs[k], xi_of(k));
            y.rows_mut(o, NODE)
                .copy_from_slice(&[a.x, a.y, g.x, g.y, g.z, xi.x, xi.y]);
        }
        y
    }

    /// Replays segment `s` from its start in `y` and returns its defects (7 values, or the 5
    /// terminal ones for the last segment) and its end `g`. `lift(v, t)` makes the scalar
    /// for the start value `v` of tangent `t` (0..7 the segment's start `(α, x, y, θ, ξ)`,
    /// 7..10 `μ`); values that are not unknowns of the segment are constants.
    fn segment<T: Real>(
        &self,
        problem: &Problem,
        y: &DVector<f64>,
        s: usize,
        lift: impl Fn(f64, usize) -> T,
    ) -> Result<(Vec<T>, Se2<T>), purcell_core::Error> {
        let c = |v: f64| T::from_f64(v);
        let kin = problem.kinematics::<T>()?;
        let mu = Vector3::new(lift(y[0], 7), lift(y[1], 8), lift(y[2], 9));
        let (start, xi) = if s == 0 {
            let a = problem.alpha0.map(c);
            (
                State::at_origin(a),
                Vector2::new(lift(y[3], 5), lift(y[4], 6)),
            )
        } else {
            let o = 5 + NODE * (s - 1);
            let st = State {
                alpha: Vector2::new(lift(y[o], 0), lift(y[o + 1], 1)),
                g: Se2::new(lift(y[o + 2], 2), lift(y[o + 3], 3), lift(y[o + 4], 4)),
            };
            (st, Vector2::new(lift(y[o + 5], 5), lift(y[o + 6], 6)))
        };
        let steps = self.nodes[s + 1] - self.nodes[s];
        let mut replay = Replay::new(kin, start, Costate { mu, xi }, steps, &[])?;
        while replay.step()?.is_some() {}
        let end = *replay.state();
        let xi_end = *replay.xi();
        if s + 2 == self.nodes.len() {
            let e = problem.target_se2::<T>().between(&end.g).log();
            let a0 = problem.alpha0;
            let vals = vec![end.alpha.x - c(a0.x), end.alpha.y - c(a0.y), e.x, e.y, e.z];
            return Ok((vals, end.g));
        }
        let o = 5 + NODE * s;
        let node = Se2::new(c(y[o + 2]), c(y[o + 3]), c(y[o + 4]));
        let e = node.between(&end.g).log();
        let vals = vec![
            end.alpha.x - c(y[o]),
            end.alpha.y - c(y[o + 1]),
            e.x,
            e.y,
            e.z,
            xi_end.x - c(y[o + 5]),
            xi_end.y - c(y[o + 6]),
        ];
        Ok((vals, end.g))
    }

    /// First residual row of segment `s`.
    fn row(&self, s: usize) -> usize {
        if s + 2 == self.nodes.len() {
            self.len() - 5
        } else {
            NODE * s
        }
    }

    /// The residuals at `y`, in `f64`.
    pub fn residuals(
        &self,
        problem: &Problem,
        y: &DVector<f64>,
    ) -> Result<DVector<f64>, purcell_core::Error> {
        let mut f = DVector::zeros(self.len());
        for s in 0..self.nodes.len() - 1 {
            let (vals, _) = self.segment(problem, y, s, |v, _| v)?;
            f.rows_mut(self.row(s), vals.len()).copy_from_slice(&vals);
        }
        Ok(f)
    }

    /// The residuals and their exact Jacobian at `y`.
    pub fn evaluate(
        &self,
        problem: &Problem,
        y: &DVector<f64>,
    ) -> Result<(DVector<f64>, DMatrix<f64>), purcell_core::Error> {
        let n = self.len();
        let mut f = DVector::zeros(n);
        let mut jm = DMatrix::zeros(n, n);
        for s in 0..self.nodes.len() - 1 {
            let (vals, end_g) = self.segment(problem, y, s, D::variable)?;
            let row = self.row(s);
            // Columns of the segment's start values (tangents 0..7).
            let start_cols: Vec<(usize, usize)> = if s == 0 {
                vec![(5, 3), (6, 4)]
            } else {
                let o = 5 + NODE * (s - 1);
                (0..NODE).map(|t| (t, o + t)).collect()
            };
            for (i, v) in vals.iter().enumerate() {
                f[row + i] = v.v;
                for &(t, col) in &start_cols {
                    jm[(row + i, col)] += v.d[t];
                }
                for t in 0..3 {
                    jm[(row + i, t)] += v.d[7 + t];
                }
            }
            if s + 2 == self.nodes.len() {
                continue;
            }
            // ∂/∂(next node): −I for α and ξ; for g, −(∂log(node⁻¹g)/∂node) by duals.
            let o = 5 + NODE * s;
            jm[(row, o)] -= 1.0;
            jm[(row + 1, o + 1)] -= 1.0;
            jm[(row + 5, o + 5)] -= 1.0;
            jm[(row + 6, o + 6)] -= 1.0;
            let gend = Se2::new(
                D::constant(end_g.x().v),
                D::constant(end_g.y().v),
                D::constant(end_g.theta().v),
            );
            let node = Se2::new(
                D::variable(y[o + 2], 0),
                D::variable(y[o + 3], 1),
                D::variable(y[o + 4], 2),
            );
            let e = node.between(&gend).log();
            for i in 0..3 {
                for t in 0..3 {
                    jm[(row + 2 + i, o + 2 + t)] += e[i].d[t];
                }
            }
        }
        Ok((f, jm))
    }

    /// Damped Newton / Levenberg–Marquardt on the residuals; returns the best `y`, its
    /// `max |F_i|` and the iterations used.
    ///
    /// A step that removes at least half of the largest defect keeps its Jacobian, updated by
    /// Broyden's rank-one formula, for the next step: a residual costs a fifteenth of a
    /// Jacobian (plain `f64` against 10-tangent duals), and from a good start Newton spends
    /// most of its steps there. A step the updated Jacobian does not make good is retried
    /// with a fresh one before any damping; slower progress also refreshes it.
    pub fn solve(
        &self,
        problem: &Problem,
        y0: &DVector<f64>,
        tolerance: f64,
        max_iterations: usize,
    ) -> (DVector<f64>, f64, usize) {
        let mut y = y0.clone();
        let Ok((mut f, mut j)) = self.evaluate(problem, &y) else {
            return (y, f64::INFINITY, 0);
        };
        let mut fresh = true;
        let mut it = 0;
        let mut lambda = 0.0f64;
        let (mut last, mut slow) = (f.amax(), 0);
        while f.amax() > tolerance && it < max_iterations {
            it += 1;
            let norm = f.norm();
            let mut lu = j.clone().lu();
            let mut accepted = None;
            for _ in 0..30 {
                let step = if lambda == 0.0 {
                    lu.solve(&(-&f))
                } else {
                    let jt = j.transpose();
                    let mut a = &jt * &j;
                    let dmax = a.diagonal().max();
                    for i in 0..a.nrows() {
                        a[(i, i)] += lambda * (a[(i, i)] + 1e-12 * dmax);
                    }
                    a.cholesky().map(|c| c.solve(&(-(&jt * &f))))
                };
                if let Some(step) = step.filter(|s| s.iter().all(|v| v.is_finite())) {
                    let trial = &y + &step;
                    if let Ok(ft) = self.residuals(problem, &trial)
                        && ft.norm() < norm
                    {
                        accepted = Some((trial, ft));
                        lambda = if lambda < 1e-9 { 0.0 } else { lambda * 0.1 };
                        break;
                    }
                }
                if !fresh {
                    // A kept Jacobian failed: refresh it before damping.
                    let Ok((_, jy)) = self.evaluate(problem, &y) else {
                        break;
                    };
                    j = jy;
                    lu = j.clone().lu();
                    fresh = true;
                    continue;
                }
                lambda = if lambda == 0.0 { 1e-6 } else { lambda * 10.0 };
                if lambda > 1e8 {
                    break;
                }
            }
            let Some((y_new, f_new)) = accepted else {
                break;
            };
            let r = f_new.amax();
            let keep = r <= 0.5 * last && lambda == 0.0;
            let s = &y_new - &y;
            let df = &f_new - &f;
            y = y_new;
            f = f_new;
            if r <= tolerance {
                break;
            }
            if keep {
                // Broyden's update: the least change to J that maps s to df.
                let ss = s.norm_squared();
                if ss > 0.0 {
                    let js = &j * &s;
                    j += (df - js) * (s.transpose() / ss);
                }
                fresh = false;
            } else {
                match self.evaluate(problem, &y) {
                    Ok((_, jy)) => {
                        j = jy;
                        fresh = true;
                    }
                    Err(_) => break,
                }
            }
            // Give up on a start that stalls: two iterations in a row that each remove
            // less than 10 % of the largest defect (converging starts remove ≥ 45 % per
            // iteration on the paper's problem; stalled ones creep at 1–5 % for the
            // remaining iterations).
            slow = if r > 0.9 * last { slow + 1 } else { 0 };
            last = r;
            if slow >= 2 {
                break;
            }
        }
        let r = f.amax();
        (y, r, it)
    }
}
