//! `field`: the curvature of the connection over the shape plane (MODEL.md §8), for a
//! swimmer or under a stored gait (a costate file or a binary gait file).

use super::args::{
    Failure, ModelArgs, OutDirArgs, costate_of_gait, fail, output_failure, read_costate,
};
use crate::{plots, replay};
use clap::{Args, ValueEnum};
use purcell_core::Arc;
use purcell_solver::problem::{Problem, Spec};
use serde_json::json;
use std::path::{Path, PathBuf};

/// A row of the curvature.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum FieldComponent {
    /// Forward motion (m/rad^2).
    X,
    /// Sideways motion (m/rad^2).
    Y,
    /// Turning (1/rad).
    Theta,
}

/// `field` flags.
#[derive(Debug, Args)]
pub struct FieldArgs {
    /// Swimmer parameters (not with --costate or --gait: a gait's file has its own).
    #[command(flatten)]
    pub model: ModelArgs,
    /// A costate file (DIR/costate.json) whose gait (replayed in f64) is drawn on top.
    #[arg(long, conflicts_with_all = ["links", "drag", "ratio", "gait"])]
    pub costate: Option<PathBuf>,
    /// A binary gait file (export's output), drawn the same way.
    #[arg(long, conflicts_with_all = ["links", "drag", "ratio"])]
    pub gait: Option<PathBuf>,
    /// Draw only this row (default: all three). field.csv always has all three.
    #[arg(long, value_enum)]
    pub component: Option<FieldComponent>,
    /// Shape axes of the figures in degrees (the curvature stays per rad^2, the CSV in
    /// radians; angle flags take degrees with their own deg suffix).
    #[arg(long)]
    pub degrees: bool,
    /// The output directory.
    #[command(flatten)]
    pub output: OutDirArgs,
}

/// `field`: the swimmer (and gait) of the flags, its figures written; the files as printed.
pub(super) fn run_field(a: FieldArgs, quiet: bool) -> Result<String, Failure> {
    let stored = match (&a.costate, &a.gait) {
        (Some(path), _) => Some((path, read_costate(path)?)),
        (None, Some(path)) => Some((path, costate_of_gait(path)?)),
        (None, None) => None,
    };
    let problem = match &stored {
        Some((path, file)) => {
            // Drawn from its whole replayed path.
            super::args::budget(path, file.steps, crate::budget::Work::Path, quiet)?;
            file.problem()
                .map_err(|e| fail(2, format!("{}: {e}", path.display())))?
        }
        None => {
            let spec = Spec {
                links: a.model.links,
                drag: a.model.drag,
                ratio: a.model.ratio,
                ..Spec::default()
            };
            Problem::new(&spec).map_err(|e| fail(2, e))?
        }
    };
    let components = match a.component {
        None => plots::field::Component::ALL.to_vec(),
        Some(FieldComponent::X) => vec![plots::field::Component::X],
        Some(FieldComponent::Y) => vec![plots::field::Component::Y],
        Some(FieldComponent::Theta) => vec![plots::field::Component::Theta],
    };
    let inputs: Vec<&Path> = stored.iter().map(|(p, _)| p.as_path()).collect();
    // The output checked before the gait is replayed.
    let out = a.output.prepare("field", &inputs)?;
    let (states, arcs) = match &stored {
        Some((path, file)) => {
            let (states, stride) = replay::gait_states(file, 10_000).map_err(|e| {
                fail(
                    2,
                    format!("{}: the gait does not replay: {e}", path.display()),
                )
            })?;
            // The arcs on the drawn states (every `stride`-th).
            let arcs = file
                .arcs
                .iter()
                .map(|a| Arc {
                    first: a.first / stride as u32,
                    last: a.last / stride as u32,
                    ..*a
                })
                .collect();
            (Some(states), arcs)
        }
        None => (None, Vec::new()),
    };
    let options = plots::Options { degrees: a.degrees };
    let gait = states.as_deref().map(|states| plots::FieldGait {
        problem: &problem,
        states,
        arcs: &arcs,
    });
    let files = plots::field_files(&problem.swimmer, gait, &components, &options)
        .map_err(|e| fail(1, format!("plotting: {e}")))?;
    out.commit(&files).map_err(output_failure(false))?;
    let names: Vec<&str> = files.iter().map(|f| f.0.as_str()).collect();
    Ok(serde_json::to_string_pretty(
        &json!({ "out": a.output.out.to_string_lossy(), "files": names }),
    )
    .map_err(|e| fail(1, e))?
        + "\n")
}
