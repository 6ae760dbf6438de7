//! A single output file: checked and staged before the work, renamed over its path after it.

use super::classify::{Existing, classify_file};
use super::disk::{
    create_parents, create_staging, keep_permissions, remove_empty_dirs, rename_no_replace, split,
    sync_dir, write_synced,
};
use super::error::{OutputError, io_error};
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// An output file, checked and staged by [`OutputFile::prepare`], written by
/// [`OutputFile::commit`]; dropped uncommitted, it removes what it created.
#[derive(Debug)]
pub struct OutputFile {
    path: PathBuf,
    recognise: fn(&[u8]) -> bool,
    force: bool,
    inputs: Vec<PathBuf>,
    staging: Option<PathBuf>,
    created_parents: Vec<PathBuf>,
}

impl OutputFile {
    /// Checks that `path` may be written: missing, or a regular file whose contents
    /// `recognise` accepts as a previous result of ours (any regular file with `force`), and
    /// never one of `inputs` (the same file by any name); then creates the staging file next
    /// to it, before any work.
    pub fn prepare(
        path: &Path,
        recognise: fn(&[u8]) -> bool,
        force: bool,
        inputs: &[&Path],
    ) -> Result<Self, OutputError> {
        let (parent, name) = split(path)?;
        let mut out = OutputFile {
            path: parent.join(&name),
            recognise,
            force,
            inputs: inputs.iter().map(|p| p.to_path_buf()).collect(),
            staging: None,
            created_parents: Vec::new(),
        };
        out.check()?;
        out.created_parents =
            create_parents(&parent).map_err(io_error(path, "cannot create its directory"))?;
        out.staging =
            Some(create_staging(&parent, false).map_err(io_error(path, "cannot be created"))?);
        Ok(out)
    }

    /// `Ok` if the path may be written now.
    fn check(&self) -> Result<Existing, OutputError> {
        let path = &self.path;
        let existing = classify_file(path, self.recognise, &self.inputs)
            .map_err(io_error(path, "cannot inspect"))?;
        match existing {
            Existing::Foreign {
                reason,
                force_overrides,
            } if !(self.force && force_overrides) => Err(OutputError::Refused {
                path: path.clone(),
                reason,
                force_overrides,
            }),
            e => Ok(e),
        }
    }

    /// Writes `bytes` to the staging file and renames it over the path.
    pub fn commit(mut self, bytes: &[u8]) -> Result<(), OutputError> {
        let staging = self.staging.clone().unwrap_or_default();
        write_synced(&staging, bytes).map_err(io_error(&staging, "cannot write"))?;
        let existing = self.check()?;
        let placed = match existing {
            Existing::Missing => match rename_no_replace(&staging, &self.path) {
                Err(e) if e.kind() == io::ErrorKind::Unsupported => {
                    fs::rename(&staging, &self.path)
                }
                r => r,
            },
            _ => {
                keep_permissions(&staging, &self.path);
                fs::rename(&staging, &self.path)
            }
        };
        placed.map_err(io_error(&self.path, "cannot write"))?;
        self.staging = None;
        self.created_parents.clear();
        if let Some(parent) = self.path.parent() {
            sync_dir(parent);
        }
        Ok(())
    }
}

impl Drop for OutputFile {
    fn drop(&mut self) {
        if let Some(s) = self.staging.take() {
            let _ = fs::remove_file(s);
        }
        remove_empty_dirs(&self.created_parents);
    }
}
