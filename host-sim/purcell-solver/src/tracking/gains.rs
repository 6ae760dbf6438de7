//! The tracking table of a gait ([`purcell_core::tracking`], MODEL.md §10): a time-varying LQR
//! on the exact linearisation of the discrete dynamics along the extremal, with the drag
//! ratio's relative error `ε` as a sixth, constant state, and the closed loop's error per unit
//! `ε` for the running estimate of `ε`.
//!
//! With the solver's stage Jacobians `A_k = ∂f/∂s`, `B_k = ∂f/∂u` at `(s_k, u_k)`
//! ([`StageModel::linearise`], `s = (α, x, y, θ)`), `G_k = r·∂f/∂r` (dual numbers through
//! [`stage::step`]) and `T_k = diag(I₂, R(θ_k)ᵀ, 1)` (orthogonal; `e_k = T_k δs_k` to first
//! order), the error obeys `e_{k+1} = Â_k e_k + B̂_k δu_k + Ĝ_k ε` with `Â_k = T_{k+1}A_kT_kᵀ`,
//! `B̂_k = T_{k+1}B_k`, `Ĝ_k = T_{k+1}G_k`. On `z = (e, ε)`, `z_{k+1} = 𝒜_k z_k + ℬ_k δu_k` with
//! `𝒜 = [[Â, Ĝ], [0, 1]]`, `ℬ = [B̂; 0]`, the recursion minimises
//! `½e_NᵀQ_N e_N + Σ_k ½(e_kᵀQ e_k + h|δu_k|²)` (the effort weighted as the gait's own cost):
//!
//! ```text
//! P_N = diag(Q_N, 0),   S = hI + ℬᵀPℬ,   [K_k κ_k] = −S⁻¹ℬᵀP𝒜,   P ← diag(Q, 0) + 𝒜ᵀP(𝒜 + ℬ[K_k κ_k])
//! ```
//!
//! (symmetrised). Then a forward pass of the linearised closed loop at `ε = 1` under the gains
//! held over each record's `D` steps gives `ψ_j = e_{jD}` and `β_j = 1/Σ_{i≤j}|ψ_i|²` (0 before
//! the estimate is used): with `ε̂ = β_j Σ_{i≤j} ψ_iᵀe_{iD}` the estimate is exact in that model,
//! so the forward pass runs with `ε̂ = ε` wherever `β_j > 0`.
//!
//! This is not [`crate::solver::riccati`]: that one solves the Newton step of the problem with
//! its terminal state fixed (a multiplier, no terminal weight); tracking needs the feedback
//! of a terminal penalty, the textbook recursion above.

use super::plan::PlanStep;
use crate::dual::Dual;
use crate::solver::stage::{self, Rule, StageModel, StageState};
use nalgebra::{Matrix2, Matrix5, Matrix5x2, Matrix6, Matrix6x2, Vector2, Vector5, Vector6};
use purcell_core::tracking::{RECORD_VALUES, Record};
use purcell_core::{Error, Kinematics, State, Swimmer};

/// The design of the tracking table: weights (each a diagonal, per unit of `e`), the record
/// spacing and where the estimate starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Design {
    /// Terminal weight on each `α` error (per rad²).
    pub terminal_alpha: f64,
    /// Terminal weight on each pose error `(x, y, θ)` (per m², rad²).
    pub terminal_pose: f64,
    /// Running weight on each `α` error, per second.
    pub running_alpha: f64,
    /// Running weight on each pose error, per second.
    pub running_pose: f64,
    /// Steps per record `D` (at least 1) before the tail.
    pub every: u32,
    /// Steps at the end with a record each (the gains change fast there: the terminal weight).
    pub tail: u32,
    /// The first step whose record uses the estimate `ε̂` (before it, `ε̂ = 0`).
    pub estimate_from: u32,
    /// The bound the joints are held within ([`purcell_core::tracking::joint_bound`]).
    pub bound: f64,
    /// Where the nominal joint is within `band` of `bound`, its running weight is
    /// `bound_weight` more (per rad², per second): corrections stay away from the bound.
    pub band: f64,
    /// See `band`.
    pub bound_weight: f64,
    /// Whether the gain on `ε` comes from the plant's neighbouring extremal where the gait has
    /// one ([`super::plan`], [`super::table_of`]) instead of the LQR's own.
    pub plan: bool,
}

