//! Single output files: checked and staged before the work, renamed over their paths after it,
//! each with its record beside it ([`record_path`]) that makes it ours.
//!
//! A file is ours only if its record, `.NAME.purcell-sim` (a manifest of that one file, written
//! by the same subcommand), lists its length and hash: an edited, appended-to or foreign file is
//! refused (without `force`) whatever it starts with. A commit of several files
//! ([`OutputFile::commit_all`], the C source and header of `export --format c`) writes and
//! syncs every new file and record first, so a full disk or a refusal stops it before any
//! rename; then, for each file in the order given, the record is replaced by one that lists
//! the old and the new contents, then the file; last, each record by one that lists only the
//! new. Interrupted between any two renames, every file still matches its record (it is old
//! or new), so the next run replaces it without `force`; a signal waits for the renames to
//! end ([`super::staging::swap_guard`]). Whether the files agree with each other is the
//! caller's to make checkable (the C pair carries one key in both, checked at compile time).

use super::claim::Claim;
use super::classify::{Existing, classify_file};
use super::disk::{
    keep_permissions, remove_empty_dirs, rename_no_replace, split, sync_dir, write_synced,
};
use super::error::{OutputError, io_error};
use super::manifest::{Entry, Manifest};
use super::staging::{Staging, create_parents, swap_guard};
use std::ffi::{OsStr, OsString};
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// The record of an output file `parent/name`: `parent/.NAME.purcell-sim`, with `NAME` the
/// name, or for a name too long for that, its first 200 bytes and a hash of the whole.
pub(super) fn record_path(parent: &Path, name: &OsStr) -> PathBuf {
    const SUFFIX: &str = ".purcell-sim";
    let bytes = name.as_encoded_bytes();
    let mut record = OsString::from(".");
    if bytes.len() + 1 + SUFFIX.len() <= 255 {
        record.push(name);
    } else {
        let text = name.to_string_lossy();
        let mut cut = 200.min(text.len());
        while !text.is_char_boundary(cut) {
            cut -= 1;
        }
        record.push(format!(
            "{}-{:016x}",
            text.get(..cut).unwrap_or_default(),
            super::manifest::fnv1a64(bytes)
        ));
    }
    record.push(SUFFIX);
    parent.join(record)
}

/// An output file, checked and staged by [`OutputFile::prepare`], written by
/// [`OutputFile::commit`]; dropped uncommitted, it removes what it created.
#[derive(Debug)]
pub struct OutputFile {
    /// What the command asks.
    claim: Claim,
    /// The path resolved to `parent/name`.
    path: PathBuf,
    record: PathBuf,
    staging: Option<Staging>,
    created_parents: Vec<PathBuf>,
}

impl OutputFile {
    /// Checks that the claim's path may be written by its command: missing, or a regular
    /// file whose record says the command wrote exactly its contents (any regular file with
    /// `force`), and never one of its inputs (the same file by any name); then creates the
    /// staging file next to it, before any work.
    pub fn prepare(claim: Claim) -> Result<Self, OutputError> {
        let (parent, name) = split(&claim.path)?;
        let mut out = OutputFile {
            path: parent.join(&name),
            record: record_path(&parent, &name),
            claim,
            staging: None,
            created_parents: Vec::new(),
        };
        out.check()?;
        let shown = &out.claim.path;
        out.created_parents =
            create_parents(&parent).map_err(io_error(shown, "cannot create its directory"))?;
        out.staging =
            Some(Staging::create(&parent, false).map_err(io_error(shown, "cannot be created"))?);
        Ok(out)
    }

    /// The path, its directory resolved (after symbolic links, `.` and `..`): two outputs
    /// with the same key are the same file.
    pub fn key(&self) -> PathBuf {
        let parent = self.path.parent().unwrap_or(Path::new("."));
        let name = self.path.file_name().unwrap_or_default();
        fs::canonicalize(parent)
            .unwrap_or_else(|_| parent.to_path_buf())
            .join(name)
    }

    /// `Ok` (what is there) if the path may be written now.
    fn check(&self) -> Result<Existing, OutputError> {
        let path = &self.path;
        let existing = classify_file(path, &self.record, self.claim.command, &self.claim.inputs)
            .map_err(io_error(path, "cannot inspect"))?;
        match existing {
            Existing::Foreign {
                reason,
                force_overrides,
            } if !(self.claim.force && force_overrides) => Err(OutputError::Refused {
                path: path.clone(),
                reason,
                force_overrides,
            }),
            e => Ok(e),
        }
    }

