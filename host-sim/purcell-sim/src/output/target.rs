//! Where results go, without ever losing a user's data: the one place every subcommand
//! writes its outputs through ([`OutputDir`] for a directory of files, [`OutputFile`] for one
//! file).
//!
//! - **Ours or nothing.** An existing output directory is replaced only if it is a previous
//!   result of ours: it holds our manifest ([`MANIFEST`], which names every file we wrote with
//!   its length and FNV-1a hash) and nothing else than those files, byte for byte as we wrote
//!   them (an empty directory holds nothing to lose and is replaced too). An existing single
//!   file is replaced only if its caller recognises the contents as its own format, and a
//!   directory only by the subcommand that wrote it. Anything else is refused before any
//!   work ([`OutputError::Refused`]), unless `force`; symbolic links (`LINK/` included),
//!   device nodes and other special files, a directory where a file goes, a mount point,
//!   what this process cannot replace (another user's entry in a sticky directory, an
//!   immutable or unwritable directory) and a path that is or holds an input of the command
//!   (after symbolic links, `.` and `..`) are refused even then.
//! - **Checked before the work.** `prepare` creates the staging directory or file next to
//!   the path (and any missing parent directories), which proves the path can be written
//!   before a long computation; if the command fails, dropping the value removes what it
//!   created. Staging entries of runs that were killed (their process is gone) are removed
//!   then too.
//! - **Atomic.** `commit` writes everything into the staging entry, re-checks the path (it
//!   may have changed during the work), and swaps it in with one rename: a directory by
//!   `renameat2(RENAME_EXCHANGE)`, after which the old contents (now under the staging name)
//!   are removed; a file by `rename`, which replaces atomically. The new entry keeps the
//!   permissions of the one it replaces. Where the filesystem cannot exchange, the new files
//!   are renamed into the existing directory one by one under a manifest that lists the old
//!   and the new files at every moment: the path never goes missing, and a run interrupted
//!   half-way leaves a directory that the next run recognises as ours.

use serde::{Deserialize, Serialize};
use std::ffi::OsString;
use std::fs;
use std::io::{self, Write as _};
use std::path::{Component, Path, PathBuf};

/// The manifest each output directory holds, naming every file the tool wrote into it.
pub const MANIFEST: &str = "purcell-sim-manifest.json";
/// The manifest's `format` tag.
const FORMAT: &str = "purcell-sim-output";
/// The only manifest version this build reads and writes.
const VERSION: u64 = 1;
/// Staging entries are named `.purcell-sim-PID-N.tmp` (this prefix, the process id, a
/// counter, this suffix): short, so any output name fits beside them.
const STAGING: [&str; 2] = [".purcell-sim-", ".tmp"];
/// Why an output is refused when it is or holds an input.
const INPUT: &str = "is or holds an input of this command";

/// Why an output was refused or could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The path holds something the tool did not write (or must never replace).
    #[error("{}: {reason}; refusing to replace it ({})", .path.display(),
        if *.force_overrides { "pass --force to replace it anyway" } else { "even with --force" })]
    Refused {
        /// The output path.
        path: PathBuf,
        /// What is there.
        reason: String,
        /// Whether `force` would replace it.
        force_overrides: bool,
    },
    /// A filesystem operation failed.
    #[error("{}: {what}: {source}", .path.display())]
    Io {
        /// The path the operation was on.
        path: PathBuf,
        /// What was being done.
        what: &'static str,
        /// The operating system's error.
        #[source]
        source: io::Error,
    },
}

fn io_error(path: &Path, what: &'static str) -> impl FnOnce(io::Error) -> OutputError {
    let path = path.to_path_buf();
    move |source| OutputError::Io { path, what, source }
}

/// One file as the manifest records it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Entry {
    /// Path relative to the output directory, `/`-separated.
    name: String,
    /// Length in bytes.
    bytes: u64,
    /// FNV-1a 64 of the contents, 16 hex digits.
    fnv1a64: String,
}

impl Entry {
    fn of(name: &str, contents: &[u8]) -> Self {
        Entry {
            name: name.to_string(),
            bytes: contents.len() as u64,
            fnv1a64: format!("{:016x}", fnv1a64(contents)),
        }
    }
}

