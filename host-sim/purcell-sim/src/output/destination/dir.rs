//! An output directory: checked and staged before the work, swapped in after it in one step
//! (or file by file, under a manifest that accounts for every file, where the filesystem
//! cannot exchange).

use super::claim::Claim;
use super::classify::{Existing, classify_dir};
use super::disk::{
    exchange, keep_permissions, remove_any, remove_empty_dirs, split, sync_dir, walk, write_synced,
};
use super::error::{OutputError, io_error};
use super::manifest::{Entry, MANIFEST, Manifest};
use super::staging::{Staging, create_parents, swap_guard};
use std::fs;
use std::io;
use std::path::{Component, Path, PathBuf};

/// Files that can be named inside an output directory: relative, `/`-separated, no `..`.
fn check_names(files: &[(String, Vec<u8>)]) -> io::Result<()> {
    let mut seen = std::collections::HashSet::new();
    for (name, _) in files {
        let plain = !name.is_empty()
            && name != MANIFEST
            && Path::new(name)
                .components()
                .all(|c| matches!(c, Component::Normal(_)));
        if !plain || !seen.insert(name.as_str()) {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("bad or repeated output file name {name:?}"),
            ));
        }
    }
    Ok(())
}

/// An output directory, checked and staged by [`OutputDir::prepare`], written by
/// [`OutputDir::commit`]; dropped uncommitted, it removes what it created.
#[derive(Debug)]
pub struct OutputDir {
    /// What the command asks (its path as given, for messages).
    claim: Claim,
    /// The path resolved to `parent/name` (so `.` is replaced as its real name).
    path: PathBuf,
    pub(super) staging: Option<Staging>,
    created_parents: Vec<PathBuf>,
}

impl OutputDir {
    /// Checks that the claim's path may be written by its command (missing, empty, a
    /// previous result of the command, or anything replaceable with `force`), and never
    /// holds one of its inputs; then creates the staging directory next to it, before any
    /// work.
    pub fn prepare(claim: Claim) -> Result<Self, OutputError> {
        let path = claim.path.as_path();
        let (parent, name) = split(path)?;
        // The path as `parent/name`: `LINK/` is the link, not the directory it points to.
        if let Existing::Foreign {
            reason,
            force_overrides,
        } = classify_dir(&parent.join(&name), claim.command, &claim.inputs)
            .map_err(io_error(path, "cannot inspect"))?
            && !(claim.force && force_overrides)
        {
            return Err(OutputError::Refused {
                path: path.to_path_buf(),
                reason,
                force_overrides,
            });
        }
        let created_parents =
            create_parents(&parent).map_err(io_error(path, "cannot create its directory"))?;
        let mut out = OutputDir {
            path: parent.join(&name),
            claim,
            staging: None,
            created_parents,
        };
        let staged = Staging::create(&parent, true);
        out.staging = Some(staged.map_err(io_error(&out.claim.path, "cannot be created"))?);
        Ok(out)
    }

    /// Writes `files` (name relative to the directory, contents) and the manifest, then
    /// puts them in place of the path in one step.
    pub fn commit(mut self, files: &[(String, Vec<u8>)]) -> Result<(), OutputError> {
        let staging = self.staging.as_ref().map(|s| s.path().to_path_buf());
        let staging = staging.unwrap_or_default();
        let manifest = self.stage(&staging, files)?;
        let shown = self.claim.path.clone();
        let existing = classify_dir(&self.path, self.claim.command, &self.claim.inputs)
            .map_err(io_error(&shown, "cannot inspect"))?;
        match existing {
            Existing::Missing => {
                let _swap = swap_guard();
                fs::rename(&staging, &self.path).map_err(io_error(&shown, "cannot create"))?;
                if let Some(s) = self.staging.take() {
                    s.done();
                }
            }
            Existing::Foreign {
                reason,
                force_overrides,
            } if !(self.claim.force && force_overrides) => {
                return Err(OutputError::Refused {
                    path: shown,
                    reason: format!("{reason} (it changed while the command ran)"),
                    force_overrides,
                });
            }
            existing => {
                let old = match existing {
                    Existing::Ours(m) => m,
                    _ => None,
                };
                keep_permissions(&staging, &self.path);
                for e in &manifest.files {
                    keep_permissions(&staging.join(&e.name), &self.path.join(&e.name));
                }
                let _swap = swap_guard();
                match exchange(&staging, &self.path) {
                    Ok(()) => remove_any(&staging)
                        .map_err(io_error(&staging, "replaced; cannot remove the old copy"))?,
                    Err(e) if e.kind() == io::ErrorKind::Unsupported => {
                        replace_file_by_file(&staging, &self.path, &manifest, old)
                            .map_err(io_error(&shown, "cannot replace"))?
                    }
                    Err(e) => return Err(io_error(&shown, "cannot replace")(e)),
                }
            }
        }
        if let Some(s) = self.staging.take() {
            s.done();
        }
        self.created_parents.clear();
        if let Some(parent) = self.path.parent() {
            sync_dir(parent);
        }
        Ok(())
    }

