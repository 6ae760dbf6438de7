//! `replay`: a stored gait (a costate file or a binary gait file) through the core, as
//! firmware flies it; and the checks every route to a replay makes of a stored gait.

use super::args::{Failure, GaitInput, fail, output_failure};
use crate::budget::Work;
use crate::{output, replay};
use clap::{Args, ValueEnum};
use purcell_core::Gait;
use serde_json::json;
use std::path::{Path, PathBuf};

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
    /// The gait to replay.
    #[command(flatten)]
    pub input: GaitInput,
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
    #[arg(short, long)]
    pub out: Option<PathBuf>,
    /// Also write the per-step path of one replay to this CSV file: trajectory.csv's
    /// columns (k, t_s, shape, controls, position, costate, arcs), numbers as replayed (f32
    /// or f64), of the replay --precision selects (default f64), with its checkpoints
    /// unless --no-checkpoints; rows up to the failing step if it fails. Written
    /// atomically; an existing file is replaced only with --force, an input never.
    #[arg(long, value_name = "CSV")]
    pub trace: Option<PathBuf>,
    /// Replace --out or --trace even if they hold something else (never an input file).
    #[arg(long)]
    pub force: bool,
}

/// What every route to a replay checks in a stored gait of `path` (`replay`, `export`,
/// `robustness`), besides the core's own validation, before any work: the step and memory
/// budget of `work` ([`super::args::budget`]) and [`replay::check_stored`]; exit 2.
pub(super) fn check_stored(
    path: &Path,
    gait: &Gait<'_>,
    f32: bool,
    work: Work,
    quiet: bool,
) -> Result<(), Failure> {
    super::args::budget(path, gait.params().steps, work, quiet)?;
    replay::check_stored(gait, f32).map_err(|e| fail(2, format!("{}: {e}", path.display())))
}

/// The `format` tag of the `replay` report.
const REPLAY_REPORT: &str = "purcell-replay";

/// `replay`: reads and checks the gait, prepares `--out`, flies it, writes the report; the
/// text report as printed (exit 3 with it when a replay fails).
pub(super) fn run_replay(a: ReplayArgs, quiet: bool) -> Result<String, Failure> {
    let (path, bytes) = a.input.gait_bytes()?;
    let gait = Gait::from_bytes(&bytes).map_err(|e| fail(2, format!("{}: {e}", path.display())))?;
    let work = if a.trace.is_some() {
        Work::Path
    } else {
        Work::Fly
    };
    let f32 = !matches!(a.precision, Some(Precision::F64));
    check_stored(path, &gait, f32, work, quiet)?;
    let prepare = |out: &Option<PathBuf>, command| {
        out.as_deref()
            .map(|p| output::OutputFile::prepare(output::Claim::new(p, command, a.force, &[path])))
            .transpose()
            .map_err(output_failure(true))
    };
    let out = prepare(&a.out, "replay")?;
    let trace = prepare(&a.trace, "replay --trace")?;
    // The same file by two names (`r.json`, `x/../r.json`): refused before the work.
    if let (Some(o), Some(t)) = (&out, &trace)
        && o.key() == t.key()
    {
        return Err(fail(2, "--out and --trace name the same file"));
    }
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
                             "alpha0": p.alpha0, "alpha_end": p.end_shape(),
                             "replays": results });
        let json = serde_json::to_string_pretty(&report).map_err(|e| fail(1, e))? + "\n";
        out.commit(json.as_bytes()).map_err(output_failure(false))?;
    }
    if let Some(trace) = trace {
        let csv = match a.precision {
            Some(Precision::F32) => replay::trace::<f32>(&gait, checkpoints),
            _ => replay::trace::<f64>(&gait, checkpoints),
        };
        trace
            .commit(csv.as_bytes())
            .map_err(output_failure(false))?;
    }
    let text = replay::text(&gait, &results);
    let failed: Vec<String> = results
        .iter()
        .filter_map(|r| r.failure_message(&gait))
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