/// The manifest. A name may appear twice (old and new contents) while a directory is
/// updated file by file; a file matches if it matches any entry of its name.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Manifest {
    format: String,
    version: u64,
    /// `purcell-sim <version>`, for people reading it.
    written_by: String,
    /// The subcommand that wrote the directory.
    command: String,
    files: Vec<Entry>,
}

impl Manifest {
    fn new(command: &str, files: Vec<Entry>) -> Self {
        Manifest {
            format: FORMAT.into(),
            version: VERSION,
            written_by: concat!("purcell-sim ", env!("CARGO_PKG_VERSION")).into(),
            command: command.into(),
            files,
        }
    }

    /// The manifest in `bytes`, if it is one of ours of this version.
    fn parse(bytes: &[u8]) -> Option<Self> {
        crate::input::json::<Manifest>(bytes)
            .ok()
            .filter(|m| m.format == FORMAT && m.version == VERSION)
    }

    fn to_bytes(&self) -> Vec<u8> {
        let mut text = serde_json::to_string_pretty(self).unwrap_or_default();
        text.push('\n');
        text.into_bytes()
    }

    fn lists(&self, name: &str) -> bool {
        self.files.iter().any(|e| e.name == name)
    }

    /// Whether the file `name` of length `len` holds what we wrote (read only if the
    /// length matches one of the entries).
    fn matches(&self, name: &str, len: u64, path: &Path) -> io::Result<bool> {
        let entries: Vec<&Entry> = self
            .files
            .iter()
            .filter(|e| e.name == name && e.bytes == len)
            .collect();
        if entries.is_empty() {
            return Ok(false);
        }
        let hash = format!("{:016x}", fnv1a64(&fs::read(path)?));
        Ok(entries.iter().any(|e| e.fnv1a64 == hash))
    }
}

/// FNV-1a, 64 bit: detects a changed file, does not resist forgery.
fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// What a path holds now.
#[derive(Debug)]
enum Existing {
    /// Nothing.
    Missing,
    /// A previous result of ours (for a directory: its manifest, `None` if it is empty).
    Ours(Option<Manifest>),
    /// Anything else.
    Foreign {
        /// What is there, for the message.
        reason: String,
        /// Whether `force` replaces it.
        force_overrides: bool,
    },
}

fn foreign(reason: impl Into<String>, force_overrides: bool) -> Existing {
    Existing::Foreign {
        reason: reason.into(),
        force_overrides,
    }
}

/// Classifies the output directory path `parent/name` of subcommand `command` (symbolic links
/// are not followed).
fn classify_dir(path: &Path, command: &str, inputs: &[PathBuf]) -> io::Result<Existing> {
    if holds_input(path, inputs) {
        return Ok(foreign(INPUT, false));
    }
    let meta = match fs::symlink_metadata(path) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Existing::Missing),
        r => r?,
    };
    let kind = meta.file_type();
    if let Some(reason) = unreplaceable(path, &meta)? {
        return Ok(foreign(reason, false));
    }
    Ok(if kind.is_dir() {
        ownership(path, command)?
    } else if kind.is_file() {
        foreign("is a file, not a directory", true)
    } else if kind.is_symlink() {
        foreign("is a symbolic link (give the path it points to)", false)
    } else {
        foreign("is a device or other special file", false)
    })
}

/// Whether the directory `dir` is a previous result of subcommand `command`.
fn ownership(dir: &Path, command: &str) -> io::Result<Existing> {
    if fs::read_dir(dir)?.next().is_none() {
        return Ok(Existing::Ours(None));
    }
    let manifest = match crate::input::read(&dir.join(MANIFEST)) {
        Ok(bytes) => match Manifest::parse(&bytes) {
            Some(m) => m,
            None => {
                return Ok(foreign(
                    format!("holds a {MANIFEST} that this build of purcell-sim did not write"),
                    true,
                ));
            }
        },
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            return Ok(foreign(
                format!("is not empty and is not a purcell-sim output (no {MANIFEST})"),
                true,
            ));
        }
        Err(e) => return Err(e),
    };
    if manifest.command != command {
        return Ok(foreign(
            format!("is a result of `purcell-sim {}`", manifest.command),
            true,
        ));
    }
    Ok(match first_stranger(dir, "", &manifest)? {
        Some(stranger) => foreign(stranger, true),
        None => Existing::Ours(Some(manifest)),
    })
}