impl Default for Design {
    /// The design measured in docs/ROBUSTNESS.md.
    fn default() -> Self {
        Design {
            terminal_alpha: 1e4,
            terminal_pose: 1e4,
            running_alpha: 0.0,
            running_pose: 1.0,
            every: 20,
            tail: 100,
            estimate_from: 500,
            bound: core::f64::consts::PI,
            band: 1.0,
            bound_weight: 1e4,
            plan: false,
        }
    }
}

/// The tracking table: record `j` holds from step `starts[j]` to the next record's start
/// (the last one to the end); [`table`] puts one every `D` steps up to the tail, then one per
/// step ([`Table::index`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// The first step of each record: `0`, then increasing.
    pub starts: Vec<u32>,
    /// The records.
    pub records: Vec<Record<f64>>,
}

impl Table {
    /// The index of the record of step `k` in a table with a record every `every` steps up
    /// to step `tail_from` (a multiple of it) and one per step from there, and whether `k` is
    /// its first step.
    pub fn index(every: u32, tail_from: u32, k: usize) -> (usize, bool) {
        let (d, t) = (every.max(1) as usize, tail_from as usize);
        if k < t {
            (k / d, k.is_multiple_of(d))
        } else {
            (t / d + (k - t), true)
        }
    }

    /// The record of step `k`, and whether `k` is its first step.
    pub fn at(&self, k: usize) -> Option<(&Record<f64>, bool)> {
        let j = self
            .starts
            .partition_point(|&s| s as usize <= k)
            .checked_sub(1)?;
        let first = self.starts.get(j).is_some_and(|&s| s as usize == k);
        self.records.get(j).map(|r| (r, first))
    }

    /// The table a gait file stores ([`purcell_core::gait::TrackingTable`]), in `f64`.
    pub fn stored(table: &purcell_core::gait::TrackingTable<'_>) -> Self {
        let (starts, records) = table.iter().map(|(k, r)| (k, r.map(f64::from))).unzip();
        Table { starts, records }
    }

    /// The records rounded to `f32` with their first steps, as a gait file stores them
    /// ([`purcell_core::gait::encode_with_tracking`]).
    pub fn to_f32(&self) -> Vec<(u32, Record<f32>)> {
        self.starts
            .iter()
            .zip(&self.records)
            .map(|(&k, r)| (k, r.map(|v| v as f32)))
            .collect()
    }
}

/// `diag(I₂, R(θ)ᵀ, 1)` of a pose.
fn frame(g: &purcell_core::Se2<f64>) -> Matrix5<f64> {
    let (c, s) = (g.cos(), g.sin());
    let mut t = Matrix5::identity();
    t[(2, 2)] = c;
    t[(2, 3)] = s;
    t[(3, 2)] = -s;
    t[(3, 3)] = c;
    t
}

/// One stage in error coordinates: `Â`, `B̂`, `Ĝ`.
struct ErrorStage {
    a: Matrix5<f64>,
    b: Matrix5x2<f64>,
    g: Vector5<f64>,
}

/// The stages along `states` under `controls`.
fn error_stages(
    kin: &Kinematics<f64>,
    states: &[State<f64>],
    controls: &[Vector2<f64>],
) -> Result<Vec<ErrorStage>, Error> {
    let model = StageModel::new(*kin, Rule::LEFT_POINT)?;
    let sw = kin.swimmer();
    let c = Dual::<1>::constant;
    let ratio = sw.ratio();
    let kin1 = Kinematics::new(
        Swimmer::new(sw.lengths().map(c), c(sw.drag()), Dual::variable(ratio, 0))?,
        c(kin.h()),
    )?;
    states
        .windows(2)
        .zip(controls)
        .map(|(pair, u)| {
            let s = stage::coordinates(&pair[0]);
            let lin = model.linearise(&StageState::from(s), u, &StageState::zeros())?;
            let d = stage::step(&kin1, Rule::LEFT_POINT, &s.map(c), &u.map(c))?;
            let (t, t_next) = (frame(&pair[0].g), frame(&pair[1].g));
            Ok(ErrorStage {
                a: t_next * lin.a * t.transpose(),
                b: t_next * lin.b,
                g: t_next * Vector5::from(d.map(|v| v.d[0] * ratio)),
            })
        })
        .collect()
}

