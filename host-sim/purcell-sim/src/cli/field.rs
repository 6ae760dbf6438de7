//! `field`: the curvature of the connection over the shape plane (MODEL.md §8), for a
//! swimmer or under a stored gait (a costate file or a binary gait file).

use super::args::{
    Failure, ModelArgs, OutDirArgs, costate_of_gait, fail, output_failure, read_costate,
};
use crate::costate_file::CostateFile;
use crate::{plots, replay};
use clap::{Args, ValueEnum};
use purcell_core::{Arc, State};
use purcell_solver::problem::{Problem, Spec};
use purcell_solver::solver::cost::Power;
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
    /// A second gait (a costate file or a binary gait file, the same swimmer) drawn with the
    /// first, e.g. the power-optimal against the effort-optimal one: the legend gives each
    /// one's effort and power (from its replay's controls), the title the second's saving.
    #[arg(long, value_name = "FILE")]
    pub against: Option<PathBuf>,
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

/// `field`: the swimmer (and gait, and the gait against it) of the flags, its figures
/// written; the files as printed.
pub(super) fn run_field(a: FieldArgs, quiet: bool) -> Result<String, Failure> {
    let stored = match (&a.costate, &a.gait) {
        (Some(path), _) => Some((path, read_costate(path)?)),
        (None, Some(path)) => Some((path, costate_of_gait(path)?)),
        (None, None) => None,
    };
    let against = match (&a.against, &stored) {
        (None, _) => None,
        (Some(_), None) => return Err(fail(2, "--against needs --costate or --gait")),
        (Some(path), Some(_)) => Some((path, read_stored(path)?)),
    };
    let problem = match &stored {
        Some((path, file)) => problem_of(path, file, quiet)?,
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
    let second = match &against {
        Some((path, file)) => Some(problem_of(path, file, quiet)?),
        None => None,
    };
    if second.is_some_and(|s| s.swimmer != problem.swimmer) {
        return Err(fail(
            2,
            "--against: a gait of another swimmer (links, drag, ratio)",
        ));
    }
    let components = match a.component {
        None => plots::field::Component::ALL.to_vec(),
        Some(FieldComponent::X) => vec![plots::field::Component::X],
        Some(FieldComponent::Y) => vec![plots::field::Component::Y],
        Some(FieldComponent::Theta) => vec![plots::field::Component::Theta],
    };
    let inputs: Vec<&Path> = stored
        .iter()
        .chain(&against)
        .map(|(p, _)| p.as_path())
        .collect();
    // The output checked before the gaits are replayed.
    let out = a.output.prepare("field", &inputs)?;
    let drawn_first = stored.as_ref().map(|(p, f)| drawn(p, f)).transpose()?;
    let drawn_against = against.as_ref().map(|(p, f)| drawn(p, f)).transpose()?;
    let options = plots::Options { degrees: a.degrees };
    let first = drawn_first.as_ref().map(|d| field_gait(&problem, d));
    let files = match (first, &stored, &against, &second, &drawn_against) {
        (Some(first), Some((_, file)), Some((path, other)), Some(second), Some(d)) => {
            let [label, label_against, note] =
                comparison(file, other).map_err(|e| fail(2, format!("{}: {e}", path.display())))?;
            plots::comparison_files(
                &problem.swimmer,
                [first, field_gait(second, d)],
                [label, label_against],
                &note,
                &components,
                &options,
            )
        }
        _ => plots::field_files(&problem.swimmer, first, &components, &options),
    }
    .map_err(|e| fail(1, format!("plotting: {e}")))?;
    out.commit(&files).map_err(output_failure(false))?;
    let names: Vec<&str> = files.iter().map(|f| f.0.as_str()).collect();
    Ok(serde_json::to_string_pretty(
        &json!({ "out": a.output.out.to_string_lossy(), "files": names }),
    )
    .map_err(|e| fail(1, e))?
        + "\n")
}

/// A costate file, or a binary gait file read as one (by its magic), exit 2 if neither.
fn read_stored(path: &Path) -> Result<CostateFile, Failure> {
    let head = std::fs::File::open(path).and_then(|mut f| {
        let mut head = [0u8; 8];
        std::io::Read::read(&mut f, &mut head).map(|_| head)
    });
    match head {
        Ok(head) if head == purcell_core::gait::MAGIC => costate_of_gait(path),
        _ => read_costate(path),
    }
}

/// The problem of the stored gait `file` (read from `path`), its whole path within the
/// budget of a drawing.
fn problem_of(path: &Path, file: &CostateFile, quiet: bool) -> Result<Problem, Failure> {
    super::args::budget(path, file.steps, crate::budget::Work::Path, quiet)?;
    file.problem()
        .map_err(|e| fail(2, format!("{}: {e}", path.display())))
}

/// The states of `file`'s `f64` replay to draw (about 10 000) and its arcs on them.
fn drawn(path: &Path, file: &CostateFile) -> Result<(Vec<State<f64>>, Vec<Arc>), Failure> {
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
    Ok((states, arcs))
}

/// A gait of `problem` drawn with its `states` and `arcs`.
fn field_gait<'a>(
    problem: &'a Problem,
    (states, arcs): &'a (Vec<State<f64>>, Vec<Arc>),
) -> plots::FieldGait<'a> {
    plots::FieldGait {
        problem,
        states,
        arcs,
    }
}

/// The legend labels of `first` and `second` (each its cost's optimum, its effort and power)
/// and the title's note: the second's saving in each cost.
fn comparison(
    first: &CostateFile,
    second: &CostateFile,
) -> Result<[String; 3], purcell_core::Error> {
    let ([e1, p1], [e2, p2]) = (costs(first)?, costs(second)?);
    let label = |f: &CostateFile, e: f64, p: f64| {
        format!("{}-optimal: effort {e:.5}, power {p:.5}", f.cost.name())
    };
    let change = |a: f64, b: f64| {
        let pct = 100.0 * (b - a) / a;
        format!("{}{:.1} %", if pct < 0.0 { "−" } else { "+" }, pct.abs())
    };
    Ok([
        label(first, e1, p1),
        label(second, e2, p2),
        format!(
            "{}-optimal against {}-optimal: power {}, effort {}",
            second.cost.name(),
            first.cost.name(),
            change(p1, p2),
            change(e1, e2)
        ),
    ])
}

/// The effort `Σ h/2·|u_k|²` and the power `Σ h/2·u_kᵀG(α_k)u_k` (MODEL.md §11) of the
/// controls of `file`'s `f64` replay, along its shapes.
fn costs(file: &CostateFile) -> Result<[f64; 2], purcell_core::Error> {
    let t = replay::trajectory(file)?;
    let swimmer = file
        .problem()
        .map_err(|_| purcell_core::Error::InvalidParameters)?
        .swimmer;
    let metric = Power::new(&swimmer);
    let h = file.h;
    let (mut effort, mut power) = (0.0, 0.0);
    for (s, u) in t.states.iter().zip(&t.controls) {
        effort += 0.5 * h * u.norm_squared();
        power += 0.5 * h * (u.transpose() * metric.metric_at(&s.alpha) * u)[0];
    }
    Ok([effort, power])
}
