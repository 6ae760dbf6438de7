//! `solve`: the optimal gait of one target, from the global search or a stored extremal
//! (`--from`), written with its costate file, report and figures.

use super::args::{
    Failure, OutDirArgs, PrintArgs, ProblemArgs, Progress, fail, output_failure, warn,
};
use super::summary;
use super::units::{
    self,
    Quantity::{Angle, Length},
};
use crate::find::{Found, find};
use crate::plots;
use crate::report::{Solved, search_warnings};
use crate::spec::{self, Prepared, SolveSpec};
use crate::words::{Front, Worded};
use clap::Args;
use purcell_solver::solver::{Progress as _, Solution};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// `solve`'s search flags.
#[derive(Debug, Args)]
pub struct SearchArgs {
    /// Budget of start loops of the global search (run in batches of 32, in parallel; 1 to
    /// 4096; the family has 1 128 loops, 936 with --alpha-max and 96 rim loops riding the
    /// limit first, a larger budget runs them all; with --alpha-max each loop runs along two
    /// barrier paths, in one order for every seed). The search stops earlier once its
    /// stopping rule is met: at least 128 starts run (64 with --alpha-max), an estimated
    /// chance below 0.5 % that another start reaches a minimum not seen yet
    /// that is no dearer than the cheapest admissible one (Good-Turing: the share of starts
    /// that alone reached such a minimum), and that extremal reached from 3 starts. A search that spends its budget first says so
    /// on stderr and returns the cheapest gait it found [default: 1024, 160 with
    /// --alpha-max].
    #[arg(long)]
    pub starts: Option<usize>,
    /// Orders the start loops after the first 128, which are seed 0's for every seed (any value
    /// gives a diverse family; 0 is the default order). With --alpha-max every seed runs the
    /// same starts (seed 0's order), so the seed does not change the gait.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
}

/// `solve` flags.
#[derive(Debug, Args)]
pub struct SolveArgs {
    /// Target position g_bar = X,Y,THETA reached from the origin: X, Y in metres, THETA in
    /// radians or degrees with deg (0.1,0.1,30deg), taken modulo 2 pi into ]-pi, pi]; 0,0,0
    /// or a largest component of at least 1e-6 (the smallest may exit 3: on the paper's swimmer
    /// X of 5e-5 m or less and THETA of 1e-6 rad do, their extremals not certified stationary).
    #[arg(long, value_parser = units::List([Length, Length, Angle]), default_value = "0.1,0.1,0",
          allow_hyphen_values = true)]
    pub target: [f64; 3],
    /// The problem and the search.
    #[command(flatten)]
    pub problem: ProblemArgs<SearchArgs>,
    /// Costate checkpoint spacing M in steps, below the horizon's N steps (0: none; a gait
    /// on its joint limit also has one at each arc's last step, which its replay needs)
    /// [default: 100, none if N is not above it].
    #[arg(long)]
    pub checkpoint_every: Option<u32>,
    /// Skip the figures (SVG and PNG) and field.csv.
    #[arg(long)]
    pub no_plots: bool,
    /// Angles in the figures in degrees and deg/s (the CSV files stay in radians; angle
    /// flags take degrees with their own deg suffix, e.g. --alpha-max 85deg).
    #[arg(long)]
    pub degrees: bool,
    /// Start from a stored extremal (a costate file for a nearby target, start shape, horizon,
    /// time step or swimmer: e.g. the same gait for another drag ratio) instead of the global
    /// search; if Newton does not reach an admissible extremal from it, the global search
    /// runs.
    #[arg(long, value_name = "COSTATE_JSON")]
    pub from: Option<PathBuf>,
    /// The output directory.
    #[command(flatten)]
    pub output: OutDirArgs,
    /// What to print.
    #[command(flatten)]
    pub print: PrintArgs,
}

/// `solve`: checks every input, prepares the output, solves, writes the files; the summary
/// (or with `--json` the report) as printed; no warning if `quiet`.
pub(super) fn run_solve(a: SolveArgs, quiet: bool) -> Result<String, Failure> {
    let t0 = Instant::now();
    let prepared = spec::prepare(&solve_spec(&a)).map_err(|e| fail(2, e))?;
    let inputs: Vec<&Path> = a.from.iter().map(PathBuf::as_path).collect();
    let out = a.output.prepare("solve", &inputs)?;
    let progress = Progress::new(t0, quiet);
    let Found {
        solution,
        problem,
        seconds,
        ..
    } = find_gait(&a, &prepared, quiet, &progress)?;
    let problem = &problem;
    progress.phase("output", 1, "directory");
    progress.suspend(|| warn_search(&solution, quiet));
    let best = &solution.extremals[solution.best];
    let solved = Solved::new(problem, &solution, prepared.checkpoint_every, seconds)
        .map_err(|e| fail(1, e))?;
    let figures = plots::Options { degrees: a.degrees };
    let figures = (!a.no_plots).then_some(&figures);
    let files = solved
        .files(problem, best, figures)
        .map_err(|e| fail(1, e))?;
    out.commit(&files).map_err(output_failure(false))?;
    progress.finish();
    Ok(if a.print.json {
        solved.report_text
    } else {
        summary::solve(
            &solved.report,
            &a.output.out,
            &files,
            t0.elapsed().as_secs_f64(),
        )
    })
}

/// The plain numbers of `a`'s solve.
fn solve_spec(a: &SolveArgs) -> SolveSpec {
    SolveSpec {
        problem: a.problem.spec(a.target),
        starts: a.problem.search.starts,
        seed: a.problem.search.seed,
        checkpoint_every: a.checkpoint_every,
    }
}

/// The warnings of a search that gave up early or left a cheaper minimum unrefined.
fn warn_search(solution: &Solution, quiet: bool) {
    for w in search_warnings(solution) {
        warn(quiet, format_args!("{}", w.words(Front::Cli)));
    }
}

/// [`find`] of `prepared` from `a.from`'s stored extremal (exit 2 for a file that is no
/// start), its notes warned, exit 3 (and what to try) for no gait.
fn find_gait(
    a: &SolveArgs,
    prepared: &Prepared,
    quiet: bool,
    progress: &Progress,
) -> Result<Found, Failure> {
    let warm = match &a.from {
        None => None,
        Some(path) => Some(spec::warm_start(path).map_err(|e| fail(2, e))?),
    };
    let found =
        find(prepared, warm.as_ref(), progress).map_err(|u| fail(3, u.words(Front::Cli)))?;
    progress.suspend(|| {
        for note in &found.notes {
            warn(quiet, format_args!("{}", note.words(Front::Cli)));
        }
    });
    Ok(found)
}
