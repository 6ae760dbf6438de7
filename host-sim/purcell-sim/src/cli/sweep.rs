//! `sweep`: a lattice of targets solved by continuation from neighbours, written as a table,
//! a summary and a map of the cost.

use super::args::{Failure, OutDirArgs, PrintArgs, ProblemArgs, Progress, fail, output_failure};
use super::summary;
use crate::report::SweepReport;
use crate::spec;
use crate::units::{self, Quantity::Angle, Quantity::Length};
use crate::{output, plots};
use clap::Args;
use purcell_solver::solver::Progress as _;
use purcell_solver::solver::continuation;
use std::time::Instant;

/// `sweep`'s search flags.
#[derive(Debug, Args)]
pub struct SearchArgs {
    /// Budget of start loops of each global search (see `solve --help`) [default: 1024, 160
    /// with --alpha-max].
    #[arg(long)]
    pub starts: Option<usize>,
}

/// `sweep` flags. The problem's flags are `solve`'s, with two shorter help texts.
#[derive(Debug, Args)]
#[command(
    mut_arg("horizon", |a| a.help("Horizon T in seconds; must be a whole number of steps")),
    mut_arg("alpha_max", |a| a.help(
        "Joint limit |alpha_i| <= alpha-max, below pi: radians, or degrees with deg (see `solve \
         --help`)"
    )),
)]
pub struct SweepArgs {
    /// Target x in metres: a value, or FROM:TO:COUNT for COUNT evenly spaced values (the
    /// decimals meant: -0.3:0.3:13 gives 0.05, not 0.050000000000000044).
    #[arg(long, default_value = "-0.3:0.3:13", allow_hyphen_values = true)]
    pub x: String,
    /// Target y in metres: a value or FROM:TO:COUNT.
    #[arg(long, default_value = "-0.3:0.3:13", allow_hyphen_values = true)]
    pub y: String,
    /// Target theta: a value or FROM:TO:COUNT, each end in radians or degrees with deg
    /// (-30deg:30deg:5; sweep.csv and report.json hold radians), each value taken modulo 2 pi
    /// into ]-pi, pi].
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

/// `sweep`: checks every input, prepares the output, solves every target, writes the files;
/// the summary (or with `--json` the report) as printed; no progress bar if `quiet`.
pub(super) fn run_sweep(a: SweepArgs, quiet: bool) -> Result<String, Failure> {
    let t0 = Instant::now();
    let axis = |name, text, q| spec::axis(name, text, q).map_err(|e| fail(2, e));
    let lattice = spec::lattice([
        axis("x", &a.x, Length)?,
        axis("y", &a.y, Length)?,
        axis("theta", &a.theta, Angle)?
            .into_iter()
            .map(units::wrap_angle)
            .collect(),
    ])
    .map_err(|e| fail(2, e))?;
    let spec = a.problem.spec([0.0; 3]);
    let options = spec::sweep_options(&spec, a.problem.search.starts).map_err(|e| fail(2, e))?;
    let out = a.output.prepare("sweep", &[])?;
    let progress = Progress::new(t0, quiet);
    let t1 = Instant::now();
    let points =
        continuation::sweep(&spec, &lattice, &options, &progress).map_err(|e| fail(2, e))?;
    let seconds = t1.elapsed().as_secs_f64();
    progress.phase("output", 1, "directory");
    let csv = output::sweep_csv(&points);
    let summary = SweepReport::new(&spec, &lattice, &points, seconds);
    let summary_text = serde_json::to_string_pretty(&summary).map_err(|e| fail(1, e))? + "\n";
    let mut files = vec![
        ("sweep.csv".to_string(), csv.into_bytes()),
        ("report.json".to_string(), summary_text.clone().into_bytes()),
    ];
    if !a.no_plots {
        files.extend(
            plots::sweep_files(&lattice, &points, a.problem.horizon)
                .map_err(|e| fail(1, format!("plotting: {e}")))?,
        );
    }
    out.commit(&files).map_err(output_failure(false))?;
    progress.finish();
    Ok(if a.print.json {
        summary_text
    } else {
        summary::sweep(&summary, &a.output.out, &files, t0.elapsed().as_secs_f64())
    })
}
