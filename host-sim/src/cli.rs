//! The `purcell-sim` command line (clap): `solve`, `replay`, `connection`.

use crate::costate_file::CostateFile;
use crate::problem::{Problem, Spec};
use crate::solve::{SolveOptions, solve};
use crate::{output, plots, replay};
use clap::{Args, Parser, Subcommand, ValueEnum};
use serde_json::json;
use std::io::IsTerminal;
use std::path::PathBuf;
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
    /// costate.json, report.json, *.svg}.
    Solve(SolveArgs),
    /// Replay a costate file through the core (f64 and f32, with and without checkpoints)
    /// and report the terminal error against the target and alpha0.
    Replay(ReplayArgs),
    /// Print the local connection A(alpha) and its derivatives as JSON (rows x, y, theta;
    /// columns alpha1, alpha2).
    Connection(ConnectionArgs),
}

/// Largest `--starts` (each start is a full direct solve and Newton run).
pub const MAX_STARTS: usize = 100;
/// Largest `--segments` (the multiple-shooting Jacobian is dense: `(5 + 7(M − 1))²` numbers).
pub const MAX_SEGMENTS: u32 = 200;
/// Largest horizon `solve` accepts, in steps (its memory grows by about 0.3 kB per step and
/// start); `replay` accepts up to [`crate::problem::MAX_STEPS`].
pub const MAX_SOLVE_STEPS: u32 = 1_000_000;

// Number flags take values as typed, negative ones included (`--alpha -0.5,0.3`), and list
// their defaults as they can be typed back (`0.1,0.1,0`).

/// Swimmer parameters shared by the subcommands.
#[derive(Debug, Args)]
pub struct ModelArgs {
    /// Link lengths L0 (middle), L1 (front), L2 (rear), in metres.
    #[arg(
        long,
        value_delimiter = ',',
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
    /// Target position g_bar = X,Y,THETA (metres, metres, radians), reached from the origin.
    #[arg(
        long,
        value_delimiter = ',',
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
        default_value = "0,0",
        allow_hyphen_values = true
    )]
    pub alpha0: Vec<f64>,
    /// Swimmer parameters.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Number of starts (shape loops) tried in parallel (1 to 100).
    #[arg(long, default_value_t = 8)]
    pub starts: usize,
    /// Seed for the start generator (0: the built-in starts first, then random ones).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Admissibility limit on |alpha_i| along the path, radians (links overlap at pi).
    #[arg(long, default_value_t = core::f64::consts::PI, allow_hyphen_values = true)]
    pub alpha_max: f64,
    /// Costate checkpoint spacing M in steps (0: none).
    #[arg(long, default_value_t = 100)]
    pub checkpoint_every: u32,
    /// Multiple-shooting segments (1 to 200).
    #[arg(long, default_value_t = 20)]
    pub segments: u32,
    /// Skip the SVG figures.
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
pub struct ReplayArgs {
    /// The costate file written by `solve` (DIR/costate.json).
    #[arg(long)]
    pub costate: PathBuf,
    /// Replay only in this precision (default: the standard set f64, f32 with and without
    /// checkpoints).
    #[arg(long, value_enum)]
    pub precision: Option<Precision>,
    /// With --precision: ignore the file's costate checkpoints.
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

/// `connection` flags.
#[derive(Debug, Args)]
pub struct ConnectionArgs {
    /// Shape A1,A2 in radians (each |A_i| < pi).
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        required = true
    )]
    pub alpha: Vec<f64>,
    /// Swimmer parameters.
    #[command(flatten)]
    pub model: ModelArgs,
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

/// Runs a parsed command; the output to print on stdout on success.
pub fn run(cli: Cli) -> Result<String, Failure> {
    match cli.command {
        Command::Solve(a) => run_solve(a),
        Command::Replay(a) => run_replay(a),
        Command::Connection(a) => run_connection(a),
    }
}

