//! `export`: the binary gait file of a costate file (or of a gait file), for `include_bytes!`
//! in firmware, or the same bytes as C source (`--format c`) for `purcell_flight_open`.

use super::args::{Failure, GaitInput, fail, output_failure};
use super::replay::check_stored;
use crate::output::{self, OutputFile, c_array};
use clap::{Args, ValueEnum};
use purcell_core::{Gait, gait};
use purcell_solver::tracking::{self, Design, Feedforward, PlanError, joint_bound};
use std::path::{Path, PathBuf};

/// What `export` writes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// The binary gait file (docs/GAIT.md).
    #[default]
    Gait,
    /// The gait file's bytes as a C array: --out NAME.c and NAME.h beside it.
    C,
}

/// `export` flags.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The gait to export (a gait file: with --format c, its bytes as C source).
    #[command(flatten)]
    pub input: GaitInput,
    /// The file to write (atomically; an existing file is replaced only if it is one `export`
    /// wrote in that format, never an input). With --format c, the `.c` file; the header
    /// goes beside it with the extension `.h`, and the array is named after the file stem.
    #[arg(short, long)]
    pub out: PathBuf,
    /// What to write.
    #[arg(long, value_enum, default_value_t)]
    pub format: Format,
    /// Replace --out (and its .h) even if it holds something else (never an input).
    #[arg(long)]
    pub force: bool,
    /// Add the gait's tracking table (a version-3 file, docs/GAIT.md): the gains of the
    /// closed loop, computed with the design of `robustness`'s defaults, in f32.
    #[arg(long)]
    pub tracking: bool,
    /// With --tracking: the table's gain on the ratio error from the plant's neighbouring
    /// extremal, as `robustness --plan` (the LQR's where the gait has none: said in the line
    /// printed).
    #[arg(long, requires = "tracking")]
    pub plan: bool,
}

/// Whether `bytes` are a gait file (its magic), by which `export --out` recognises its own.
fn is_gait_file(bytes: &[u8]) -> bool {
    bytes.starts_with(&purcell_core::gait::MAGIC)
}

/// The files to write for `bytes`: `(path, contents, recogniser)`.
type Outputs = Vec<(PathBuf, Vec<u8>, fn(&[u8]) -> bool)>;

/// The `.c` and `.h` files of `--format c` (exit 2 unless `out` ends in `.c`).
fn c_outputs(out: &Path, about: &str, bytes: &[u8]) -> Result<Outputs, Failure> {
    let stem = match (out.extension(), out.file_stem()) {
        (Some(e), Some(stem)) if e == "c" => stem.to_string_lossy(),
        _ => {
            return Err(fail(
                2,
                format!(
                    "{}: --format c writes NAME.c (and NAME.h beside it): --out must end in .c",
                    out.display()
                ),
            ));
        }
    };
    let header = out.with_extension("h");
    let header_name = header.file_name().unwrap_or_default().to_string_lossy();
    let (c, h) = c_array::source(&c_array::identifier(&stem), &header_name, about, bytes);
    Ok(vec![
        (header, h.into_bytes(), c_array::is_ours),
        (out.to_path_buf(), c.into_bytes(), c_array::is_ours),
    ])
}

/// `gait`'s file with its tracking table ([`Design`]'s defaults, the joints' bound of its
/// `α_max`, the neighbouring extremal's gain if `plan`; [`tracking::table_of`]) and where its
/// gain on the ratio error came from.
fn with_tracking(
    gait: &Gait<'_>,
    plan: bool,
) -> Result<(Vec<u8>, Feedforward), purcell_core::Error> {
    let p = gait.params();
    let design = Design {
        bound: joint_bound(p.alpha_max),
        plan,
        ..Design::default()
    };
    let (t, source) = tracking::table_of(gait, &tracking::nominal(gait)?, &design)?;
    let records = t.to_f32();
    let (checkpoints, arcs): (Vec<_>, Vec<_>) =
        (gait.checkpoints().collect(), gait.arcs().collect());
    let mut out =
        vec![0; gait::encoded_len_with_tracking(checkpoints.len(), arcs.len(), records.len())];
    gait::encode_with_tracking(p, &checkpoints, &arcs, &records, &mut out)?;
    Ok((out, source))
}

/// `export`: reads and checks the costate file (or gait file), writes its gait; a line naming
/// what it wrote.
pub(super) fn run_export(a: ExportArgs) -> Result<String, Failure> {
    let (input, bytes) = a.input.gait_bytes()?;
    let refused = |e: &dyn std::fmt::Display| fail(2, format!("{}: {e}", input.display()));
    let mut bytes = bytes;
    let mut gain = None;
    if a.tracking {
        let (tracked, source) =
            with_tracking(&Gait::from_bytes(&bytes).map_err(|e| refused(&e))?, a.plan)
                .map_err(|e| refused(&format!("tracking table: {e}")))?;
        bytes = tracked;
        gain = Some(source);
    }
    let gait = Gait::from_bytes(&bytes).map_err(|e| refused(&e))?;
    // The gait is for the f32 firmware.
    check_stored(input, &gait, true)?;
    let mut about = format!(
        "{} bytes, crc={:#010x}, steps={}, checkpoints={}, arcs={}",
        bytes.len(),
        gait.crc(),
        gait.params().steps,
        gait.checkpoint_count(),
        gait.arc_count()
    );
    if let Some(t) = gait.tracking() {
        about += &format!(", tracking records={}", t.len());
    }
    match gain {
        Some(Feedforward::Extremal) => about += ", gain on the ratio error: extremal",
        Some(Feedforward::Lqr(PlanError::Off)) | None => {}
        Some(Feedforward::Lqr(why)) => {
            about += &format!(", gain on the ratio error: LQR (no plan: {why})");
        }
    }
    let outputs = match a.format {
        Format::Gait => vec![(a.out.clone(), bytes, is_gait_file as fn(&[u8]) -> bool)],
        Format::C => c_outputs(&a.out, &about, &bytes)?,
    };
    // Every output checked and staged before any is written.
    let staged = outputs
        .into_iter()
        .map(|(path, contents, ours)| {
            OutputFile::prepare(&path, ours, a.force, &[input]).map(|f| (f, contents))
        })
        .collect::<Result<Vec<_>, output::OutputError>>()
        .map_err(output_failure(true))?;
    for (file, contents) in staged {
        file.commit(&contents).map_err(output_failure(false))?;
    }
    Ok(format!("gait: wrote {} ({about})\n", a.out.display()))
}
