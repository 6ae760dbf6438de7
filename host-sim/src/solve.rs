//! The multi-start solver: direct loops → fitted costate → multiple shooting → extremals.
//!
//! For each start (an elliptic shape loop, [`crate::seed`]):
//! 1. the direct method of [`crate::direct`] improves the loop towards a KKT point of the
//!    truncated-Fourier problem;
//! 2. `(μ, ξ^{−1})` and the costate path are fitted to it ([`crate::seed::fit`]);
//! 3. Newton on the multiple-shooting system ([`crate::multiple`]) converges to an exact
//!    extremal of the discrete problem (all segment defects and the terminal defect ≤ 1e-12).
//!
//! Starts run in parallel (rayon). Converged extremals are deduplicated by their unknowns,
//! classified as admissible or not (`max |α_i| < α_max`), and the cheapest admissible one
//! is returned.

use crate::direct::{self, Basis};
use crate::kkt;
use crate::multiple::MultipleShooting;
use crate::problem::Problem;
use crate::seed::{self, Ellipse};
use crate::shooting::{self, Unknowns};
use nalgebra::{DVector, Vector2, Vector3};
use purcell_core::{Costate, Replay, State};
use rayon::prelude::*;

/// Solver settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveOptions {
    /// Number of starts.
    pub starts: usize,
    /// Seed of the start generator (0: the built-in list first).
    pub seed: u64,
    /// Multiple-shooting segments.
    pub segments: u32,
    /// Iterations of the direct method per start.
    pub direct_iterations: usize,

    /// Newton iterations of multiple shooting per start.
    pub newton_iterations: usize,
    /// Convergence threshold on the largest defect.
    pub tolerance: f64,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            starts: 8,
            seed: 0,
            segments: 20,
            direct_iterations: 60,
            newton_iterations: 25,
            tolerance: 1e-12,
        }
    }
}

/// One extremal (or one failed start).
#[derive(Clone, Debug, PartialEq)]
pub struct Extremal {
    /// Start index that produced it.
    pub start: usize,
    /// Initial costate `(μ, ξ^{−1})`.
    pub z: Unknowns,
    /// `J = Σ h/2 |u_k|²`.
    pub cost: f64,
    /// Largest defect of the multiple-shooting system (including the five terminal ones).
    pub residual: f64,
    /// The five terminal defects of the stitched trajectory, largest absolute value.
    pub terminal_residual: f64,
    /// Terminal defect of a plain `f64` replay from `(μ, ξ^{−1})` alone (no checkpoints).
    pub single_shooting_residual: f64,
    /// Largest `|α_i|` along the path.
    pub max_abs_alpha: f64,
    /// Whether `max_abs_alpha < α_max`.
    pub admissible: bool,
    /// `max |∂L/∂u_k| / h` ([`crate::kkt`]).
    pub kkt_residual: f64,
    /// Newton iterations (multiple shooting).
    pub newton_iterations: usize,
    /// The trajectory.
    pub trajectory: Trajectory,
}

/// A trajectory on the grid: `k = 0..N` states, `k < N` controls, costates `ξ^{k−1}`.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Trajectory {
    /// `(α_k, g_k)`, `k = 0..=N`.
    pub states: Vec<State<f64>>,
    /// `u_k`, `k < N`.
    pub controls: Vec<Vector2<f64>>,
    /// `ξ^{k−1}`, `k = 0..=N` (the first is `ξ^{−1}`).
    pub xis: Vec<Vector2<f64>>,
}

/// Outcome of a solve.
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    /// Index into `extremals` of the returned one.
    pub best: usize,
    /// Every distinct converged extremal, cheapest first.
    pub extremals: Vec<Extremal>,
    /// Starts tried.
    pub starts: usize,
}

/// Why no extremal was returned.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// No start converged.
    #[error(
        "no start reached the target: best residual {best_residual:.3e} (tolerance {tolerance:.0e})"
    )]
    Unreachable {
        /// Smallest largest-defect reached by any start.
        best_residual: f64,
        /// The tolerance.
        tolerance: f64,
    },
    /// Extremals were found but none is admissible.
    #[error(
        "{found} extremal(s) found, none admissible (smallest max |alpha_i| = {best_alpha:.4} rad >= alpha-max)"
    )]
    NoneAdmissible {
        /// How many.
        found: usize,
        /// Smallest of their largest `|α_i|`.
        best_alpha: f64,
    },
}

