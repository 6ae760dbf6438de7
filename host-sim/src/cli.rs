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
    /// costate.json, report.json, field.csv, *.svg, *.png}.
    Solve(SolveArgs),
    /// Replay a costate file through the core (f64 and f32, with and without checkpoints)
    /// and report the terminal error against the target and alpha0.
    Replay(ReplayArgs),
    /// Print the local connection A(alpha) and its derivatives as JSON (rows x, y, theta;
    /// columns alpha1, alpha2).
    Connection(ConnectionArgs),
    /// Draw the curvature of the connection over the shape plane (rows x, y, theta), with a
    /// gait on top, and write DIR/{field.svg, field.png, field.csv}.
    Field(FieldArgs),
}

/// Swimmer parameters shared by the subcommands.
#[derive(Debug, Args)]
pub struct ModelArgs {
    /// Link lengths L0 (middle), L1 (front), L2 (rear), in metres.
    #[arg(long, value_delimiter = ',', default_values_t = [1.0, 1.0, 1.0], allow_negative_numbers = true)]
    pub links: Vec<f64>,
    /// Drag coefficient k (force per unit length per unit speed; scales forces only).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub drag: f64,
    /// Drag ratio r: normal over tangential drag (2 for slender bodies).
    #[arg(long, default_value_t = 2.0, allow_negative_numbers = true)]
    pub ratio: f64,
}

/// `solve` flags.
#[derive(Debug, Args)]
pub struct SolveArgs {
    /// Target position g_bar = X,Y,THETA (metres, metres, radians), reached from the origin.
    #[arg(long, value_delimiter = ',', default_values_t = [0.1, 0.1, 0.0], allow_negative_numbers = true)]
    pub target: Vec<f64>,
    /// Horizon T in seconds; must be a whole number of steps.
    #[arg(long, default_value_t = 100.0, allow_negative_numbers = true)]
    pub horizon: f64,
    /// Time step h in seconds.
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
    pub step: f64,
    /// Start and end shape alpha_bar = A1,A2 in radians (each |A_i| < pi).
    #[arg(long, value_delimiter = ',', default_values_t = [0.0, 0.0], allow_negative_numbers = true)]
    pub alpha0: Vec<f64>,
    /// Swimmer parameters.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Number of starts (shape loops) tried in parallel.
    #[arg(long, default_value_t = 8)]
    pub starts: usize,
    /// Seed for the start generator (0: the built-in starts first, then random ones).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Admissibility limit on |alpha_i| along the path, radians (links overlap at pi).
    #[arg(long, default_value_t = core::f64::consts::PI, allow_negative_numbers = true)]
    pub alpha_max: f64,
    /// Costate checkpoint spacing M in steps (0: none).
    #[arg(long, default_value_t = 100)]
    pub checkpoint_every: u32,
    /// Multiple-shooting segments.
    #[arg(long, default_value_t = 20)]
    pub segments: u32,
    /// Skip the figures (SVG and PNG) and field.csv.
    #[arg(long)]
    pub no_plots: bool,
    /// Angles in the figures in degrees and deg/s (the CSV files stay in radians).
    #[arg(long)]
    pub degrees: bool,
    /// Output directory (created or replaced atomically).
    #[arg(long)]
    pub out: PathBuf,
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
    /// Also write the JSON report to this file (atomically).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// `connection` flags.
#[derive(Debug, Args)]
pub struct ConnectionArgs {
    /// Shape A1,A2 in radians (each |A_i| < pi).
    #[arg(
        long,
        value_delimiter = ',',
        allow_negative_numbers = true,
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
    /// Output directory (created or replaced atomically).
    #[arg(long)]
    pub out: PathBuf,
}

/// A failure of the command, with its exit code.
#[derive(Debug)]
pub struct Failure {
    /// Message for stderr.
    pub message: String,
    /// Exit code: 2 bad input, 3 not solved, 1 other.
    pub code: u8,
}

fn fail(code: u8, message: impl ToString) -> Failure {
    Failure {
        message: message.to_string(),
        code,
    }
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
        Command::Field(a) => run_field(a),
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
    if a.starts == 0 || a.segments == 0 {
        return Err(fail(2, "--starts and --segments must be at least 1"));
    }
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
        let mu = nalgebra::Vector3::new(best.z[0], best.z[1], best.z[2]);
        let options = plots::Options { degrees: a.degrees };
        files.extend(
            plots::figures(&problem, &best.trajectory, &mu, &file, &options)
                .map_err(|e| fail(1, format!("plotting: {e}")))?,
        );
    }
    output::write_dir_atomically(&a.out, &files)
        .map_err(|e| fail(1, format!("writing {}: {e}", a.out.display())))?;
    Ok(report_text)
}

