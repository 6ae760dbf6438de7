//! `export`: the binary gait file of a costate file (or of a gait file), for `include_bytes!`
//! in firmware, or the same bytes as C source (`--format c`) for `purcell_flight_open`.

use super::args::{Failure, GaitInput, fail, output_failure};
use super::replay::check_stored;
use crate::budget::Work;
use crate::input::MAX_INPUT_BYTES;
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
    /// The file to write (atomically; an existing file is replaced only if its record
    /// `.NAME.purcell-sim` beside it says `export` wrote exactly that, never an input). With
    /// --format c, the `.c` file; the header goes beside it with the extension `.h`, and the
    /// array is named after the file stem (prefixed with gait_ where that would clash with
    /// C).
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

/// The paths `--format c` writes, the `.c` first (exit 2 unless `out` ends in `.c` and the
/// header's name can be `#include`d): renamed in this order, a new `.c` meets the old `.h`
/// only if the export is interrupted between the two, and then fails to compile
/// ([`c_array::source`]'s key), so an interrupted export never leaves a pair that builds.
fn c_paths(out: &Path) -> Result<[PathBuf; 2], Failure> {
    if out.extension().is_none_or(|e| e != "c") || out.file_stem().is_none() {
        return Err(fail(
            2,
            format!(
                "{}: --format c writes NAME.c (and NAME.h beside it): --out must end in .c",
                out.display()
            ),
        ));
    }
    let header = out.with_extension("h");
    if let Some(why) = c_array::unincludable(header.file_name().unwrap_or_default()) {
        return Err(fail(2, format!("{}: {why}", out.display())));
    }
    Ok([out.to_path_buf(), header])
}

/// The `.c` and `.h` sources of the gait file `bytes` for the paths [`c_paths`] gave.
fn c_sources([c, h]: &[PathBuf; 2], about: &str, bytes: &[u8]) -> [Vec<u8>; 2] {
    let stem = c.file_stem().unwrap_or_default().to_string_lossy();
    let header = h.file_name().unwrap_or_default().to_string_lossy();
    let (c, h) = c_array::source(&c_array::identifier(&stem), &header, about, bytes);
    [c.into_bytes(), h.into_bytes()]
}

/// The length of `gait`'s file with a tracking table of `design` ([`tracking::table_of`]'s
/// records: one every `every` steps up to the tail, then one a step), known before the work.
fn tracked_len(gait: &Gait<'_>, design: &Design) -> usize {
    let n = gait.params().steps;
    let d = design.every.max(1);
    let tail_from = n.saturating_sub(design.tail) / d * d;
    let records = n.checked_sub(1).map_or(0, |last| {
        tracking::Table::index(d, tail_from, last as usize).0 + 1
    });
    gait::encoded_len_with_tracking(gait.checkpoint_count(), gait.arc_count(), records)
}

/// The design of `export --tracking`: [`Design`]'s defaults, the joints' bound of the gait's
/// `α_max`, the neighbouring extremal's gain if `plan`.
fn design(gait: &Gait<'_>, plan: bool) -> Design {
    Design {
        bound: joint_bound(gait.params().alpha_max),
        plan,
        ..Design::default()
    }
}

/// `gait`'s file with its tracking table of `design` ([`tracking::table_of`]) and where its
/// gain on the ratio error came from.
fn with_tracking(
    gait: &Gait<'_>,
    design: &Design,
) -> Result<(Vec<u8>, Feedforward), purcell_core::Error> {
    let (t, source) = tracking::table_of(gait, &tracking::nominal(gait)?, design)?;
    let records = t.to_f32();
    let (checkpoints, arcs): (Vec<_>, Vec<_>) =
        (gait.checkpoints().collect(), gait.arcs().collect());
    let mut out =
        vec![0; gait::encoded_len_with_tracking(checkpoints.len(), arcs.len(), records.len())];
    gait::encode_with_tracking(gait.params(), &checkpoints, &arcs, &records, &mut out)?;
    Ok((out, source))
}

/// `export`: reads and checks the costate file (or gait file), writes its gait; a line naming
/// what it wrote.
pub(super) fn run_export(a: ExportArgs, quiet: bool) -> Result<String, Failure> {
    let (input, bytes) = a.input.gait_bytes()?;
    let refused = |e: &dyn std::fmt::Display| fail(2, format!("{}: {e}", input.display()));
    let source = Gait::from_bytes(&bytes).map_err(|e| refused(&e))?;
    // The gait is for the f32 firmware; --tracking flies it and keeps per-step gains.
    let work = if a.tracking {
        Work::Tracking
    } else {
        Work::Read
    };
    check_stored(input, &source, true, work, quiet)?;
    let design = design(&source, a.plan);
    let len = if a.tracking {
        tracked_len(&source, &design)
    } else {
        bytes.len()
    };
    if len as u64 > MAX_INPUT_BYTES {
        return Err(fail(
            2,
            format!(
                "{}: the gait file would be {len} bytes, more than replay and the other readers \
                 take ({} MiB)",
                input.display(),
                MAX_INPUT_BYTES >> 20
            ),
        ));
    }
    let paths = match a.format {
        Format::Gait => vec![a.out.clone()],
        Format::C => c_paths(&a.out)?.to_vec(),
    };
    // Every output checked and staged before any work.
    let files = paths
        .iter()
        .map(|p| OutputFile::prepare(output::Claim::new(p, "export", a.force, &[input])))
        .collect::<Result<Vec<_>, output::OutputError>>()
        .map_err(output_failure(true))?;
    let mut gain = None;
    let bytes = if a.tracking {
        let (tracked, source) = with_tracking(&source, &design)
            .map_err(|e| refused(&format!("tracking table: {e}")))?;
        gain = Some(source);
        tracked
    } else {
        bytes
    };
    // The size checked before the work is the size written.
    debug_assert_eq!(bytes.len(), len);
    let gait = Gait::from_bytes(&bytes).map_err(|e| refused(&e))?;
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
    let contents = match a.format {
        Format::Gait => vec![bytes],
        Format::C => {
            c_sources(&[a.out.clone(), a.out.with_extension("h")], &about, &bytes).to_vec()
        }
    };
    let staged = files.into_iter().zip(contents).collect();
    OutputFile::commit_all(staged).map_err(output_failure(false))?;
    Ok(format!("gait: wrote {} ({about})\n", a.out.display()))
}
