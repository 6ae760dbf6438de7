//! The `purcell-sim` command line (clap), one module per subcommand: [`solve`] (the optimal
//! gait of one target), [`replay`] (a gait through the core, as firmware flies it),
//! [`export`] (the binary gait file), [`connection`] (the local connection as JSON),
//! [`sweep`] (a lattice of targets by continuation) and [`field`] (the connection's
//! curvature); [`args`] holds the flags, checks and errors they share.

pub mod args;
pub mod connection;
pub mod export;
pub mod field;
pub mod replay;
pub mod solve;
pub mod sweep;

pub use args::{Failure, MAX_SOLVE_STEPS, MAX_STARTS};
pub use solve::MAX_CHECKPOINTS;
pub use sweep::MAX_SWEEP_TARGETS;

use clap::{Parser, Subcommand};

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
    Solve(solve::SolveArgs),
    /// Replay a gait (binary, or a costate file) through the core as firmware does (f64 and
    /// f32, with and without checkpoints): print each trajectory's digest, final state bits and
    /// terminal error against the target and alpha0.
    Replay(replay::ReplayArgs),
    /// Write the binary gait file of a costate file, for `include_bytes!` in firmware.
    Export(export::ExportArgs),
    /// Print the local connection A(alpha) and its derivatives as JSON (rows x, y, theta;
    /// columns alpha1, alpha2).
    Connection(connection::ConnectionArgs),
    /// Solve a lattice of targets by continuation from neighbours and write DIR/sweep.csv
    /// (target, cost, residual, largest |alpha_i|, local minimum) and a map of the cost over
    /// the target plane.
    Sweep(sweep::SweepArgs),
    /// Draw the curvature of the connection over the shape plane (rows x, y, theta), with a
    /// gait on top, and write DIR/{field.svg, field.png, field.csv}.
    Field(field::FieldArgs),
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
        .map_err(|e| args::fail(1, format!("cannot start worker threads: {e}")))
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
        Command::Solve(a) => solve::run_solve(a),
        Command::Replay(a) => replay::run_replay(a),
        Command::Export(a) => export::run_export(a),
        Command::Connection(a) => connection::run_connection(a),
        Command::Sweep(a) => sweep::run_sweep(a),
        Command::Field(a) => field::run_field(a),
    }
}