fn run_solve(a: SolveArgs) -> Result<String, Failure> {
    let spec = Spec {
        target: arr("target", &a.target)?,
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
    if !(1..=MAX_STARTS).contains(&a.starts) {
        return Err(fail(
            2,
            format!("--starts must be 1 to {MAX_STARTS} (got {})", a.starts),
        ));
    }
    if !(1..=MAX_SEGMENTS).contains(&a.segments) {
        return Err(fail(
            2,
            format!(
                "--segments must be 1 to {MAX_SEGMENTS} (got {})",
                a.segments
            ),
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
    let out = output::OutputDir::prepare(&a.out, "solve", a.force).map_err(output_failure(true))?;
    let options = SolveOptions {
        starts: a.starts,
        seed: a.seed,
        segments: a.segments,
        ..SolveOptions::default()
    };
    let bar = std::io::stderr().is_terminal().then(|| {
        let b = indicatif::ProgressBar::new(a.starts as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "solving {bar:30} {pos}/{len} starts ({elapsed})",
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
    let result = solve(&problem, &options, &tick);
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let solution = result.map_err(|e| fail(3, e))?;
    let seconds = t0.elapsed().as_secs_f64();
    let best = &solution.extremals[solution.best];
    let file = output::costate_file(&problem, best, a.checkpoint_every);
    let extremals: Vec<_> = solution
        .extremals
        .iter()
        .map(|x| {
            json!({
                "cost": x.cost, "residual": x.residual, "terminal_residual": x.terminal_residual,
                "single_shooting_residual": x.single_shooting_residual,
                "max_abs_alpha": x.max_abs_alpha, "admissible": x.admissible,
                "kkt_residual": x.kkt_residual, "newton_iterations": x.newton_iterations,
                "start": x.start, "mu": [x.z[0], x.z[1], x.z[2]], "xi0": [x.z[3], x.z[4]],
            })
        })
        .collect();
    let report = json!({
        "cost": best.cost,
        "residual": best.residual,
        "terminal_residual": best.terminal_residual,
        "single_shooting_residual": best.single_shooting_residual,
        "kkt_residual": best.kkt_residual,
        "newton_iterations": best.newton_iterations,
        "max_abs_alpha": best.max_abs_alpha,
        "admissible": best.admissible,
        "solve_seconds": seconds,
        "starts": solution.starts,
        "segments": a.segments,
        "mu": file.mu, "xi0": file.xi0,
        "problem": {"target": file.target, "horizon": problem.horizon(), "step": problem.h,
                    "steps": problem.steps, "alpha0": file.alpha0, "links": file.model.links,
                    "drag": file.model.drag, "ratio": file.model.ratio, "alpha_max": problem.alpha_max},
        "extremals": extremals,
        // Terminal errors of the stored costate replayed through the core, as the firmware
        // flies it (f32 with checkpoints) beside f64.
        "replays": replay::standard_replays(&file),
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
        for (name, svg) in plots::figures(&problem, &best.trajectory)
            .map_err(|e| fail(1, format!("plotting: {e}")))?
        {
            files.push((name, svg.into_bytes()));
        }
    }
    out.commit(&files).map_err(output_failure(false))?;
    Ok(report_text)
}

/// The `format` tag of the `replay` report, by which `replay --out` recognises its own.
const REPLAY_REPORT: &str = "purcell-replay";

/// Whether `bytes` are a `replay` report.
fn is_replay_report(bytes: &[u8]) -> bool {
    serde_json::from_slice::<serde_json::Value>(bytes)
        .is_ok_and(|v| v.get("format").and_then(|f| f.as_str()) == Some(REPLAY_REPORT))
}

fn run_replay(a: ReplayArgs) -> Result<String, Failure> {
    let text = std::fs::read_to_string(&a.costate)
        .map_err(|e| fail(2, format!("reading {}: {e}", a.costate.display())))?;
    let file =
        CostateFile::parse(&text).map_err(|e| fail(2, format!("{}: {e}", a.costate.display())))?;
    let refused = |e: &dyn std::fmt::Display| fail(2, format!("{}: {e}", a.costate.display()));
    file.problem().map_err(|e| refused(&e))?;
    if !matches!(a.precision, Some(Precision::F64)) {
        file.check_precision::<f32>("f32")
            .map_err(|e| refused(&e))?;
    }
    let out = match &a.out {
        Some(path) => Some(
            output::OutputFile::prepare(path, is_replay_report, a.force, &[&a.costate])
                .map_err(output_failure(true))?,
        ),
        None => None,
    };
    let results = match a.precision {
        None => replay::standard_replays(&file),
        Some(Precision::F64) => vec![replay::replay::<f64>(&file, "f64", !a.no_checkpoints)],
        Some(Precision::F32) => vec![replay::replay::<f32>(&file, "f32", !a.no_checkpoints)],
    };
    let report = json!({
        "format": REPLAY_REPORT, "version": 1,
        "target": file.target, "alpha0": file.alpha0, "replays": results,
    });
    let text = serde_json::to_string_pretty(&report).map_err(|e| fail(1, e))? + "\n";
    if let Some(out) = out {
        out.commit(text.as_bytes()).map_err(output_failure(false))?;
    }
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
                    file.steps,
                    (f64::from(k) * file.h * 1e9).round() / 1e9
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
