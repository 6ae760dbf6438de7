//! The `purcell-sim` command line (clap), one module per subcommand: [`solve`] (the optimal
//! gait of one target), [`replay`] (a gait through the core, as firmware flies it),
//! [`robustness`] (a gait through a mismatched plant, open and closed loop), [`export`] (the
//! binary gait file, or its bytes as C source), [`connection`] (the local connection as JSON),
//! [`sweep`] (a lattice of targets by continuation), [`field`] (the connection's curvature)
//! and [`docs`] (shell completions and the manual page); [`args`] holds the flags, checks and
//! errors they share, `summary` what `solve` and `sweep` print.

pub mod args;
pub mod connection;
pub mod docs;
pub mod export;
pub mod field;
pub mod replay;
pub mod robustness;
pub mod solve;
mod summary;
pub mod sweep;
pub mod units;

pub use args::{EXIT_CODES, Failure};

use clap::{Parser, Subcommand};

/// `--version`: the package's version and, when built from a git checkout, its commit
/// (`build.rs`).
pub const VERSION: &str = env!("PURCELL_SIM_VERSION");

/// Exact optimal control of the planar three-link Purcell swimmer: solve offline, replay
/// through the embedded core, inspect the model.
#[derive(Debug, Parser)]
#[command(name = "purcell-sim", version = VERSION, after_help = args::EXIT_CODES)]
pub struct Cli {
    /// Print nothing but errors: no report or summary on stdout, no warning or progress bar
    /// on stderr.
    #[arg(short, long, global = true)]
    pub quiet: bool,
    /// Worker threads of the search and the figures (default: one per core). The results do
    /// not depend on it.
    #[arg(short = 'j', long, global = true, value_name = "N",
          value_parser = clap::value_parser!(u16).range(1..))]
    pub threads: Option<u16>,
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Solve the discrete optimal-control problem and write DIR/{trajectory.csv,
    /// costate.json, report.json, field.csv, *.svg, *.png}; print a summary (--json: the
    /// report).
    #[command(after_help = args::EXIT_CODES)]
    Solve(solve::SolveArgs),
    /// Replay a gait (binary, or a costate file) through the core as firmware does (f64 and
    /// f32, with and without checkpoints): print each trajectory's digest, final state bits and
    /// terminal error against the target and alpha0.
    #[command(after_help = args::EXIT_CODES)]
    Replay(replay::ReplayArgs),
    /// Fly a gait through a plant whose drag ratio, drag coefficient and link lengths differ
    /// from the model's, with noisy measurements: print the terminal errors of the open-loop
    /// flight (the law's controls) and of the closed-loop one (the tracking law).
    #[command(after_help = args::EXIT_CODES)]
    Robustness(robustness::RobustnessArgs),
    /// Write the binary gait file of a costate file, for `include_bytes!` in firmware, or
    /// (--format c) its bytes as a C array for the C API's purcell_flight_open.
    #[command(after_help = args::EXIT_CODES)]
    Export(export::ExportArgs),
    /// Print the local connection A(alpha) and its derivatives as JSON (rows x, y, theta;
    /// columns alpha1, alpha2).
    #[command(after_help = args::EXIT_CODES)]
    Connection(connection::ConnectionArgs),
    /// Solve a lattice of targets by continuation from neighbours and write DIR/sweep.csv
    /// (target, cost, residual, largest |alpha_i|, local minimum, status) and a map of the
    /// cost over the target plane; print a summary (--json: the report).
    ///
    /// sweep.csv's status: "ok" (the certificates vouch for the extremal); else the first
    /// that does not: "not admissible", "not a strict local minimum", "terminal residual
    /// above 1e-10", "KKT residual above 1e-8", "law residual above 1e-9"; or, for a target
    /// without an extremal (its numbers empty), why: "no start reached the target: ...", "N
    /// extremal(s) of the coarse search, none carried to the problem's grid: ...", "N
    /// extremal(s) found, none admissible: ...".
    #[command(after_help = args::EXIT_CODES)]
    Sweep(sweep::SweepArgs),
    /// Draw the curvature of the connection over the shape plane (rows x, y, theta), with a
    /// gait on top, and write DIR/{field.svg, field.png, field.csv}.
    #[command(after_help = args::EXIT_CODES)]
    Field(field::FieldArgs),
    /// Print the shell completion script for SHELL (e.g. `purcell-sim completions bash >
    /// ~/.local/share/bash-completion/completions/purcell-sim`).
    #[command(after_help = args::EXIT_CODES)]
    Completions(docs::CompletionsArgs),
    /// Print the manual page (roff) of purcell-sim or of one of its commands (e.g.
    /// `purcell-sim man solve | man -l -`).
    #[command(after_help = args::EXIT_CODES)]
    Man(docs::ManArgs),
}

/// Starts the worker threads of the search and the figures (rayon's global pool, `threads`
/// of them or one per core) once per process: a system that refuses threads is exit 1, not
/// a panic in the middle of the work.
fn start_threads(threads: Option<u16>) -> Result<(), Failure> {
    static STARTED: std::sync::OnceLock<Result<(), String>> = std::sync::OnceLock::new();
    STARTED
        .get_or_init(|| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads.map_or(0, usize::from))
                .build_global()
                .map_err(|e| e.to_string())
        })
        .clone()
        .map_err(|e| args::fail(1, format!("cannot start worker threads: {e}")))
}

/// Runs a parsed command; the output to print on stdout on success (nothing with `-q`, nor
/// in a failure's).
pub fn run(cli: Cli) -> Result<String, Failure> {
    if matches!(
        cli.command,
        Command::Solve(_) | Command::Sweep(_) | Command::Field(_)
    ) {
        start_threads(cli.threads)?;
    }
    let quiet = cli.quiet;
    let result = match cli.command {
        Command::Solve(a) => solve::run_solve(a, quiet),
        Command::Replay(a) => replay::run_replay(a, quiet),
        Command::Robustness(a) => robustness::run_robustness(a, quiet),
        Command::Export(a) => export::run_export(a, quiet),
        Command::Connection(a) => connection::run_connection(a),
        Command::Sweep(a) => sweep::run_sweep(a, quiet),
        Command::Field(a) => field::run_field(a, quiet),
        Command::Completions(a) => Ok(docs::completions(&a)),
        Command::Man(a) => docs::man(&a),
    };
    match result {
        Ok(_) if quiet => Ok(String::new()),
        Err(f) if quiet => Err(Failure {
            stdout: String::new(),
            ..f
        }),
        r => r,
    }
}
