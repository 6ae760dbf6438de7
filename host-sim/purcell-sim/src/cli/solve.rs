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
use crate::plots;
use crate::report::{Solved, search_warnings};
use crate::spec::{self, MAX_STARTS, Prepared, SolveSpec};
use crate::words::{Front, Worded};
use clap::Args;
use purcell_solver::problem::{OVERLAP, Problem};
use purcell_solver::solver::settings::OVERLAP_MARGIN;
use purcell_solver::solver::{Progress as _, Solution, SolveError, SolveOptions, solve};
use purcell_solver::solver::{continuation, starts};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// `solve`'s search flags.
#[derive(Debug, Args)]
pub struct SearchArgs {
    /// Budget of start loops of the global search (run in batches of 32, in parallel; 1 to
    /// 4096; the family has 1 128 loops, 936 with --alpha-max, a larger budget runs them
    /// all). The search stops
    /// earlier once its stopping rule is met: at least 128 starts run, an estimated chance
    /// below 0.5 % that another start reaches a minimum not seen yet that is no dearer than
    /// the cheapest admissible one (Good-Turing: the share of starts that alone reached such
    /// a minimum), and that extremal reached from 3 starts. A search that spends its budget first says so on stderr and returns the
    /// cheapest gait it found.
    #[arg(long, default_value_t = SolveOptions::default().starts)]
    pub starts: usize,
    /// Orders the start loops (any value gives a diverse family; 0 is the default order).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
}

/// `solve` flags.
#[derive(Debug, Args)]
pub struct SolveArgs {
    /// Target position g_bar = X,Y,THETA reached from the origin: X, Y in metres, THETA in
    /// radians or degrees with deg (0.1,0.1,30deg), taken modulo 2 pi into ]-pi, pi]; 0,0,0
    /// or a largest component of at least 1e-6.
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
    /// Start from a stored extremal (a costate file for a nearby target, start shape, horizon
    /// or swimmer: e.g. the same gait for another drag ratio) instead of the global search; if
    /// Newton does not reach an admissible extremal from it, the global search runs.
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
    let (solution, problem, seconds) = find(&a, &prepared, quiet, &progress)?;
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

/// The solution of `problem` from `a.from`'s stored extremal, or from the global search
/// (without `--from`, or when it reaches no admissible extremal: a warning), the problem it
/// solves and its seconds, its phases told to `progress`; exit 2 for a `--from` file that is
/// no start, 3 for no extremal. Without a joint limit, when every extremal found crosses the
/// links' overlap, the cheapest gait within [`OVERLAP_MARGIN`] of it (the problem with
/// `--alpha-max π − OVERLAP_MARGIN`, a warning), if there is one.
fn find(
    a: &SolveArgs,
    prepared: &Prepared,
    quiet: bool,
    progress: &Progress,
) -> Result<(Solution, Problem, f64), Failure> {
    let (problem, options) = (&prepared.problem, prepared.options);
    let warm = match &a.from {
        None => None,
        Some(path) => Some(spec::warm_start(path).map_err(|e| fail(2, e))?),
    };
    let t0 = Instant::now();
    let result = match &warm {
        None => solve(problem, &options, progress),
        Some(w) => {
            let (result, failed) = continuation::solve_from(problem, w, &options, progress);
            if let Some(e) = failed {
                warn(
                    quiet,
                    format_args!(
                        "--from reached no admissible extremal of this problem ({e}); solved \
                         by the global search instead"
                    ),
                );
            }
            result
        }
    };
    let failure = |e: SolveError| fail(3, format!("{e}\n{}", what_to_try(&e, a, problem)));
    let solution = match result {
        Ok(s) => s,
        Err(e @ SolveError::NoneAdmissible { .. }) if problem.alpha_max.is_none() => {
            let alpha_max = OVERLAP - OVERLAP_MARGIN;
            let margin = Problem {
                alpha_max: Some(alpha_max),
                ..*problem
            };
            progress.suspend(|| {
                warn(
                    quiet,
                    format_args!(
                        "{e}: no gait found inside the links' overlap; solving for the cheapest \
                         within {OVERLAP_MARGIN} rad of it (--alpha-max {alpha_max:.4}); the gait \
                         returned rests on that bound where it has arcs (report.json: alpha_max)"
                    ),
                )
            });
            let solution = solve(&margin, &options, progress).map_err(|_| failure(e))?;
            return Ok((solution, margin, t0.elapsed().as_secs_f64()));
        }
        Err(e) => return Err(failure(e)),
    };
    Ok((solution, *problem, t0.elapsed().as_secs_f64()))
}

/// What exit 3's message suggests after `e`, by its cause.
fn what_to_try(e: &SolveError, a: &SolveArgs, problem: &Problem) -> String {
    let starts = a.problem.search.starts;
    // More starts than the family holds run no more loops.
    let family = starts::family(
        1.0,
        &problem.alpha0,
        0,
        MAX_STARTS,
        problem.alpha_max.is_none(),
    );
    let mut tries = Vec::new();
    if starts < family.len() {
        tries.push(format!(
            "more starts (--starts {}; {starts} now)",
            (4 * starts).min(family.len())
        ));
    }
    tries.push(format!("another --seed ({} now)", a.problem.search.seed));
    tries.push(
        "a warm start from the gait of a nearer target, solved first (--from DIR/costate.json)"
            .into(),
    );
    match (e, problem.alpha_max) {
        (SolveError::Unreachable { .. }, _) => {}
        (_, Some(limit)) => tries.push(format!("a looser joint limit (--alpha-max; {limit} now)")),
        (SolveError::NoneAdmissible { .. }, None) => tries.push(
            "another start shape if it is yours to choose (--alpha0): every extremal found \
             crosses the links' overlap"
                .into(),
        ),
        (_, None) => {}
    }
    let last = tries.pop().unwrap_or_default();
    format!("try {}, or {last}", tries.join(", "))
}
