//! Results: `trajectory.csv` ([`path`]), the costate file, `sweep.csv`, a gait as C source
//! ([`c_array`]), and ([`destination`]) where every output goes: never over anything the tool did
//! not write, checked before the work, atomically.

use purcell_solver::problem::Problem;
use purcell_solver::solver::Extremal;
use std::fmt::Write as _;

pub mod c_array;
pub mod destination;
pub mod path;
pub use destination::{
    Claim, MANIFEST, OutputDir, OutputError, OutputFile, remove_staging_on_interrupt,
};

/// `trajectory.csv` of the extremal `x` of `problem`: its path, rows `k = 0..=N`, columns
/// [`path::HEADER`] (see [`path`]).
pub fn trajectory_csv(problem: &Problem, x: &Extremal) -> String {
    let t = &x.trajectory;
    let mut csv = path::PathCsv::new(problem.h, problem.steps, x.arcs.iter().copied());
    for (k, st) in t.states.iter().enumerate() {
        let g = st.g.to_xytheta();
        let xi = t.xis.get(k).copied().unwrap_or_default();
        csv.push(&path::Row {
            alpha: [st.alpha.x, st.alpha.y],
            u: t.controls.get(k).map(|u| [u.x, u.y]),
            g: [g.x, g.y, g.z],
            xi: [xi.x, xi.y],
        });
    }
    csv.finish()
}

/// The costate file for an extremal, with checkpoints every `every` steps and at each
/// joint-limit arc's last state (MODEL.md §9; `every = 0`: at the arcs' exits only).
///
/// The checkpoints are `(α_k, g_k, ξ̃^{k−1})` of the converged trajectory itself (states of the
/// direct method, costates from its multipliers with state `k`'s jump on the limit), not of a
/// free replay of `(μ, ξ^{−1})`, which drifts from it on unstable problems: a replay restarts on
/// the extremal at each one.
pub fn costate_file(
    problem: &Problem,
    x: &Extremal,
    every: u32,
) -> crate::costate_file::CostateFile {
    use crate::costate_file::*;
    let t = &x.trajectory;
    let periodic = (every > 0)
        .then(|| (every..problem.steps).step_by(every as usize))
        .into_iter()
        .flatten();
    let mut steps: Vec<u32> = periodic.chain(x.arcs.iter().map(|a| a.last)).collect();
    steps.sort_unstable();
    steps.dedup();
    let checkpoints = steps
        .into_iter()
        .filter_map(|k| {
            let (s, xi) = (t.states.get(k as usize)?, t.xis.get(k as usize)?);
            Some(CheckpointRecord {
                k,
                alpha: [s.alpha.x, s.alpha.y],
                g: [s.g.x(), s.g.y(), s.g.cos(), s.g.sin()],
                xi: [xi.x, xi.y],
            })
        })
        .collect();
    CostateFile::new(
        GaitParams {
            model: Model {
                links: problem.swimmer.lengths(),
                drag: problem.swimmer.drag(),
                ratio: problem.swimmer.ratio(),
            },
            h: problem.h,
            steps: problem.steps,
            alpha0: [problem.alpha0.x, problem.alpha0.y],
            target: [problem.target.x, problem.target.y, problem.target.z],
            mu: [x.mu.x, x.mu.y, x.mu.z],
            xi0: [x.xi0.x, x.xi0.y],
            checkpoint_every: every,
            alpha_max: problem.alpha_max,
            alpha_end: problem.stored_end(),
            cost: problem.cost,
        },
        x.arcs.clone(),
        checkpoints,
    )
}

/// `sweep.csv`'s columns, units in their names: the target `x_m`, `y_m`, `theta_rad`, each
/// printed as the decimal typed where it is one ([`crate::spec::axis`]); `J`
/// (rad²/s); the terminal defect (largest component, m or rad); the largest `|α_i|` (rad);
/// admissible and strict local minimum (`true`/`false`); the KKT residual (rad/s); `status`.
pub const SWEEP_HEADER: &str = "x_m,y_m,theta_rad,cost_rad2_per_s,residual,max_abs_alpha_rad,\
                                admissible,local_min,kkt_residual_rad_per_s,status";

/// `sweep.csv` ([`SWEEP_HEADER`]), one row per target. `status` is `ok` where the
/// extremal's certificates vouch for it ([`Extremal::uncertified`]), else the first that
/// does not (`not admissible`, `not a strict local minimum`, `terminal residual above 1e-10`,
/// `KKT residual above 1e-8`, `law residual above 1e-9`); for a target without an extremal
/// the numbers are empty and `status` is why, quoted (the solver's
/// [`SolveError`](purcell_solver::solver::SolveError): `no start reached the target: …`,
/// `N extremal(s) of the coarse search, none carried to the problem's grid: …`, `N
/// extremal(s) found, none admissible: …`).
///
/// [`Extremal::uncertified`]: purcell_solver::solver::Extremal::uncertified
pub fn sweep_csv(points: &[purcell_solver::solver::continuation::SweepPoint]) -> String {
    let mut s = format!("{SWEEP_HEADER}\n");
    for p in points {
        let t = p.target;
        let _ = match &p.result {
            Ok(x) => writeln!(
                s,
                "{},{},{},{},{:e},{},{},{},{},{}",
                t.x,
                t.y,
                t.z,
                x.cost,
                x.residual,
                x.max_abs_alpha,
                x.admissible,
                x.local_min,
                x.kkt_residual.map_or(String::new(), |k| format!("{k:e}")),
                x.uncertified().unwrap_or("ok")
            ),
            Err(e) => writeln!(s, "{},{},{},,,,,,,\"{e}\"", t.x, t.y, t.z),
        };
    }
    s
}