/// Whether `path` is one of `inputs` (the same file by any name) or a directory that holds
/// one (after symbolic links, `.` and `..`).
fn holds_input(path: &Path, inputs: &[PathBuf]) -> bool {
    let Ok(out) = fs::canonicalize(path) else {
        return false;
    };
    inputs
        .iter()
        .any(|i| same_file(path, i) || fs::canonicalize(i).is_ok_and(|i| i.starts_with(&out)))
}

/// The directory an output path `parent/name` is in.
fn parent_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Why the existing `path` (`meta`, a directory or a file) cannot be replaced by this
/// process, even with `force`: a mount point (on another device than its directory),
/// another user's entry in a sticky directory, or one that cannot be written (immutable, on
/// a read-only filesystem, or for a directory, whose old contents are removed after the
/// swap, without write permission).
#[cfg(target_os = "linux")]
fn unreplaceable(path: &Path, meta: &fs::Metadata) -> io::Result<Option<String>> {
    use std::os::unix::{ffi::OsStrExt, fs::MetadataExt};
    if !(meta.is_dir() || meta.is_file()) {
        return Ok(None);
    }
    let up = fs::metadata(parent_of(path))?;
    // SAFETY: geteuid has no preconditions and cannot fail.
    let euid = unsafe { libc::geteuid() };
    if meta.dev() != up.dev() {
        return Ok(Some("is a mount point".into()));
    }
    if up.mode() & libc::S_ISVTX != 0 && euid != 0 && meta.uid() != euid && up.uid() != euid {
        return Ok(Some(
            "is another user's, in a sticky directory where only they can replace it".into(),
        ));
    }
    let c = std::ffi::CString::new(path.as_os_str().as_bytes())?;
    // SAFETY: a valid NUL-terminated path; the call reads it and nothing else.
    if unsafe { libc::access(c.as_ptr(), libc::W_OK) } == 0 {
        return Ok(None);
    }
    let e = io::Error::last_os_error();
    // A file is replaced by a rename in its directory: its own mode does not matter.
    Ok((meta.is_dir() || e.raw_os_error() != Some(libc::EACCES))
        .then(|| format!("cannot be replaced ({e})")))
}

#[cfg(not(target_os = "linux"))]
fn unreplaceable(_: &Path, _: &fs::Metadata) -> io::Result<Option<String>> {
    Ok(None)
}

/// The first entry under `dir` that the manifest does not account for, described.
fn first_stranger(dir: &Path, prefix: &str, manifest: &Manifest) -> io::Result<Option<String>> {
    for entry in fs::read_dir(dir)? {
        let entry = entry?;
        let Some(name) = entry.file_name().to_str().map(|n| format!("{prefix}{n}")) else {
            return Ok(Some(format!(
                "holds {:?}, which purcell-sim did not write",
                entry.file_name()
            )));
        };
        if name == MANIFEST {
            continue;
        }
        let kind = entry.file_type()?;
        if kind.is_dir() {
            if let Some(s) = first_stranger(&entry.path(), &format!("{name}/"), manifest)? {
                return Ok(Some(s));
            }
        } else if !kind.is_file() || !manifest.lists(&name) {
            return Ok(Some(format!(
                "holds {name}, which purcell-sim did not write"
            )));
        } else if !manifest.matches(&name, entry.metadata()?.len(), &entry.path())? {
            return Ok(Some(format!(
                "holds {name}, changed since purcell-sim wrote it"
            )));
        }
    }
    Ok(None)
}

/// `(parent, name)` of an output path; `.`, `..` and the like are resolved first.
fn split(path: &Path) -> Result<(PathBuf, OsString), OutputError> {
    let resolved = if path.file_name().is_none() {
        fs::canonicalize(path).map_err(io_error(path, "cannot resolve the path"))?
    } else {
        path.to_path_buf()
    };
    match (resolved.parent(), resolved.file_name()) {
        (Some(parent), Some(name)) => {
            let parent = if parent.as_os_str().is_empty() {
                PathBuf::from(".")
            } else {
                parent.to_path_buf()
            };
            Ok((parent, name.to_os_string()))
        }
        _ => Err(OutputError::Refused {
            path: path.to_path_buf(),
            reason: "is the root directory".into(),
            force_overrides: false,
        }),
    }
}