    /// Writes `bytes` to the staging file and renames it over the path.
    pub fn commit(self, bytes: &[u8]) -> Result<(), OutputError> {
        Self::commit_all(vec![(self, bytes.to_vec())])
    }

    /// Writes every file (and its records) to staging, checks every path again, then renames
    /// them into place in the order given (the module's documentation says how).
    pub fn commit_all(files: Vec<(OutputFile, Vec<u8>)>) -> Result<(), OutputError> {
        struct Staged {
            file: OutputFile,
            existing: Existing,
            transition: Staging,
            last: Staging,
        }
        let mut staged = Vec::with_capacity(files.len());
        for (file, bytes) in files {
            let staging = file.staging.as_ref().map(|s| s.path().to_path_buf());
            let staging = staging.unwrap_or_default();
            write_synced(&staging, &bytes).map_err(io_error(&staging, "cannot write"))?;
            let existing = file.check()?;
            let name = file.path.file_name().unwrap_or_default().to_string_lossy();
            let new = Entry::of(&name, &bytes);
            let mut both = match &existing {
                Existing::Ours(Some(m)) => m.files.clone(),
                _ => Vec::new(),
            };
            both.push(new.clone());
            let parent = file.path.parent().unwrap_or(Path::new("."));
            let record = |entries: Vec<Entry>| {
                let s = Staging::create(parent, false)
                    .map_err(io_error(&file.path, "cannot be created"))?;
                write_synced(
                    s.path(),
                    &Manifest::new(file.claim.command, entries).to_bytes(),
                )
                .map_err(io_error(s.path(), "cannot write"))?;
                Ok::<_, OutputError>(s)
            };
            let transition = record(both)?;
            let last = record(vec![new])?;
            keep_permissions(&staging, &file.path);
            staged.push(Staged {
                file,
                existing,
                transition,
                last,
            });
        }
        let _swap = swap_guard();
        let mut renames = Renames(0);
        for s in &mut staged {
            let f = &mut s.file;
            renames.rename(s.transition.path(), &f.record, &f.path)?;
            let staging = f.staging.take();
            let from = staging.as_ref().map(|s| s.path().to_path_buf());
            let from = from.unwrap_or_default();
            let placed = match s.existing {
                Existing::Missing => match rename_no_replace(&from, &f.path) {
                    Err(e) if e.kind() == io::ErrorKind::Unsupported => fs::rename(&from, &f.path),
                    r => r,
                },
                _ => fs::rename(&from, &f.path),
            };
            placed.map_err(io_error(&f.path, "cannot write"))?;
            if let Some(s) = staging {
                s.done();
            }
            renames.step();
        }
        for s in staged {
            renames.rename(s.last.path(), &s.file.record, &s.file.path)?;
            s.transition.done();
            s.last.done();
            let mut file = s.file;
            file.created_parents.clear();
            if let Some(parent) = file.path.parent() {
                sync_dir(parent);
            }
        }
        Ok(())
    }
}

/// The renames of a commit, counted for the fault-injection hook of debug builds:
/// `PURCELL_SIM_TEST_ABORT_AFTER_RENAMES=N` aborts the process after the `N`-th, as a kill
/// would (the tests' kill between the C pair's renames).
struct Renames(u32);

impl Renames {
    /// Renames `from` over `to`, a record of the output `out`.
    fn rename(&mut self, from: &Path, to: &Path, out: &Path) -> Result<(), OutputError> {
        fs::rename(from, to).map_err(io_error(out, "cannot write its record"))?;
        self.step();
        Ok(())
    }

    fn step(&mut self) {
        self.0 += 1;
        #[cfg(debug_assertions)]
        if std::env::var("PURCELL_SIM_TEST_ABORT_AFTER_RENAMES").ok() == Some(self.0.to_string()) {
            std::process::abort();
        }
    }
}

impl Drop for OutputFile {
    fn drop(&mut self) {
        drop(self.staging.take());
        remove_empty_dirs(&self.created_parents);
    }
}