    /// Writes the files and the manifest into the staging directory.
    pub(super) fn stage(
        &self,
        staging: &Path,
        files: &[(String, Vec<u8>)],
    ) -> Result<Manifest, OutputError> {
        check_names(files).map_err(io_error(&self.claim.path, "cannot write"))?;
        let mut entries = Vec::with_capacity(files.len());
        for (name, bytes) in files {
            let p = staging.join(name);
            if let Some(d) = p.parent() {
                fs::create_dir_all(d).map_err(io_error(d, "cannot create"))?;
            }
            write_synced(&p, bytes).map_err(io_error(&p, "cannot write"))?;
            entries.push(Entry::of(name, bytes));
        }
        let manifest = Manifest::new(self.claim.command, entries);
        let p = staging.join(MANIFEST);
        write_synced(&p, &manifest.to_bytes()).map_err(io_error(&p, "cannot write"))?;
        sync_dir(staging);
        Ok(manifest)
    }
}

impl Drop for OutputDir {
    fn drop(&mut self) {
        drop(self.staging.take());
        remove_empty_dirs(&self.created_parents);
    }
}

/// Replaces the contents of the existing directory `target` by those of `staging` without
/// an exchange: first a manifest listing the old and the new files, then each new file
/// renamed over its old copy, then the old files that are not new removed, then the new
/// manifest. At every step the directory exists and its manifest accounts for every file.
pub(super) fn replace_file_by_file(
    staging: &Path,
    target: &Path,
    manifest: &Manifest,
    old: Option<Manifest>,
) -> io::Result<()> {
    if !fs::symlink_metadata(target)?.is_dir() {
        return Err(io::Error::new(
            io::ErrorKind::Unsupported,
            "the filesystem cannot exchange paths, and a non-directory cannot be replaced \
             by a directory in one step: remove it first",
        ));
    }
    let (mut old_files, mut old_dirs) = (Vec::new(), Vec::new());
    walk(target, "", &mut old_files, &mut old_dirs)?;
    old_files.retain(|n| n != MANIFEST);
    // 1. A manifest that accepts the old contents (as listed, or as found if forced) and
    //    the new ones.
    let mut both = manifest.clone();
    match old {
        Some(m) => both.files.extend(m.files),
        None => {
            for name in &old_files {
                if let Ok(bytes) = fs::read(target.join(name)) {
                    both.files.push(Entry::of(name, &bytes));
                }
            }
        }
    }
    let transition = staging.join(".transition");
    write_synced(&transition, &both.to_bytes())?;
    fs::rename(&transition, target.join(MANIFEST))?;
    // 2. New files over old ones.
    for e in &manifest.files {
        let to = target.join(&e.name);
        if let Some(d) = to.parent() {
            fs::create_dir_all(d)?;
        }
        fs::rename(staging.join(&e.name), to)?;
    }
    // 3. Old files that are not new.
    for name in old_files.iter().filter(|n| !manifest.lists(n)) {
        fs::remove_file(target.join(name))?;
    }
    remove_empty_dirs(&old_dirs);
    // 4. The final manifest; the staging directory is left with empty directories only.
    fs::rename(staging.join(MANIFEST), target.join(MANIFEST))?;
    sync_dir(target);
    fs::remove_dir_all(staging)
}