/// Creates the missing ancestors of `dir` (outermost first); returns them innermost first.
fn create_parents(dir: &Path) -> io::Result<Vec<PathBuf>> {
    let mut missing = Vec::new();
    let mut p = dir;
    loop {
        match fs::symlink_metadata(p) {
            Ok(_) => break,
            Err(e) if e.kind() == io::ErrorKind::NotFound => {
                missing.push(p.to_path_buf());
                match p.parent() {
                    Some(q) if !q.as_os_str().is_empty() => p = q,
                    _ => break,
                }
            }
            Err(e) => return Err(e),
        }
    }
    for (i, d) in missing.iter().enumerate().rev() {
        if let Err(e) = fs::create_dir(d) {
            remove_empty_dirs(missing.get(i + 1..).unwrap_or_default());
            return Err(e);
        }
    }
    Ok(missing)
}

/// Removes directories (innermost first) if they are empty; best effort.
fn remove_empty_dirs(dirs: &[PathBuf]) {
    for d in dirs {
        let _ = fs::remove_dir(d);
    }
}

/// A fresh staging directory or file in `parent`, after removing the stale ones there.
fn create_staging(parent: &Path, directory: bool) -> io::Result<PathBuf> {
    remove_stale_staging(parent);
    let [prefix, suffix] = STAGING;
    for n in 0..1000 {
        let p = parent.join(format!("{prefix}{}-{n}{suffix}", std::process::id()));
        let made = if directory {
            fs::create_dir(&p)
        } else {
            fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&p)
                .map(drop)
        };
        match made {
            Ok(()) => return Ok(p),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
    Err(io::Error::new(
        io::ErrorKind::AlreadyExists,
        "no free temporary name",
    ))
}

/// Removes the staging entries in `parent` whose process is gone (a run killed before it
/// could clean up); best effort.
fn remove_stale_staging(parent: &Path) {
    let Ok(entries) = fs::read_dir(parent) else {
        return;
    };
    let [prefix, suffix] = STAGING;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let pid = name
            .to_str()
            .and_then(|n| {
                n.strip_prefix(prefix)?
                    .strip_suffix(suffix)?
                    .split_once('-')
            })
            .filter(|(_, n)| n.parse::<u32>().is_ok())
            .and_then(|(pid, _)| pid.parse::<u32>().ok());
        if let Some(pid) = pid
            && !running(pid)
        {
            let _ = remove_any(&entry.path());
        }
    }
}

/// Whether process `pid` exists (assumed, where that cannot be asked).
#[cfg(target_os = "linux")]
fn running(pid: u32) -> bool {
    let Ok(pid) = libc::pid_t::try_from(pid) else {
        return true;
    };
    // SAFETY: signal 0 sends nothing; it only asks whether `pid` (> 0: one process) exists.
    pid <= 0
        || unsafe { libc::kill(pid, 0) } == 0
        || io::Error::last_os_error().raw_os_error() != Some(libc::ESRCH)
}

#[cfg(not(target_os = "linux"))]
fn running(_: u32) -> bool {
    true
}

/// Gives `staging` the permissions of `old`, the entry it replaces, if of the same kind (best
/// effort).
fn keep_permissions(staging: &Path, old: &Path) {
    if let (Ok(old), Ok(new)) = (fs::symlink_metadata(old), fs::symlink_metadata(staging))
        && old.file_type() == new.file_type()
    {
        let _ = fs::set_permissions(staging, old.permissions());
    }
}

fn write_synced(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let mut f = fs::File::create(path)?;
    f.write_all(bytes)?;
    f.sync_all()
}