fn run_field(a: FieldArgs) -> Result<String, Failure> {
    let (problem, states) = match &a.gait {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .map_err(|e| fail(2, format!("reading {}: {e}", path.display())))?;
            let file = CostateFile::parse(&text)
                .map_err(|e| fail(2, format!("{}: {e}", path.display())))?;
            let problem = file
                .problem()
                .map_err(|e| fail(2, format!("{}: {e}", path.display())))?;
            let states = replay::gait_states(&file, 10_000).map_err(|e| {
                fail(
                    2,
                    format!("{}: the gait does not replay: {e}", path.display()),
                )
            })?;
            (problem, Some(states))
        }
        None => {
            let spec = Spec {
                links: arr("links", &a.model.links)?,
                drag: a.model.drag,
                ratio: a.model.ratio,
                ..Spec::default()
            };
            (Problem::new(&spec).map_err(|e| fail(2, e))?, None)
        }
    };
    let components = match a.component {
        None => plots::field::Component::ALL.to_vec(),
        Some(FieldComponent::X) => vec![plots::field::Component::X],
        Some(FieldComponent::Y) => vec![plots::field::Component::Y],
        Some(FieldComponent::Theta) => vec![plots::field::Component::Theta],
    };
    let options = plots::Options { degrees: a.degrees };
    let gait = states.as_deref().map(|s| (&problem, s));
    let files = plots::field_files(&problem.swimmer, gait, &components, &options)
        .map_err(|e| fail(1, format!("plotting: {e}")))?;
    output::write_dir_atomically(&a.out, &files)
        .map_err(|e| fail(1, format!("writing {}: {e}", a.out.display())))?;
    let names: Vec<&str> = files.iter().map(|f| f.0.as_str()).collect();
    Ok(
        serde_json::to_string_pretty(&json!({ "out": a.out, "files": names }))
            .map_err(|e| fail(1, e))?
            + "\n",
    )
}

fn run_replay(a: ReplayArgs) -> Result<String, Failure> {
    let text = std::fs::read_to_string(&a.costate)
        .map_err(|e| fail(2, format!("reading {}: {e}", a.costate.display())))?;
    let file =
        CostateFile::parse(&text).map_err(|e| fail(2, format!("{}: {e}", a.costate.display())))?;
    file.problem()
        .map_err(|e| fail(2, format!("{}: {e}", a.costate.display())))?;
    let results = match a.precision {
        None => replay::standard_replays(&file),
        Some(Precision::F64) => vec![replay::replay::<f64>(&file, "f64", !a.no_checkpoints)],
        Some(Precision::F32) => vec![replay::replay::<f32>(&file, "f32", !a.no_checkpoints)],
    };
    let out = serde_json::to_string_pretty(
        &json!({ "target": file.target, "alpha0": file.alpha0, "replays": results }),
    )
    .map_err(|e| fail(1, e))?
        + "\n";
    if let Some(path) = &a.out {
        output::write_file_atomically(path, out.as_bytes())
            .map_err(|e| fail(1, format!("writing {}: {e}", path.display())))?;
    }
    Ok(out)
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