/// The gains `[K_k κ_k]` (2×6) of every step (module docs).
fn riccati(
    stages: &[ErrorStage],
    states: &[State<f64>],
    h: f64,
    w: &Design,
) -> Result<Vec<nalgebra::Matrix2x6<f64>>, Error> {
    let diag =
        |a1: f64, a2: f64, p: f64| Matrix6::from_diagonal(&Vector6::new(a1, a2, p, p, p, 0.0));
    let near = |a: f64| {
        w.running_alpha
            + if a.abs() > w.bound - w.band {
                w.bound_weight
            } else {
                0.0
            }
    };
    let mut p = diag(w.terminal_alpha, w.terminal_alpha, w.terminal_pose);
    let mut out = vec![nalgebra::Matrix2x6::zeros(); stages.len()];
    for (k, st) in stages.iter().enumerate().rev() {
        let alpha = states[k].alpha;
        let q = diag(near(alpha.x), near(alpha.y), w.running_pose) * h;
        let mut a = Matrix6::identity();
        a.fixed_view_mut::<5, 5>(0, 0).copy_from(&st.a);
        a.fixed_view_mut::<5, 1>(0, 5).copy_from(&st.g);
        let mut b = Matrix6x2::zeros();
        b.fixed_view_mut::<5, 2>(0, 0).copy_from(&st.b);
        let bp = b.transpose() * p;
        let pivot = Matrix2::identity() * h + bp * b;
        let gain = -pivot.try_inverse().ok_or(Error::Singular)? * bp * a;
        if !gain.iter().all(|v| v.is_finite()) {
            return Err(Error::NonFinite);
        }
        p = q + a.transpose() * p * (a + b * gain);
        p = (p + p.transpose()) * 0.5;
        out[k] = gain;
    }
    Ok(out)
}

/// The tracking table along the trajectory `states` (`N + 1`) under `controls` (`N`) of the
/// swimmer `kin` (module docs), its gain on `ε` from `plan` if given (one step each,
/// [`super::plan`]): `κ_k = φ_k − K_kψ_k` at each record's first step, so that the law flies
/// the plant's neighbouring extremal `u_k + φ_kε̂` where it tracks its error `ψ_kε̂`; without
/// one, the LQR's own `κ_k`.
///
/// Errors: those of the linearisation ([`StageModel::linearise`]), [`Error::Singular`] if a
/// pivot `S` is singular, [`Error::NonFinite`] for a non-finite gain,
/// [`Error::InvalidStep`] for trajectories whose lengths do not match or `D = 0`.
pub fn table(
    kin: &Kinematics<f64>,
    states: &[State<f64>],
    controls: &[Vector2<f64>],
    design: &Design,
    plan: Option<&[PlanStep]>,
) -> Result<Table, Error> {
    if states.len() != controls.len() + 1
        || design.every == 0
        || plan.is_some_and(|p| p.len() != controls.len())
    {
        return Err(Error::InvalidStep);
    }
    let stages = error_stages(kin, states, controls)?;
    let gains = riccati(&stages, states, kin.h(), design)?;
    let d = design.every as usize;
    let n = stages.len();
    let tail_from = (n.saturating_sub(design.tail as usize) / d * d) as u32;
    let (mut psi, mut sum, mut estimate) = (Vector5::zeros(), 0.0, 0.0);
    let (mut starts, mut records) = (Vec::new(), Vec::new());
    let mut held = nalgebra::Matrix2x6::zeros();
    for (k, (st, gain)) in stages.iter().zip(&gains).enumerate() {
        if Table::index(design.every, tail_from, k).1 {
            held = *gain;
            if let Some(step) = plan.map(|p| p[k]) {
                let feedback = gain.fixed_view::<2, 5>(0, 0);
                held.set_column(5, &(step.control - feedback * step.error));
            }
            sum += psi.norm_squared();
            let beta = if k >= design.estimate_from as usize && sum > 0.0 {
                1.0 / sum
            } else {
                0.0
            };
            estimate = if beta > 0.0 { 1.0 } else { estimate };
            let mut r = [0.0; RECORD_VALUES];
            for i in 0..2 {
                for j in 0..5 {
                    r[5 * i + j] = held[(i, j)];
                }
                r[10 + i] = held[(i, 5)];
            }
            r[12..17].copy_from_slice(psi.as_slice());
            r[17] = beta;
            starts.push(k as u32);
            records.push(r);
        }
        let du = held.fixed_view::<2, 5>(0, 0) * psi + held.column(5) * estimate;
        psi = st.a * psi + st.b * du + st.g;
    }
    Ok(Table { starts, records })
}
