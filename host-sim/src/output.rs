//! Results: `trajectory.csv`, the costate file, and ([`target`]) where every output goes:
//! never over anything the tool did not write, checked before the work, atomically.

use crate::problem::Problem;
use crate::solve::{Extremal, Trajectory};
use std::fmt::Write as _;

pub mod target;
pub use target::{MANIFEST, OutputDir, OutputError, OutputFile};

/// `trajectory.csv`: `t,alpha1,alpha2,u1,u2,x,y,theta`, rows `k = 0..=N` (last `u` is 0).
pub fn trajectory_csv(problem: &Problem, t: &Trajectory) -> String {
    let mut s = String::from("t,alpha1,alpha2,u1,u2,x,y,theta\n");
    for (k, st) in t.states.iter().enumerate() {
        let u = t.controls.get(k).copied().unwrap_or_default();
        let g = st.g.to_xytheta();
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{}",
            problem.h * k as f64,
            st.alpha.x,
            st.alpha.y,
            u.x,
            u.y,
            g.x,
            g.y,
            g.z
        );
    }
    s
}

/// The costate file for an extremal, with checkpoints every `every` steps.
///
/// The checkpoints are `(α_k, g_k, ξ^{k−1})` of a plain `f64` replay from `(μ, ξ^{−1})`: an
/// `f64` replay with them is bit-identical to one without, and an `f32` replay restarts from
/// that `f64` run at each one. (Taking them from the stitched multiple-shooting trajectory
/// instead would jump by its node defects.) If that replay fails before the end, the file
/// has none (`checkpoint_every = 0`): a partial table would not be a valid file.
pub fn costate_file(
    problem: &Problem,
    x: &Extremal,
    every: u32,
) -> crate::costate_file::CostateFile {
    use crate::costate_file::*;
    let mut checkpoints = Vec::new();
    if every > 0
        && let Ok(kin) = problem.kinematics::<f64>()
        && let Ok(mut replay) = purcell_core::Replay::new(
            kin,
            purcell_core::State::at_origin(problem.alpha0),
            crate::shooting::costate(&x.z),
            problem.steps,
            &[],
        )
    {
        while let Ok(Some(sample)) = replay.step() {
            let k = sample.k + 1;
            if k % every == 0 && k < problem.steps {
                let (s, xi) = (replay.state(), replay.xi());
                checkpoints.push(CheckpointEntry {
                    k,
                    alpha: [s.alpha.x, s.alpha.y],
                    g: [s.g.x(), s.g.y(), s.g.cos(), s.g.sin()],
                    xi: [xi.x, xi.y],
                });
            }
        }
        if replay.steps_done() < problem.steps {
            checkpoints.clear();
        }
    }
    let every = if checkpoints.is_empty() { 0 } else { every };
    CostateFile {
        format: FORMAT.into(),
        version: VERSION,
        model: Model {
            links: problem.swimmer.lengths(),
            drag: problem.swimmer.drag(),
            ratio: problem.swimmer.ratio(),
        },
        h: problem.h,
        steps: problem.steps,
        alpha0: [problem.alpha0.x, problem.alpha0.y],
        target: [problem.target.x, problem.target.y, problem.target.z],
        mu: [x.z[0], x.z[1], x.z[2]],
        xi0: [x.z[3], x.z[4]],
        checkpoint_every: every,
        checkpoints,
    }
}