/// Flushes a directory's entries to disk (best effort: not every platform can).
fn sync_dir(dir: &Path) {
    if let Ok(d) = fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

/// Swaps two paths in one step (`renameat2(RENAME_EXCHANGE)`); `Unsupported` where the
/// platform or filesystem cannot.
fn exchange(a: &Path, b: &Path) -> io::Result<()> {
    rename2(a, b, RENAME_EXCHANGE)
}

/// Renames `from` to `to` only if `to` does not exist; `Unsupported` where impossible.
fn rename_no_replace(from: &Path, to: &Path) -> io::Result<()> {
    rename2(from, to, RENAME_NOREPLACE)
}

#[cfg(target_os = "linux")]
const RENAME_EXCHANGE: u32 = libc::RENAME_EXCHANGE;
#[cfg(target_os = "linux")]
const RENAME_NOREPLACE: u32 = libc::RENAME_NOREPLACE;
#[cfg(not(target_os = "linux"))]
const RENAME_EXCHANGE: u32 = 2;
#[cfg(not(target_os = "linux"))]
const RENAME_NOREPLACE: u32 = 1;

#[cfg(target_os = "linux")]
fn rename2(a: &Path, b: &Path, flags: u32) -> io::Result<()> {
    use std::os::unix::ffi::OsStrExt;
    let c = |p: &Path| std::ffi::CString::new(p.as_os_str().as_bytes());
    let (a, b) = (c(a)?, c(b)?);
    // SAFETY: two valid NUL-terminated paths; the call reads them and nothing else.
    let r = unsafe {
        libc::syscall(
            libc::SYS_renameat2,
            libc::AT_FDCWD,
            a.as_ptr(),
            libc::AT_FDCWD,
            b.as_ptr(),
            flags,
        )
    };
    if r == 0 {
        return Ok(());
    }
    let e = io::Error::last_os_error();
    Err(match e.raw_os_error() {
        Some(libc::EINVAL | libc::ENOSYS | libc::EOPNOTSUPP) => {
            io::Error::new(io::ErrorKind::Unsupported, e)
        }
        _ => e,
    })
}

#[cfg(not(target_os = "linux"))]
fn rename2(_: &Path, _: &Path, _: u32) -> io::Result<()> {
    Err(io::ErrorKind::Unsupported.into())
}

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
    /// The path as given, for messages.
    shown: PathBuf,
    /// The path resolved to `parent/name` (so `.` is replaced as its real name).
    path: PathBuf,
    command: &'static str,
    force: bool,
    inputs: Vec<PathBuf>,
    staging: Option<PathBuf>,
    created_parents: Vec<PathBuf>,
}

