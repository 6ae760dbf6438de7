//! The `purcell-sim` command line (clap): `solve`, `replay`, `connection`.

use crate::costate_file::CostateFile;
use crate::{input, output, plots, replay};
use clap::{ArgAction, Args, Parser, Subcommand, ValueEnum};
use purcell_core::{Arc, Gait};
use purcell_solver::problem::{InputError, Problem, Spec, check_gait_precision};
use purcell_solver::solver::continuation::{self, Lattice};
use purcell_solver::solver::{Evidence, Extremal, SolveOptions, solve};
use serde_json::json;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Exact optimal control of the planar three-link Purcell swimmer: solve offline, replay
/// through the embedded core, inspect the model.
#[derive(Debug, Parser)]
#[command(name = "purcell-sim", version)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Solve the discrete optimal-control problem and write DIR/{trajectory.csv,
    /// costate.json, report.json, field.csv, *.svg, *.png}.
    Solve(SolveArgs),
    /// Replay a gait (binary, or a costate file) through the core as firmware does (f64 and
    /// f32, with and without checkpoints): print each trajectory's digest, final state bits and
    /// terminal error against the target and alpha0.
    Replay(ReplayArgs),
    /// Write the binary gait file of a costate file, for `include_bytes!` in firmware.
    Export(ExportArgs),
    /// Print the local connection A(alpha) and its derivatives as JSON (rows x, y, theta;
    /// columns alpha1, alpha2).
    Connection(ConnectionArgs),
    /// Solve a lattice of targets by continuation from neighbours and write DIR/sweep.csv
    /// (target, cost, residual, largest |alpha_i|, local minimum) and a map of the cost over
    /// the target plane.
    Sweep(SweepArgs),
    /// Draw the curvature of the connection over the shape plane (rows x, y, theta), with a
    /// gait on top, and write DIR/{field.svg, field.png, field.csv}.
    Field(FieldArgs),
}

/// `--checkpoint-every` when not given.
const CHECKPOINT_EVERY: u32 = 100;
/// Most periodic checkpoints `solve` writes (0.33 kB each in the costate file), so that its
/// files stay below [`input::MAX_INPUT_BYTES`] and can be read back.
pub const MAX_CHECKPOINTS: u32 = 100_000;

/// Largest `--starts` (each start is a Newton–SQP run on the coarse grid, a few ms).
pub const MAX_STARTS: usize = 4096;
/// Largest horizon `solve` accepts, in steps (its memory grows by about 0.3 kB per step and
/// start); `replay` accepts up to [`purcell_solver::problem::MAX_STEPS`].
pub const MAX_SOLVE_STEPS: u32 = 1_000_000;

// Number flags take values as typed, negative ones included (`--alpha -0.5,0.3`), and list
// their defaults as they can be typed back (`0.1,0.1,0`). A flag given twice is refused
// (clap's usage error), lists included: `--target 1,2 --target 3` is not `1,2,3`.

/// Swimmer parameters shared by the subcommands.
#[derive(Debug, Args)]
pub struct ModelArgs {
    /// Link lengths L0 (middle), L1 (front), L2 (rear), in metres.
    #[arg(
        long,
        value_delimiter = ',',
        action = ArgAction::Set,
        default_value = "1,1,1",
        allow_hyphen_values = true
    )]
    pub links: Vec<f64>,
    /// Drag coefficient k (force per unit length per unit speed; scales forces only).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub drag: f64,
    /// Drag ratio r: normal over tangential drag (2 for slender bodies).
    #[arg(long, default_value_t = 2.0, allow_hyphen_values = true)]
    pub ratio: f64,
}

