//! `solve`: the optimal gait of one target, from the global search or a stored extremal
//! (`--from`), written with its costate file, report and figures.

use super::args::{
    Failure, MAX_STARTS, OutDirArgs, PrintArgs, ProblemArgs, Progress, fail, output_failure,
    read_costate, search_limits, warn,
};
use super::summary;
use super::units::{
    self,
    Quantity::{Angle, Length},
};
use crate::costate_file::CostateFile;
use crate::{output, plots, replay};
use clap::Args;
use purcell_core::{Arc, Gait};
use purcell_solver::problem::Problem;
use purcell_solver::solver::{
    Evidence, Extremal, Minimum, Solution, SolveError, SolveOptions, solve,
};
use purcell_solver::solver::{continuation, starts};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// `--checkpoint-every` when not given.
const CHECKPOINT_EVERY: u32 = 100;
/// Most periodic checkpoints `solve` writes (0.33 kB each in the costate file), so that its
/// files stay below [`crate::input::MAX_INPUT_BYTES`] and can be read back.
pub const MAX_CHECKPOINTS: u32 = 100_000;

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
    /// radians or degrees with deg (0.1,0.1,30deg), taken modulo 2 pi into ]-pi, pi].
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

/// `theta` modulo 2π in `]−π, π]` (as given if it is there already; NaN if not finite).
fn wrap_angle(theta: f64) -> f64 {
    use core::f64::consts::{PI, TAU};
    if -PI < theta && theta <= PI {
        return theta;
    }
    let t = theta.rem_euclid(TAU);
    if t > PI { t - TAU } else { t }
}

/// The checkpoint spacing of a solve of `steps` steps: as given, below `steps` (or 0), with
/// at most [`MAX_CHECKPOINTS`] checkpoints; [`CHECKPOINT_EVERY`] if not given (exit 2).
fn checkpoint_spacing(given: Option<u32>, steps: u32) -> Result<u32, Failure> {
    let every = given.unwrap_or(CHECKPOINT_EVERY);
    if given.is_some() && every != 0 && every >= steps {
        return Err(fail(
            2,
            format!(
                "--checkpoint-every {every} is not below the horizon's {steps} steps: the \
                 costate file would have no checkpoint (0 for none)"
            ),
        ));
    }
    if every != 0 && (steps - 1) / every > MAX_CHECKPOINTS {
        return Err(fail(
            2,
            format!(
                "--checkpoint-every {every} gives {} checkpoints over {steps} steps, more than \
                 the limit {MAX_CHECKPOINTS}",
                (steps - 1) / every
            ),
        ));
    }
    Ok(every)
}

/// `solve`: checks every input, prepares the output, solves, writes the files; the summary
/// (or with `--json` the report) as printed; no warning if `quiet`.
pub(super) fn run_solve(a: SolveArgs, quiet: bool) -> Result<String, Failure> {
    let (problem, checkpoint_every) = checked_problem(&a)?;
    let inputs: Vec<&Path> = a.from.iter().map(PathBuf::as_path).collect();
    let out = a.output.prepare("solve", &inputs)?;
    let (solution, seconds) = find(&a, &problem, quiet)?;
    if let Some(e) = solution.search.as_ref().filter(|e| !e.satisfied) {
        warn(
            quiet,
            format_args!(
                "the search used its budget of {} starts before its stopping rule was met \
                 (estimated chance that another start finds an unseen minimum no dearer than \
                 the gait returned: {:.3}); this is the cheapest gait found: raise --starts to \
                 search on",
                e.budget, e.unseen
            ),
        );
    }
    // Cheapest first, as the search's minima: one warning, for the cheapest.
    let unrefined = solution.search.iter().flat_map(|e| &e.unrefined);
    let cheaper: Vec<_> = unrefined.filter(|u| u.cheaper).collect();
    if let Some(u) = cheaper.first() {
        warn(
            quiet,
            format_args!(
                "{u} ({} such minima in report.json's search.unrefined): try another --seed \
                 or --starts",
                cheaper.len()
            ),
        );
    }
    let best = &solution.extremals[solution.best];
    let file = output::costate_file(&problem, best, checkpoint_every);
    let gait_bytes = file
        .to_gait()
        .map_err(|e| fail(1, format!("the solution's gait: {e}")))?;
    let gait =
        Gait::from_bytes(&gait_bytes).map_err(|e| fail(1, format!("the solution's gait: {e}")))?;
    let report = report_json(&problem, &solution, &file, &gait, seconds);
    let report_text = serde_json::to_string_pretty(&report).map_err(|e| fail(1, e))? + "\n";
    let mut files = vec![
        (
            "trajectory.csv".to_string(),
            output::trajectory_csv(&problem, best).into_bytes(),
        ),
        ("costate.json".to_string(), file.to_json().into_bytes()),
        ("report.json".to_string(), report_text.clone().into_bytes()),
    ];
    if !a.no_plots {
        let options = plots::Options { degrees: a.degrees };
        files.extend(
            plots::figures(
                &problem,
                &best.trajectory,
                &best.arcs,
                &best.mu,
                &file,
                &options,
            )
            .map_err(|e| fail(1, format!("plotting: {e}")))?,
        );
    }
    out.commit(&files).map_err(output_failure(false))?;
    Ok(if a.print.json {
        report_text
    } else {
        summary::solve(&report, &a.output.out, &files)
    })
}