/// The start loops: the built-in list (for seed 0), then pseudo-random ellipses.
pub fn start_loops(problem: &Problem, options: &SolveOptions) -> Vec<Ellipse> {
    let pi = core::f64::consts::PI;
    let mut list = Vec::new();
    if options.seed == 0 {
        for (turns, a, phase, dir) in [
            (2, 0.5, 0.5, -1.0),
            (1, 1.0, 1.5, -1.0),
            (2, 1.0, 1.0, -1.0),
            (3, 0.5, 1.0, -1.0),
            (1, 0.5, 1.0, 1.0),
            (2, 0.5, 1.5, 1.0),
            (3, 0.5, 0.5, 1.0),
            (1, 1.0, 0.0, 1.0),
        ] {
            list.push(Ellipse {
                a,
                b: dir * a,
                psi: 0.0,
                phase: phase * pi,
                turns,
            });
        }
    }
    // xorshift64*, deterministic in the seed.
    let mut state = options.seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut next = || {
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        (state.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    };
    while list.len() < options.starts {
        let a = 0.3 + 0.9 * next();
        let e = Ellipse {
            a,
            b: a * (0.5 + 0.5 * next()) * if next() < 0.5 { -1.0 } else { 1.0 },
            psi: pi * next(),
            phase: 2.0 * pi * next(),
            turns: 1 + (3.0 * next()) as u32,
        };
        if e.max_abs_alpha(problem) < 0.9 * problem.alpha_max {
            list.push(e);
        }
    }
    list.truncate(options.starts);
    list
}

/// Steps 1–2 for one start loop: the direct method's loop, the costate fitted to it, and
/// from them the multiple-shooting system and its starting unknowns; `None` if the loop
/// leaves the admissible shapes or the fit is degenerate.
pub fn shooting_start(
    problem: &Problem,
    basis: &Basis,
    e: &Ellipse,
    options: &SolveOptions,
) -> Option<(MultipleShooting, DVector<f64>)> {
    let p0 = direct::ellipse_coefficients(e)?;
    let d = direct::solve(problem, basis, &p0, options.direct_iterations);
    let shapes = basis.shapes(problem, &d.p);
    let z = seed::fit(problem, &shapes)?;
    let xis = seed::fitted_costates(problem, &shapes, &z)?;
    let kin = problem.kinematics::<f64>().ok()?;
    let mut st = State::at_origin(*shapes.first()?);
    let mut gs = vec![Vector3::zeros()];
    for w in shapes.windows(2) {
        st = kin.step(&st, &((w[1] - w[0]) / problem.h)).ok()?;
        st.alpha = w[1];
        gs.push(st.g.to_xytheta());
    }
    let ms = MultipleShooting::new(problem, options.segments);
    let y0 = ms.from_path(&z, &shapes, &gs, |k| xis[k]);
    Some((ms, y0))
}

/// Runs one start; `Err(best residual)` if it did not converge.
pub fn run_start(
    problem: &Problem,
    basis: &Basis,
    e: &Ellipse,
    index: usize,
    options: &SolveOptions,
) -> Result<Extremal, f64> {
    let (ms, y0) = shooting_start(problem, basis, e, options).ok_or(f64::INFINITY)?;
    let (y, residual, iterations) =
        ms.solve(problem, &y0, options.tolerance, options.newton_iterations);
    if residual.is_nan() || residual > options.tolerance {
        return Err(residual);
    }
    let z = Unknowns::from_fn(|i, _| y[i]);
    let trajectory = stitch(problem, &ms, &y).map_err(|_| residual)?;
    let end = trajectory.states.last().copied().ok_or(residual)?;
    let e_end = problem.target_se2::<f64>().between(&end.g).log();
    let terminal = (end.alpha - problem.alpha0).amax().max(e_end.amax());
    let single = shooting::residual(problem, &z).map_or(f64::INFINITY, |f| f.amax());
    let cost: f64 = trajectory
        .controls
        .iter()
        .map(|u| 0.5 * problem.h * u.norm_squared())
        .sum();
    let max_abs_alpha = trajectory
        .states
        .iter()
        .map(|s| s.alpha.amax())
        .fold(0.0, f64::max);
    let mu = Vector3::new(z[0], z[1], z[2]);
    let xi_last = trajectory.xis.last().copied().unwrap_or_default();
    let n = trajectory.controls.len();
    let kkt_residual = kkt::kkt_residual(
        problem,
        &trajectory.states[..n],
        &trajectory.controls,
        &end,
        &mu,
        &xi_last,
    )
    .unwrap_or(f64::INFINITY);
    Ok(Extremal {
        start: index,
        z,
        cost,
        residual,
        terminal_residual: terminal,
        single_shooting_residual: single,
        max_abs_alpha,
        admissible: max_abs_alpha < problem.alpha_max,
        kkt_residual,
        newton_iterations: iterations,
        trajectory,
    })
}

/// Replays each multiple-shooting segment from its node and joins them.
pub fn stitch(
    problem: &Problem,
    ms: &MultipleShooting,
    y: &DVector<f64>,
) -> Result<Trajectory, purcell_core::Error> {
    let kin = problem.kinematics::<f64>()?;
    let mu = Vector3::new(y[0], y[1], y[2]);
    let mut t = Trajectory::default();
    let segs = ms.nodes.len() - 1;
    let mut last = None;
    for s in 0..segs {
        let (start, xi) = if s == 0 {
            (State::at_origin(problem.alpha0), Vector2::new(y[3], y[4]))
        } else {
            let o = 5 + 7 * (s - 1);
            (
                State {
                    alpha: Vector2::new(y[o], y[o + 1]),
                    g: purcell_core::Se2::new(y[o + 2], y[o + 3], y[o + 4]),
                },
                Vector2::new(y[o + 5], y[o + 6]),
            )
        };
        let steps = ms.nodes[s + 1] - ms.nodes[s];
        let mut replay = Replay::new(kin, start, Costate { mu, xi }, steps, &[])?;
        t.xis.push(xi);
        for item in replay.by_ref() {
            let sample = item?;
            t.states.push(sample.state);
            t.controls.push(sample.u);
            t.xis.push(sample.xi);
        }
        t.xis.pop();
        last = Some((*replay.state(), *replay.xi()));
    }
    if let Some((state, xi)) = last {
        t.states.push(state);
        t.xis.push(xi);
    }
    Ok(t)
}

/// Solves from all starts in parallel; `progress` is called once per finished start.
pub fn solve(
    problem: &Problem,
    options: &SolveOptions,
    progress: &(dyn Fn() + Sync),
) -> Result<Solution, SolveError> {
    let basis = Basis::new(problem);
    let loops = start_loops(problem, options);
    let results: Vec<Result<Extremal, f64>> = loops
        .par_iter()
        .enumerate()
        .map(|(i, e)| {
            let r = run_start(problem, &basis, e, i, options);
            progress();
            r
        })
        .collect();
    let mut best_residual = f64::INFINITY;
    let mut extremals: Vec<Extremal> = Vec::new();
    for r in results {
        match r {
            Ok(x) => {
                let dup = extremals
                    .iter()
                    .any(|o| (o.z - x.z).amax() <= 1e-6 * (1.0 + x.z.amax()));
                if !dup {
                    extremals.push(x);
                }
            }
            Err(res) => best_residual = best_residual.min(res),
        }
    }
    if extremals.is_empty() {
        return Err(SolveError::Unreachable {
            best_residual,
            tolerance: options.tolerance,
        });
    }
    extremals.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    let Some(best) = extremals.iter().position(|x| x.admissible) else {
        return Err(SolveError::NoneAdmissible {
            found: extremals.len(),
            best_alpha: extremals
                .iter()
                .map(|x| x.max_abs_alpha)
                .fold(f64::INFINITY, f64::min),
        });
    };
    Ok(Solution {
        best,
        extremals,
        starts: loops.len(),
    })
}