/// `solve` flags.
#[derive(Debug, Args)]
pub struct SolveArgs {
    /// Target position g_bar = X,Y,THETA (metres, metres, radians), reached from the origin;
    /// THETA is taken modulo 2 pi into ]-pi, pi].
    #[arg(
        long,
        value_delimiter = ',',
        action = ArgAction::Set,
        default_value = "0.1,0.1,0",
        allow_hyphen_values = true
    )]
    pub target: Vec<f64>,
    /// Horizon T in seconds; must be a whole number of steps (at most 1000000).
    #[arg(long, default_value_t = 100.0, allow_hyphen_values = true)]
    pub horizon: f64,
    /// Time step h in seconds.
    #[arg(long, default_value_t = 0.01, allow_hyphen_values = true)]
    pub step: f64,
    /// Start and end shape alpha_bar = A1,A2 in radians (each |A_i| < pi).
    #[arg(
        long,
        value_delimiter = ',',
        action = ArgAction::Set,
        default_value = "0,0",
        allow_hyphen_values = true
    )]
    pub alpha0: Vec<f64>,
    /// Swimmer parameters.
    #[command(flatten)]
    pub model: ModelArgs,
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
    /// Joint limit |alpha_i| <= alpha-max along the path, radians, below pi (default: only
    /// the links' overlap at pi). The solver returns the cheapest gait within it, with the
    /// limit active on arcs where that is cheaper.
    #[arg(long, allow_hyphen_values = true)]
    pub alpha_max: Option<f64>,
    /// Costate checkpoint spacing M in steps, below the horizon's N steps (0: none; a gait
    /// on its joint limit also has one at each arc's last step, which its replay needs)
    /// [default: 100, none if N is not above it].
    #[arg(long)]
    pub checkpoint_every: Option<u32>,
    /// Skip the figures (SVG and PNG) and field.csv.
    #[arg(long)]
    pub no_plots: bool,
    /// Angles in the figures in degrees and deg/s (the CSV files stay in radians).
    #[arg(long)]
    pub degrees: bool,
    /// Start from a stored extremal (a costate file of the same swimmer, for a nearby target,
    /// start shape or horizon) instead of the global search.
    #[arg(long, value_name = "COSTATE_JSON")]
    pub from: Option<PathBuf>,
    /// Output directory: created, or replaced in one step if it is empty or a previous
    /// result of purcell-sim (anything else is refused before any work).
    #[arg(long)]
    pub out: PathBuf,
    /// Replace --out even if it holds files purcell-sim did not write.
    #[arg(long)]
    pub force: bool,
}

/// `sweep` flags.
#[derive(Debug, Args)]
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
    /// Horizon T in seconds; must be a whole number of steps.
    #[arg(long, default_value_t = 100.0, allow_negative_numbers = true)]
    pub horizon: f64,
    /// Time step h in seconds.
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
    pub step: f64,
    /// Start and end shape alpha_bar = A1,A2 in radians (each |A_i| < pi).
    #[arg(
        long,
        value_delimiter = ',',
        action = ArgAction::Set,
        default_value = "0,0",
        allow_hyphen_values = true
    )]
    pub alpha0: Vec<f64>,
    /// Swimmer parameters.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Budget of start loops of each global search (see `solve --help`).
    #[arg(long, default_value_t = SolveOptions::default().starts)]
    pub starts: usize,
    /// Joint limit |alpha_i| <= alpha-max, radians, below pi (see `solve --help`).
    #[arg(long, allow_negative_numbers = true)]
    pub alpha_max: Option<f64>,
    /// Skip the figure.
    #[arg(long)]
    pub no_plots: bool,
    /// Output directory: created, or replaced in one step if it is empty or a previous
    /// result of purcell-sim (anything else is refused before any work).
    #[arg(long)]
    pub out: PathBuf,
    /// Replace --out even if it holds files purcell-sim did not write.
    #[arg(long)]
    pub force: bool,
}

/// Largest number of targets a sweep accepts.
pub const MAX_SWEEP_TARGETS: usize = 10_000;

/// Replay precision selection.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Precision {
    /// Single precision (the Cortex-M4F build).
    F32,
    /// Double precision.
    F64,
}

