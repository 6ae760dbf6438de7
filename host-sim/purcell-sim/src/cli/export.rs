//! `export`: the binary gait file of a costate file, for `include_bytes!` in firmware.

use super::args::{Failure, fail, output_failure, read_costate};
use super::replay::check_stored;
use crate::output;
use clap::Args;
use purcell_core::Gait;
use std::path::PathBuf;

/// `export` flags.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The costate file written by `solve` (DIR/costate.json).
    #[arg(long)]
    pub costate: PathBuf,
    /// The binary gait file to write (atomically; an existing file is replaced only if it is
    /// a gait file, never the costate file).
    #[arg(short, long)]
    pub out: PathBuf,
    /// Replace --out even if it holds something else (never the costate file).
    #[arg(long)]
    pub force: bool,
}

/// Whether `bytes` are a gait file (its magic), by which `export --out` recognises its own.
fn is_gait_file(bytes: &[u8]) -> bool {
    bytes.starts_with(&purcell_core::gait::MAGIC)
}

/// `export`: reads and checks the costate file, writes its gait; a line naming what it wrote.
pub(super) fn run_export(a: ExportArgs) -> Result<String, Failure> {
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