impl OutputDir {
    /// Checks that `path` may be written by subcommand `command` (missing, empty, a previous
    /// result of `command`, or anything replaceable with `force`), and never holds one of
    /// `inputs`; then creates the staging directory next to it, before any work.
    pub fn prepare(
        path: &Path,
        command: &'static str,
        force: bool,
        inputs: &[&Path],
    ) -> Result<Self, OutputError> {
        let (parent, name) = split(path)?;
        let inputs: Vec<PathBuf> = inputs.iter().map(|p| p.to_path_buf()).collect();
        // The path as `parent/name`: `LINK/` is the link, not the directory it points to.
        if let Existing::Foreign {
            reason,
            force_overrides,
        } = classify_dir(&parent.join(&name), command, &inputs)
            .map_err(io_error(path, "cannot inspect"))?
            && !(force && force_overrides)
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
            shown: path.to_path_buf(),
            path: parent.join(&name),
            command,
            force,
            inputs,
            staging: None,
            created_parents,
        };
        out.staging =
            Some(create_staging(&parent, true).map_err(io_error(path, "cannot be created"))?);
        Ok(out)
    }

    /// Writes `files` (name relative to the directory, contents) and the manifest, then
    /// puts them in place of the path in one step.
    pub fn commit(mut self, files: &[(String, Vec<u8>)]) -> Result<(), OutputError> {
        let staging = self.staging.clone().unwrap_or_default();
        let manifest = self.stage(&staging, files)?;
        let shown = self.shown.clone();
        let existing = classify_dir(&self.path, self.command, &self.inputs)
            .map_err(io_error(&shown, "cannot inspect"))?;
        match existing {
            Existing::Missing => {
                fs::rename(&staging, &self.path).map_err(io_error(&shown, "cannot create"))?
            }
            Existing::Foreign {
                reason,
                force_overrides,
            } if !(self.force && force_overrides) => {
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
        self.staging = None;
        self.created_parents.clear();
        if let Some(parent) = self.path.parent() {
            sync_dir(parent);
        }
        Ok(())
    }

    /// Writes the files and the manifest into the staging directory.
    fn stage(&self, staging: &Path, files: &[(String, Vec<u8>)]) -> Result<Manifest, OutputError> {
        check_names(files).map_err(io_error(&self.shown, "cannot write"))?;
        let mut entries = Vec::with_capacity(files.len());
        for (name, bytes) in files {
            let p = staging.join(name);
            if let Some(d) = p.parent() {
                fs::create_dir_all(d).map_err(io_error(d, "cannot create"))?;
            }
            write_synced(&p, bytes).map_err(io_error(&p, "cannot write"))?;
            entries.push(Entry::of(name, bytes));
        }
        let manifest = Manifest::new(self.command, entries);
        let p = staging.join(MANIFEST);
        write_synced(&p, &manifest.to_bytes()).map_err(io_error(&p, "cannot write"))?;
        sync_dir(staging);
        Ok(manifest)
    }
}

impl Drop for OutputDir {
    fn drop(&mut self) {
        if let Some(s) = self.staging.take() {
            let _ = fs::remove_dir_all(s);
        }
        remove_empty_dirs(&self.created_parents);
    }
}

/// Removes a file, a symbolic link or a whole directory.
fn remove_any(path: &Path) -> io::Result<()> {
    if fs::symlink_metadata(path)?.is_dir() {
        fs::remove_dir_all(path)
    } else {
        fs::remove_file(path)
    }
}

/// Every non-directory entry under `dir`, as `/`-separated relative names (innermost
/// directories listed in `dirs`, deepest first).
fn walk(
    dir: &Path,
    prefix: &str,
    files: &mut Vec<String>,
    dirs: &mut Vec<PathBuf>,
) -> io::Result<()> {
    for entry in fs::read_dir(dir)? {
        let entry = entry?;
        let name = format!("{prefix}{}", entry.file_name().to_string_lossy());
        if entry.file_type()?.is_dir() {
            walk(&entry.path(), &format!("{name}/"), files, dirs)?;
            dirs.push(entry.path());
        } else {
            files.push(name);
        }
    }
    Ok(())
}

/// Replaces the contents of the existing directory `target` by those of `staging` without
/// an exchange: first a manifest listing the old and the new files, then each new file
/// renamed over its old copy, then the old files that are not new removed, then the new
/// manifest. At every step the directory exists and its manifest accounts for every file.
fn replace_file_by_file(
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

/// Whether `a` and `b` name the same existing file (after symbolic links).
fn same_file(a: &Path, b: &Path) -> bool {
    match (fs::metadata(a), fs::metadata(b)) {
        #[cfg(unix)]
        (Ok(x), Ok(y)) => {
            use std::os::unix::fs::MetadataExt;
            (x.dev(), x.ino()) == (y.dev(), y.ino())
        }
        #[cfg(not(unix))]
        (Ok(_), Ok(_)) => fs::canonicalize(a).ok() == fs::canonicalize(b).ok(),
        _ => false,
    }
}

/// Classifies a single-file output path.
fn classify_file(
    path: &Path,
    recognise: fn(&[u8]) -> bool,
    inputs: &[PathBuf],
) -> io::Result<Existing> {
    if holds_input(path, inputs) {
        return Ok(foreign(INPUT, false));
    }
    let meta = match fs::symlink_metadata(path) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Existing::Missing),
        r => r?,
    };
    if let Some(reason) = unreplaceable(path, &meta)? {
        return Ok(foreign(reason, false));
    }
    let kind = meta.file_type();
    Ok(if kind.is_file() {
        let recognised = match crate::input::read(path) {
            Ok(bytes) => recognise(&bytes),
            // Too large to be ours.
            Err(e) if e.kind() == io::ErrorKind::FileTooLarge => false,
            Err(e) => return Err(e),
        };
        if recognised {
            Existing::Ours(None)
        } else {
            foreign("holds data that purcell-sim did not write", true)
        }
    } else if kind.is_symlink() {
        foreign("is a symbolic link (give the path it points to)", false)
    } else if kind.is_dir() {
        foreign("is a directory", false)
    } else {
        foreign("is a device or other special file", false)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn files(pairs: &[(&str, &str)]) -> Vec<(String, Vec<u8>)> {
        pairs
            .iter()
            .map(|(n, c)| (n.to_string(), c.as_bytes().to_vec()))
            .collect()
    }

    fn listing(dir: &Path) -> Vec<(String, String)> {
        let (mut names, mut dirs) = (Vec::new(), Vec::new());
        walk(dir, "", &mut names, &mut dirs).unwrap();
        names.sort();
        names
            .into_iter()
            .filter(|n| n != MANIFEST)
            .map(|n| {
                let text = fs::read_to_string(dir.join(&n)).unwrap();
                (n, text)
            })
            .collect()
    }

    /// Whether `r` is a refusal that `force` does (or does not) override.
    fn refused<T>(r: Result<T, OutputError>, force_overrides: bool) -> bool {
        matches!(r, Err(OutputError::Refused { force_overrides: f, .. }) if f == force_overrides)
    }

    fn is_ours(dir: &Path) -> bool {
        matches!(classify_dir(dir, "solve", &[]).unwrap(), Existing::Ours(_))
    }

    #[test]
    fn a_directory_is_ours_only_with_our_manifest_and_nothing_else() {
        let tmp = tempfile::tempdir().unwrap();
        let out = tmp.path().join("out");
        let new = files(&[("a.csv", "1,2\n"), ("fig/b.svg", "<svg/>")]);
        OutputDir::prepare(&out, "solve", false, &[])
            .unwrap()
            .commit(&new)
            .unwrap();
        assert!(is_ours(&out));
        assert_eq!(listing(&out).len(), 2);
        // Only the output and nothing else next to it (no staging directory left).
        assert_eq!(fs::read_dir(tmp.path()).unwrap().count(), 1);

        // An edited file, an extra file, an extra link, or a damaged manifest: not ours.
        fs::write(out.join("a.csv"), "1,3\n").unwrap();
        assert!(!is_ours(&out));
        fs::write(out.join("a.csv"), "1,2\n").unwrap();
        assert!(is_ours(&out));
        fs::write(out.join("fig/notes.txt"), "mine").unwrap();
        assert!(!is_ours(&out));
        fs::remove_file(out.join("fig/notes.txt")).unwrap();
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink("a.csv", out.join("link")).unwrap();
            assert!(!is_ours(&out));
            fs::remove_file(out.join("link")).unwrap();
        }
        let m = fs::read(out.join(MANIFEST)).unwrap();
        fs::write(out.join(MANIFEST), &m[..m.len() / 2]).unwrap();
        assert!(!is_ours(&out));
        fs::write(out.join(MANIFEST), &m).unwrap();
        // A deleted file of ours loses nothing: still ours.
        fs::remove_file(out.join("a.csv")).unwrap();
        assert!(is_ours(&out));
    }

    #[test]
    fn replacing_ours_by_exchange_or_file_by_file_leaves_exactly_the_new_files() {
        for exchange in [true, false] {
            let tmp = tempfile::tempdir().unwrap();
            let out = tmp.path().join("out");
            let old = files(&[("a.csv", "old"), ("old-only.svg", "x"), ("d/e.txt", "e")]);
            OutputDir::prepare(&out, "solve", false, &[])
                .unwrap()
                .commit(&old)
                .unwrap();
            let new = files(&[("a.csv", "new"), ("b.png", "png")]);
            if exchange {
                OutputDir::prepare(&out, "solve", false, &[])
                    .unwrap()
                    .commit(&new)
                    .unwrap();
            } else {
                let staged = OutputDir::prepare(&out, "solve", false, &[]).unwrap();
                let staging = staged.staging.clone().unwrap();
                let manifest = staged.stage(&staging, &new).unwrap();
                let Existing::Ours(old_manifest) = classify_dir(&out, "solve", &[]).unwrap() else {
                    panic!("not ours")
                };
                replace_file_by_file(&staging, &out, &manifest, old_manifest).unwrap();
                assert!(!staging.exists());
            }
            assert_eq!(
                listing(&out),
                [
                    ("a.csv".into(), "new".into()),
                    ("b.png".into(), "png".into())
                ],
                "exchange: {exchange}"
            );
            assert!(!out.join("d").exists());
            assert!(is_ours(&out));
            assert_eq!(fs::read_dir(tmp.path()).unwrap().count(), 1);
        }
    }

    #[test]
    fn a_half_done_file_by_file_update_is_still_ours() {
        let tmp = tempfile::tempdir().unwrap();
        let out = tmp.path().join("out");
        OutputDir::prepare(&out, "solve", false, &[])
            .unwrap()
            .commit(&files(&[("a.csv", "old"), ("b.csv", "old")]))
            .unwrap();
        let Existing::Ours(Some(old)) = classify_dir(&out, "solve", &[]).unwrap() else {
            panic!("not ours")
        };
        // Step 1 and half of step 2: the transition manifest, one file renamed.
        let mut both = Manifest::new(
            "solve",
            vec![Entry::of("a.csv", b"new"), Entry::of("b.csv", b"new")],
        );
        both.files.extend(old.files);
        fs::write(out.join(MANIFEST), both.to_bytes()).unwrap();
        fs::write(out.join("a.csv"), "new").unwrap();
        assert!(is_ours(&out));
    }

    #[test]
    fn foreign_paths_are_refused_before_anything_is_created() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("mine");
        fs::create_dir(&dir).unwrap();
        fs::write(dir.join("thesis.tex"), "precious").unwrap();
        let file = tmp.path().join("file");
        fs::write(&file, "precious").unwrap();
        for (path, force_overrides) in [
            (dir.clone(), true),
            (file.clone(), true),
            (file.join("below"), false),
            (PathBuf::from("/"), false),
        ] {
            match OutputDir::prepare(&path, "solve", false, &[]) {
                Err(OutputError::Refused {
                    force_overrides: f, ..
                }) => assert_eq!(f, force_overrides, "{path:?}"),
                Err(OutputError::Io { .. }) => assert!(!force_overrides, "{path:?}"),
                Ok(_) => panic!("{path:?} accepted"),
            }
        }
        #[cfg(unix)]
        {
            let link = tmp.path().join("link");
            std::os::unix::fs::symlink(&dir, &link).unwrap();
            assert!(refused(
                OutputDir::prepare(&link, "solve", true, &[]),
                false
            ));
            fs::remove_file(&link).unwrap();
        }
        #[cfg(unix)]
        assert!(refused(
            OutputDir::prepare(Path::new("/dev/null"), "solve", true, &[]),
            false
        ));
        assert_eq!(
            fs::read_to_string(dir.join("thesis.tex")).unwrap(),
            "precious"
        );
        assert_eq!(fs::read_to_string(&file).unwrap(), "precious");
        assert_eq!(fs::read_dir(tmp.path()).unwrap().count(), 2);
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 1);
    }

    #[test]
    fn force_replaces_a_foreign_directory_or_file_and_a_dropped_output_cleans_up() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("mine");
        fs::create_dir(&dir).unwrap();
        fs::write(dir.join("notes"), "x").unwrap();
        let file = tmp.path().join("file");
        fs::write(&file, "x").unwrap();
        for path in [&dir, &file] {
            OutputDir::prepare(path, "solve", true, &[])
                .unwrap()
                .commit(&files(&[("a", "1")]))
                .unwrap();
            assert_eq!(listing(path), [("a".into(), "1".into())]);
        }
        // Prepared then dropped (the command failed): staging and new parents removed.
        let deep = tmp.path().join("x/y/out");
        drop(OutputDir::prepare(&deep, "solve", false, &[]).unwrap());
        drop(OutputFile::prepare(&deep, |_| false, false, &[]).unwrap());
        assert!(!tmp.path().join("x").exists());
        assert_eq!(fs::read_dir(tmp.path()).unwrap().count(), 2);
    }

    #[test]
    fn a_single_file_replaces_only_its_own_kind_and_never_an_input() {
        let tmp = tempfile::tempdir().unwrap();
        let ours = |b: &[u8]| b.starts_with(b"OURS");
        let path = tmp.path().join("r.json");
        OutputFile::prepare(&path, ours, false, &[])
            .unwrap()
            .commit(b"OURS 1")
            .unwrap();
        OutputFile::prepare(&path, ours, false, &[])
            .unwrap()
            .commit(b"OURS 2")
            .unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"OURS 2");
        fs::write(&path, "theirs").unwrap();
        assert!(refused(OutputFile::prepare(&path, ours, false, &[]), true));
        OutputFile::prepare(&path, ours, true, &[])
            .unwrap()
            .commit(b"OURS 3")
            .unwrap();
        // The input, by its own name or another one, even with force and even if ours.
        let alias = tmp.path().join("alias.json");
        fs::hard_link(&path, &alias).unwrap();
        for out in [&path, &alias] {
            assert!(refused(
                OutputFile::prepare(out, ours, true, &[&path]),
                false
            ));
        }
        assert!(refused(
            OutputFile::prepare(tmp.path(), ours, true, &[]),
            false
        ));
        assert_eq!(fs::read(&path).unwrap(), b"OURS 3");
        assert_eq!(fs::read_dir(tmp.path()).unwrap().count(), 2);
    }
}