/// `replay` flags.
#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("input").required(true).args(["costate", "gait"])))]
pub struct ReplayArgs {
    /// The costate file written by `solve` (DIR/costate.json).
    #[arg(long)]
    pub costate: Option<PathBuf>,
    /// A binary gait file written by `export`.
    #[arg(long)]
    pub gait: Option<PathBuf>,
    /// Replay only in this precision (default: the standard set f64, f32 with and without
    /// checkpoints).
    #[arg(long, value_enum)]
    pub precision: Option<Precision>,
    /// With --precision: ignore the file's costate checkpoints (except those at the
    /// joint-limit arcs' exits, which the replay of a constrained gait needs).
    #[arg(long)]
    pub no_checkpoints: bool,
    /// Also write the JSON report to this file (atomically; an existing file is replaced
    /// only if it is a previous replay report, never the costate file).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Replace --out even if it holds something else (never the costate file).
    #[arg(long)]
    pub force: bool,
}

/// `export` flags.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The costate file written by `solve` (DIR/costate.json).
    #[arg(long)]
    pub costate: PathBuf,
    /// The binary gait file to write (atomically; an existing file is replaced only if it is
    /// a gait file, never the costate file).
    #[arg(long)]
    pub out: PathBuf,
    /// Replace --out even if it holds something else (never the costate file).
    #[arg(long)]
    pub force: bool,
}

/// `connection` flags.
#[derive(Debug, Args)]
pub struct ConnectionArgs {
    /// Shape A1,A2 in radians (each |A_i| < pi).
    #[arg(
        long,
        value_delimiter = ',',
        action = ArgAction::Set,
        allow_hyphen_values = true,
        required = true
    )]
    pub alpha: Vec<f64>,
    /// Swimmer parameters.
    #[command(flatten)]
    pub model: ModelArgs,
}

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
    /// Swimmer parameters (not with --gait: the gait's file has its own).
    #[command(flatten)]
    pub model: ModelArgs,
    /// A costate file (DIR/costate.json) whose gait (replayed in f64) is drawn on top.
    #[arg(long, conflicts_with_all = ["links", "drag", "ratio"])]
    pub gait: Option<PathBuf>,
    /// Draw only this row (default: all three). field.csv always has all three.
    #[arg(long, value_enum)]
    pub component: Option<FieldComponent>,
    /// Shape axes in degrees (the curvature stays per rad^2, the CSV in radians).
    #[arg(long)]
    pub degrees: bool,
    /// Output directory: created, or replaced in one step if it is empty or a previous
    /// result of purcell-sim (anything else is refused before any work).
    #[arg(long)]
    pub out: PathBuf,
    /// Replace --out even if it holds files purcell-sim did not write.
    #[arg(long)]
    pub force: bool,
}

/// A failure of the command, with its exit code (the README's "Exit codes").
#[derive(Debug)]
pub struct Failure {
    /// Message for stderr.
    pub message: String,
    /// Exit code: 2 bad input (nothing done), 3 no solution (`solve`: no extremal;
    /// `replay`: a replay failed), 1 I/O.
    pub code: u8,
    /// What to print on stdout all the same (the `replay` report).
    pub stdout: String,
}

fn fail(code: u8, message: impl ToString) -> Failure {
    Failure {
        message: message.to_string(),
        code,
        stdout: String::new(),
    }
}

/// Exit code for an output refused or not creatable before the work (2), or failing after
/// it (1).
fn output_failure(before_work: bool) -> impl FnOnce(output::OutputError) -> Failure {
    move |e| fail(if before_work { 2 } else { 1 }, e)
}

/// `N` comma-separated numbers of flag `name`.
fn arr<const N: usize>(name: &str, v: &[f64]) -> Result<[f64; N], Failure> {
    <[f64; N]>::try_from(v).map_err(|_| {
        fail(
            2,
            format!(
                "--{name} takes {N} comma-separated numbers (got {})",
                v.len()
            ),
        )
    })
}

/// Starts the worker threads of the search and the figures (rayon's global pool) once: a
/// system that refuses threads is exit 1, not a panic in the middle of the work.
fn start_threads() -> Result<(), Failure> {
    static STARTED: std::sync::OnceLock<Result<(), String>> = std::sync::OnceLock::new();
    STARTED
        .get_or_init(|| {
            rayon::ThreadPoolBuilder::new()
                .build_global()
                .map_err(|e| e.to_string())
        })
        .clone()
        .map_err(|e| fail(1, format!("cannot start worker threads: {e}")))
}