/// The problem of `a` and its checkpoint spacing, checked as `solve` input (exit 2): the
/// model ([`Problem::new`]), every number within `f32` (the costate file is for the `f32`
/// firmware, and the report replays it in `f32`), the search's limits.
pub fn checked_problem(a: &SolveArgs) -> Result<(Problem, u32), Failure> {
    let [x, y, theta] = a.target;
    let spec = a.problem.spec([x, y, wrap_angle(theta)]);
    let problem = Problem::new(&spec).map_err(|e| fail(2, e))?;
    problem
        .check_precision::<f32>("f32")
        .map_err(|e| fail(2, e))?;
    search_limits(&problem, a.problem.search.starts)?;
    let checkpoint_every = checkpoint_spacing(a.checkpoint_every, problem.steps)?;
    Ok((problem, checkpoint_every))
}

/// The solution of `problem` from `a.from`'s stored extremal, or from the global search
/// (without `--from`, or when it reaches no admissible extremal: a warning), and its
/// seconds; exit 2 for a `--from` file that is no start, 3 for no extremal.
fn find(a: &SolveArgs, problem: &Problem, quiet: bool) -> Result<(Solution, f64), Failure> {
    let search = &a.problem.search;
    let options = SolveOptions {
        starts: search.starts,
        seed: search.seed,
        ..SolveOptions::default()
    };
    let progress = Progress::new(
        search.starts as u64 + 1,
        "searching {bar:30} {pos} starts ({elapsed})",
        quiet,
    );
    let tick = || progress.tick();
    let warm = match &a.from {
        None => None,
        Some(path) => Some(warm_start(path)?),
    };
    let t0 = Instant::now();
    let result = match &warm {
        None => solve(problem, &options, &tick),
        Some(w) => {
            let (result, failed) = continuation::solve_from(problem, w, &options, &tick);
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
    progress.finish();
    let solution = result.map_err(|e| fail(3, format!("{e}\n{}", what_to_try(&e, a, problem))))?;
    Ok((solution, t0.elapsed().as_secs_f64()))
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

/// The stored extremal of `path` as a start for a problem ([`warm_of`]).
pub fn warm_start(path: &Path) -> Result<continuation::Warm, Failure> {
    warm_of(&read_costate(path)?, &path.display().to_string())
}

/// The extremal of a costate `file` (named `name` in messages) as a start for a problem of
/// any swimmer: the gait's neighbouring extremal for another drag ratio or other links, where
/// Newton reaches it (exit 2 if its problem is invalid or its replay fails).
pub fn warm_of(file: &CostateFile, name: &str) -> Result<continuation::Warm, Failure> {
    let stored = file
        .problem()
        .map_err(|e| fail(2, format!("{name}: {e}")))?;
    let t =
        replay::trajectory(file).map_err(|e| fail(2, format!("{name}: its replay fails ({e})")))?;
    let mu = nalgebra::Vector3::from(file.mu);
    continuation::Warm::from_trajectory(&t, &mu, stored.horizon())
        .ok_or_else(|| fail(2, format!("{name}: empty trajectory")))
}

/// `report.json`'s `format` tag (schema: `docs/schemas/solve-report.schema.json`).
pub const REPORT_FORMAT: &str = "purcell-solve-report";
/// `report.json`'s version: 1 is the first tagged one.
pub const REPORT_VERSION: u64 = 1;

/// `report.json`: the returned extremal of `solution` (whose costate `file` and `gait` are
/// written), found in `seconds`, then every extremal, the search's evidence and the
/// standard replays of the gait.
pub fn report_json(
    problem: &Problem,
    solution: &Solution,
    file: &CostateFile,
    gait: &Gait<'_>,
    seconds: f64,
) -> serde_json::Value {
    let best = &solution.extremals[solution.best];
    let extremals: Vec<_> = solution.extremals.iter().map(extremal_json).collect();
    json!({
        "format": REPORT_FORMAT, "version": REPORT_VERSION,
        "cost": best.cost,
        "residual": best.residual,
        "terminal_residual": best.terminal_residual,
        "kkt_residual": best.kkt_residual,
        "arcs": arcs_json(&best.arcs),
        "min_eta": best.min_eta,
        "law_residual": best.law_residual,
        "local_min": best.local_min,
        "max_abs_alpha": best.max_abs_alpha,
        "admissible": best.admissible,
        "returned": solution.best,
        "solve_seconds": seconds,
        "search": solution.search.as_ref().map(evidence_json),
        "mu": file.mu, "xi0": file.xi0,
        "problem": {"target": file.target, "horizon": problem.horizon(), "step": problem.h,
                    "steps": problem.steps, "alpha0": file.alpha0, "links": file.model.links,
                    "drag": file.model.drag, "ratio": file.model.ratio,
                    "alpha_max": problem.alpha_max},
        "extremals": extremals,
        // Terminal errors of the stored costate replayed through the core, as the firmware
        // flies it (f32 with checkpoints) beside f64.
        "replays": replay::standard_replays(gait),
    })
}

/// One extremal in `report.json`.
fn extremal_json(x: &Extremal) -> serde_json::Value {
    json!({
        "cost": x.cost, "max_abs_alpha": x.max_abs_alpha, "admissible": x.admissible,
        "local_min": x.local_min, "residual": x.residual,
        "terminal_residual": x.terminal_residual, "kkt_residual": x.kkt_residual,
        "arcs": arcs_json(&x.arcs), "min_eta": x.min_eta,
        "stationarity": x.stationarity, "law_residual": x.law_residual,
        "newton_iterations": x.iterations, "start": x.start, "hits": x.hits, "twin_of": x.twin_of,
        "mu": [x.mu.x, x.mu.y, x.mu.z], "xi0": [x.xi0.x, x.xi0.y],
    })
}

/// The global search's evidence in `report.json` (an infinite estimate as `null`).
fn evidence_json(e: &Evidence) -> serde_json::Value {
    let finite = |x: f64| x.is_finite().then_some(x);
    json!({
        "starts": e.starts, "budget": e.budget, "rule_met": e.satisfied,
        "unseen_estimate": e.unseen, "expected_minima": finite(e.expected_minima),
        "distinct_minima": e.minima.len(),
        "minima": e.minima.iter().map(minimum_json).collect::<Vec<_>>(),
        "unrefined": e.unrefined.iter().map(|u| {
            let mut m = minimum_json(&u.minimum);
            m["defect"] = json!(finite(u.defect));
            m["cheaper"] = json!(u.cheaper);
            m
        }).collect::<Vec<_>>(),
    })
}

/// A minimum of the coarse search in `report.json`.
fn minimum_json(m: &Minimum) -> serde_json::Value {
    json!({"cost": m.cost, "max_abs_alpha": m.max_abs_alpha, "hits": m.hits})
}

/// Joint-limit arcs in `report.json`, as the costate file stores them (`purcell_core::Arc`:
/// joint 1 or 2, as `α_1`, `α_2`, the limit's sign ±1, the first and last state on it).
fn arcs_json(arcs: &[Arc]) -> serde_json::Value {
    arcs.iter().map(|a| json!(a)).collect()
}
