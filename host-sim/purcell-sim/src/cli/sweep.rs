//! `sweep`: a lattice of targets solved by continuation from neighbours, written as a table,
//! a summary and a map of the cost.

use super::args::{
    Failure, OutDirArgs, PrintArgs, ProblemArgs, Progress, fail, output_failure, search_limits,
};
use super::summary;
use crate::{output, plots};
use clap::Args;
use purcell_solver::problem::Problem;
use purcell_solver::solver::SolveOptions;
use purcell_solver::solver::continuation::{self, Lattice};
use serde_json::json;
use std::time::Instant;

/// Largest number of targets a sweep accepts.
pub const MAX_SWEEP_TARGETS: usize = 10_000;

/// `sweep`'s search flags.
#[derive(Debug, Args)]
pub struct SearchArgs {
    /// Budget of start loops of each global search (see `solve --help`).
    #[arg(long, default_value_t = SolveOptions::default().starts)]
    pub starts: usize,
}

/// `sweep` flags. The problem's flags are `solve`'s, with two shorter help texts.
#[derive(Debug, Args)]
#[command(
    mut_arg("horizon", |a| a.help("Horizon T in seconds; must be a whole number of steps")),
    mut_arg("alpha_max", |a| a.help(
        "Joint limit |alpha_i| <= alpha-max, radians, below pi (see `solve --help`)"
    )),
)]
pub struct SweepArgs {
    /// Target x in metres: a value, or FROM:TO:COUNT for COUNT evenly spaced values.
    #[arg(long, default_value = "-0.3:0.3:13", allow_hyphen_values = true)]
    pub x: String,
    /// Target y in metres: a value or FROM:TO:COUNT.
    #[arg(long, default_value = "-0.3:0.3:13", allow_hyphen_values = true)]
    pub y: String,
    /// Target theta in radians: a value or FROM:TO:COUNT.
    #[arg(long, default_value = "0", allow_hyphen_values = true)]
    pub theta: String,
    /// The problem and the searches.
    #[command(flatten)]
    pub problem: ProblemArgs<SearchArgs>,
    /// Skip the figure.
    #[arg(long)]
    pub no_plots: bool,
    /// The output directory.
    #[command(flatten)]
    pub output: OutDirArgs,
    /// What to print.
    #[command(flatten)]
    pub print: PrintArgs,
}

/// `FROM:TO:COUNT` or a single value.
pub fn axis(name: &str, text: &str) -> Result<Vec<f64>, Failure> {
    let bad = || {
        fail(
            2,
            format!("--{name} takes a number or FROM:TO:COUNT (got {text:?})"),
        )
    };
    let parts: Vec<&str> = text.split(':').collect();
    let num = |s: &str| s.trim().parse::<f64>().ok().filter(|v| v.is_finite());
    match parts.as_slice() {
        [v] => Ok(vec![num(v).ok_or_else(bad)?]),
        [a, b, n] => {
            let (a, b) = (num(a).ok_or_else(bad)?, num(b).ok_or_else(bad)?);
            let n: usize = n.trim().parse().map_err(|_| bad())?;
            if n == 0 || n > MAX_SWEEP_TARGETS {
                return Err(bad());
            }
            Ok(Lattice::spaced(a, b, n))
        }
        _ => Err(bad()),
    }
}

/// `sweep`: checks every input, prepares the output, solves every target, writes the files;
/// the summary (or with `--json` the report) as printed; no progress bar if `quiet`.
pub(super) fn run_sweep(a: SweepArgs, quiet: bool) -> Result<String, Failure> {
    let lattice = Lattice {
        axes: [axis("x", &a.x)?, axis("y", &a.y)?, axis("theta", &a.theta)?],
    };
    if lattice.len() > MAX_SWEEP_TARGETS {
        return Err(fail(
            2,
            format!(
                "{} targets: more than the limit {MAX_SWEEP_TARGETS}",
                lattice.len()
            ),
        ));
    }
    let spec = a.problem.spec([0.0; 3])?;
    let problem = Problem::new(&spec).map_err(|e| fail(2, e))?;
    search_limits(&problem, a.problem.search.starts)?;
    let out = a.output.prepare("sweep", &[])?;
    let options = SolveOptions {
        starts: a.problem.search.starts,
        ..SolveOptions::default()
    };
    // Each target ticks once when searched and once when refined.
    let progress = Progress::new(
        2 * lattice.len() as u64,
        "sweeping {bar:30} {pos}/{len} searches and refinements ({elapsed})",
        quiet,
    );
    let t0 = Instant::now();
    let points = continuation::sweep(&spec, &lattice, &options, &|| progress.tick())
        .map_err(|e| fail(2, e))?;
    progress.finish();
    let seconds = t0.elapsed().as_secs_f64();
    let csv = output::sweep_csv(&points);
    let solved = points
        .iter()
        .filter(|p| p.result.as_ref().is_ok_and(|x| x.admissible))
        .count();
    let summary = json!({
        "targets": points.len(), "solved": solved, "sweep_seconds": seconds,
        "axes": {"x": lattice.axes[0], "y": lattice.axes[1], "theta": lattice.axes[2]},
        "problem": {"horizon": a.problem.horizon, "step": a.problem.step, "alpha0": spec.alpha0,
                    "links": spec.links, "drag": spec.drag, "ratio": spec.ratio,
                    "alpha_max": spec.alpha_max},
    });
    let summary_text = serde_json::to_string_pretty(&summary).map_err(|e| fail(1, e))? + "\n";
    let mut files = vec![
        ("sweep.csv".to_string(), csv.into_bytes()),
        ("report.json".to_string(), summary_text.clone().into_bytes()),
    ];
    if !a.no_plots {
        files.extend(
            plots::sweep_files(&lattice, &points).map_err(|e| fail(1, format!("plotting: {e}")))?,
        );
    }
    out.commit(&files).map_err(output_failure(false))?;
    Ok(if a.print.json {
        summary_text
    } else {
        summary::sweep(&summary, &a.output.out, &files)
    })
}