/// Runs a parsed command; the output to print on stdout on success.
pub fn run(cli: Cli) -> Result<String, Failure> {
    if matches!(
        cli.command,
        Command::Solve(_) | Command::Sweep(_) | Command::Field(_)
    ) {
        start_threads()?;
    }
    match cli.command {
        Command::Solve(a) => run_solve(a),
        Command::Replay(a) => run_replay(a),
        Command::Export(a) => run_export(a),
        Command::Connection(a) => run_connection(a),
        Command::Sweep(a) => run_sweep(a),
        Command::Field(a) => run_field(a),
    }
}

/// The bounds of a search (`solve`, `sweep`): `1 ≤ starts ≤ MAX_STARTS`, at most
/// `MAX_SOLVE_STEPS` steps (exit 2).
fn search_limits(problem: &Problem, starts: usize) -> Result<(), Failure> {
    if !(1..=MAX_STARTS).contains(&starts) {
        return Err(fail(
            2,
            format!("--starts must be 1 to {MAX_STARTS} (got {starts})"),
        ));
    }
    if problem.steps > MAX_SOLVE_STEPS {
        return Err(fail(
            2,
            format!(
                "horizon T/h = {} steps is more than solve's limit of {MAX_SOLVE_STEPS}",
                problem.steps
            ),
        ));
    }
    Ok(())
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

fn run_solve(a: SolveArgs) -> Result<String, Failure> {
    let [x, y, theta] = arr("target", &a.target)?;
    let spec = Spec {
        target: [x, y, wrap_angle(theta)],
        horizon: a.horizon,
        step: a.step,
        alpha0: arr("alpha0", &a.alpha0)?,
        links: arr("links", &a.model.links)?,
        drag: a.model.drag,
        ratio: a.model.ratio,
        alpha_max: a.alpha_max,
    };
    let problem = Problem::new(&spec).map_err(|e| fail(2, e))?;
    // The costate file is for the f32 firmware, and the report replays it in f32.
    problem
        .check_precision::<f32>("f32")
        .map_err(|e| fail(2, e))?;
    search_limits(&problem, a.starts)?;
    let checkpoint_every = checkpoint_spacing(a.checkpoint_every, problem.steps)?;
    let inputs: Vec<&Path> = a.from.iter().map(PathBuf::as_path).collect();
    let out = output::OutputDir::prepare(&a.out, "solve", a.force, &inputs)
        .map_err(output_failure(true))?;
    let options = SolveOptions {
        starts: a.starts,
        seed: a.seed,
        ..SolveOptions::default()
    };
    let bar = std::io::stderr().is_terminal().then(|| {
        let b = indicatif::ProgressBar::new(a.starts as u64 + 1);
        b.set_style(
            indicatif::ProgressStyle::with_template("searching {bar:30} {pos} starts ({elapsed})")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    });
    let tick = || {
        if let Some(b) = &bar {
            b.inc(1);
        }
    };
    let warm = match &a.from {
        None => None,
        Some(path) => Some(warm_start(path, &problem)?),
    };
    let t0 = Instant::now();
    let result = match &warm {
        None => solve(&problem, &options, &tick),
        Some(w) => {
            let (result, failed) = continuation::solve_from(&problem, w, &options, &tick);
            if let Some(e) = failed {
                eprintln!(
                    "warning: --from reached no admissible extremal of this problem ({e}); \
                     solved by the global search instead"
                );
            }
            result
        }
    };
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let solution = result.map_err(|e| fail(3, e))?;
    let seconds = t0.elapsed().as_secs_f64();
    if let Some(e) = solution.search.as_ref().filter(|e| !e.satisfied) {
        eprintln!(
            "warning: the search used its budget of {} starts before its stopping rule was met \
             (estimated chance that another start finds an unseen minimum no dearer than the \
             gait returned: {:.3}); this is the cheapest gait found: raise --starts to search on",
            e.budget, e.unseen
        );
    }
    let best = &solution.extremals[solution.best];
    let file = output::costate_file(&problem, best, checkpoint_every);
    let gait_bytes = file
        .to_gait()
        .map_err(|e| fail(1, format!("the solution's gait: {e}")))?;
    let gait =
        Gait::from_bytes(&gait_bytes).map_err(|e| fail(1, format!("the solution's gait: {e}")))?;
    let extremals: Vec<_> = solution.extremals.iter().map(extremal_json).collect();
    let report = json!({
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
        "replays": replay::standard_replays(&gait),
    });
    let report_text = serde_json::to_string_pretty(&report).map_err(|e| fail(1, e))? + "\n";
    let mut files = vec![
        (
            "trajectory.csv".to_string(),
            output::trajectory_csv(&problem, &best.trajectory).into_bytes(),
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
    Ok(report_text)
}

fn run_field(a: FieldArgs) -> Result<String, Failure> {
    let (problem, states, arcs) = match &a.gait {
        Some(path) => {
            let file = read_costate(path)?;
            let problem = file
                .problem()
                .map_err(|e| fail(2, format!("{}: {e}", path.display())))?;
            let (states, stride) = replay::gait_states(&file, 10_000).map_err(|e| {
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
            (problem, Some(states), arcs)
        }
        None => {
            let spec = Spec {
                links: arr("links", &a.model.links)?,
                drag: a.model.drag,
                ratio: a.model.ratio,
                ..Spec::default()
            };
            (
                Problem::new(&spec).map_err(|e| fail(2, e))?,
                None,
                Vec::new(),
            )
        }
    };
    let components = match a.component {
        None => plots::field::Component::ALL.to_vec(),
        Some(FieldComponent::X) => vec![plots::field::Component::X],
        Some(FieldComponent::Y) => vec![plots::field::Component::Y],
        Some(FieldComponent::Theta) => vec![plots::field::Component::Theta],
    };
    let inputs: Vec<&Path> = a.gait.iter().map(PathBuf::as_path).collect();
    let out = output::OutputDir::prepare(&a.out, "field", a.force, &inputs)
        .map_err(output_failure(true))?;
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
    Ok(
        serde_json::to_string_pretty(&json!({ "out": a.out.to_string_lossy(), "files": names }))
            .map_err(|e| fail(1, e))?
            + "\n",
    )
}

/// The stored extremal of `path` as a start for `problem`: same swimmer required.
fn warm_start(path: &Path, problem: &Problem) -> Result<continuation::Warm, Failure> {
    let file = read_costate(path)?;
    let stored = file
        .problem()
        .map_err(|e| fail(2, format!("{}: {e}", path.display())))?;
    if stored.swimmer != problem.swimmer {
        return Err(fail(
            2,
            format!(
                "{}: stored for another swimmer (links, drag or ratio differ); --from needs the same model",
                path.display()
            ),
        ));
    }
    let t = replay::trajectory(&file)
        .map_err(|e| fail(2, format!("{}: its replay fails ({e})", path.display())))?;
    let mu = nalgebra::Vector3::from(file.mu);
    continuation::Warm::from_trajectory(&t, &mu, stored.horizon())
        .ok_or_else(|| fail(2, format!("{}: empty trajectory", path.display())))
}

/// `FROM:TO:COUNT` or a single value.
fn axis(name: &str, text: &str) -> Result<Vec<f64>, Failure> {
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

fn run_sweep(a: SweepArgs) -> Result<String, Failure> {
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
    let spec = Spec {
        target: [0.0; 3],
        horizon: a.horizon,
        step: a.step,
        alpha0: arr("alpha0", &a.alpha0)?,
        links: arr("links", &a.model.links)?,
        drag: a.model.drag,
        ratio: a.model.ratio,
        alpha_max: a.alpha_max,
    };
    let problem = Problem::new(&spec).map_err(|e| fail(2, e))?;
    search_limits(&problem, a.starts)?;
    let out =
        output::OutputDir::prepare(&a.out, "sweep", a.force, &[]).map_err(output_failure(true))?;
    let options = SolveOptions {
        starts: a.starts,
        ..SolveOptions::default()
    };
    let bar = std::io::stderr().is_terminal().then(|| {
        // Each target ticks once when searched and once when refined.
        let b = indicatif::ProgressBar::new(2 * lattice.len() as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "sweeping {bar:30} {pos}/{len} searches and refinements ({elapsed})",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    });
    let tick = || {
        if let Some(b) = &bar {
            b.inc(1);
        }
    };
    let t0 = Instant::now();
    let points = continuation::sweep(&spec, &lattice, &options, &tick).map_err(|e| fail(2, e))?;
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let seconds = t0.elapsed().as_secs_f64();
    let csv = output::sweep_csv(&points);
    let solved = points
        .iter()
        .filter(|p| p.result.as_ref().is_ok_and(|x| x.admissible))
        .count();
    let summary = json!({
        "targets": points.len(), "solved": solved, "sweep_seconds": seconds,
        "axes": {"x": lattice.axes[0], "y": lattice.axes[1], "theta": lattice.axes[2]},
        "problem": {"horizon": a.horizon, "step": a.step, "alpha0": spec.alpha0,
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
    Ok(summary_text)
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
        "minima": e.minima.iter().map(|m| json!({
            "cost": m.cost, "max_abs_alpha": m.max_abs_alpha, "hits": m.hits,
        })).collect::<Vec<_>>(),
    })
}

/// Joint-limit arcs in `report.json`, as the costate file stores them (`purcell_core::Arc`:
/// joint 1 or 2, as `α_1`, `α_2`, the limit's sign ±1, the first and last state on it).
fn arcs_json(arcs: &[Arc]) -> serde_json::Value {
    arcs.iter().map(|a| json!(a)).collect()
}

/// Reads an input file, at most [`input::MAX_INPUT_BYTES`] (exit 2 if unreadable).
fn read_input(path: &Path) -> Result<Vec<u8>, Failure> {
    input::read(path).map_err(|e| fail(2, format!("reading {}: {e}", path.display())))
}

/// Reads a costate file (exit 2 if unreadable or invalid).
fn read_costate(path: &Path) -> Result<CostateFile, Failure> {
    let text = String::from_utf8(read_input(path)?).map_err(|e| {
        fail(
            2,
            format!("{}: malformed costate file: {e}", path.display()),
        )
    })?;
    CostateFile::parse(&text).map_err(|e| fail(2, format!("{}: {e}", path.display())))
}

/// What every route to a replay checks in a stored gait of `path` (`replay --costate`,
/// `replay --gait`, `export`), besides the core's own validation: its problem as
/// command-line input ([`Problem::of_gait`], the step limit included) and, where it is
/// replayed in `f32`, every number there ([`purcell_solver::problem::check_gait_precision`]); exit 2.
fn check_stored(path: &Path, gait: &Gait<'_>, f32: bool) -> Result<(), Failure> {
    let refused = |e: InputError| fail(2, format!("{}: {e}", path.display()));
    Problem::of_gait(gait.params()).map_err(refused)?;
    if f32 {
        check_gait_precision::<f32>(gait.params(), gait.checkpoints(), "f32").map_err(refused)?;
    }
    Ok(())
}

/// The `format` tag of the `replay` report, by which `replay --out` recognises its own.
const REPLAY_REPORT: &str = "purcell-replay";

/// Whether `bytes` are a `replay` report.
fn is_replay_report(bytes: &[u8]) -> bool {
    input::json::<serde_json::Value>(bytes)
        .is_ok_and(|v| v.get("format").and_then(|f| f.as_str()) == Some(REPLAY_REPORT))
}

/// Whether `bytes` are a gait file (its magic), by which `export --out` recognises its own.
fn is_gait_file(bytes: &[u8]) -> bool {
    bytes.starts_with(&purcell_core::gait::MAGIC)
}

fn run_replay(a: ReplayArgs) -> Result<String, Failure> {
    let (path, bytes) = match (&a.costate, &a.gait) {
        (Some(path), _) => {
            let file = read_costate(path)?;
            let bytes = file
                .to_gait()
                .map_err(|e| fail(2, format!("{}: {e}", path.display())))?;
            (path, bytes)
        }
        (None, Some(path)) => (path, read_input(path)?),
        (None, None) => return Err(fail(2, "replay needs --costate or --gait")),
    };
    let gait = Gait::from_bytes(&bytes).map_err(|e| fail(2, format!("{}: {e}", path.display())))?;
    check_stored(path, &gait, !matches!(a.precision, Some(Precision::F64)))?;
    let out = match &a.out {
        Some(out) => Some(
            output::OutputFile::prepare(out, is_replay_report, a.force, &[path.as_path()])
                .map_err(output_failure(true))?,
        ),
        None => None,
    };
    let checkpoints = !a.no_checkpoints;
    let results = match a.precision {
        None => replay::standard_replays(&gait),
        Some(Precision::F64) => vec![replay::replay_gait::<f64>(&gait, "f64", checkpoints)],
        Some(Precision::F32) => vec![replay::replay_gait::<f32>(&gait, "f32", checkpoints)],
    };
    if let Some(out) = out {
        let p = gait.params();
        let report = json!({ "format": REPLAY_REPORT, "version": 1,
                             "crc": format!("{:#010x}", gait.crc()), "target": p.target,
                             "alpha0": p.alpha0, "replays": results });
        let json = serde_json::to_string_pretty(&report).map_err(|e| fail(1, e))? + "\n";
        out.commit(json.as_bytes()).map_err(output_failure(false))?;
    }
    let text = replay::text(&gait, &results);
    let p = gait.params();
    let failed: Vec<String> = results
        .iter()
        .filter_map(|r| {
            let why = r.failure.as_ref()?;
            let which = format!(
                "{} replay {} checkpoints",
                r.precision,
                if r.checkpoints { "with" } else { "without" }
            );
            Some(match r.failed_at_step {
                Some(k) => format!(
                    "{which} failed at step {k} of {} (t = {} s): {why}",
                    p.steps,
                    (f64::from(k) * p.h * 1e9).round() / 1e9
                ),
                None => format!("{which} failed before its first step: {why}"),
            })
        })
        .collect();
    if failed.is_empty() {
        Ok(text)
    } else {
        Err(Failure {
            message: failed.join("\nerror: "),
            code: 3,
            stdout: text,
        })
    }
}

fn run_export(a: ExportArgs) -> Result<String, Failure> {
    let file = read_costate(&a.costate)?;
    let bytes = file
        .to_gait()
        .map_err(|e| fail(2, format!("{}: {e}", a.costate.display())))?;
    let gait = Gait::from_bytes(&bytes).map_err(|e| fail(1, e))?;
    // The gait is for the f32 firmware.
    check_stored(&a.costate, &gait, true)?;
    let out = output::OutputFile::prepare(&a.out, is_gait_file, a.force, &[a.costate.as_path()])
        .map_err(output_failure(true))?;
    out.commit(&bytes).map_err(output_failure(false))?;
    Ok(format!(
        "gait: wrote {} ({} bytes, crc={:#010x}, steps={}, checkpoints={}, arcs={})\n",
        a.out.display(),
        bytes.len(),
        gait.crc(),
        gait.params().steps,
        gait.checkpoint_count(),
        gait.arc_count()
    ))
}

fn run_connection(a: ConnectionArgs) -> Result<String, Failure> {
    let alpha: [f64; 2] = arr("alpha", &a.alpha)?;
    let spec = Spec {
        links: arr("links", &a.model.links)?,
        drag: a.model.drag,
        ratio: a.model.ratio,
        alpha0: alpha,
        ..Spec::default()
    };
    let problem =
        Problem::new(&spec).map_err(|e| fail(2, e.to_string().replace("alpha0", "alpha")))?;
    let c = problem
        .swimmer
        .connection_with_derivatives(&nalgebra::Vector2::new(alpha[0], alpha[1]))
        .map_err(|e| fail(2, e))?;
    let rows =
        |m: &nalgebra::Matrix3x2<f64>| (0..3).map(|r| [m[(r, 0)], m[(r, 1)]]).collect::<Vec<_>>();
    let out = json!({"A": rows(&c.a), "dA_dalpha1": rows(&c.da[0]), "dA_dalpha2": rows(&c.da[1])});
    Ok(serde_json::to_string_pretty(&out).map_err(|e| fail(1, e))? + "\n")
}
