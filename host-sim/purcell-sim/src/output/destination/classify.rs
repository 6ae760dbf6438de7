//! What an output path holds now: nothing, a previous result of ours, or something else
//! (with why, and whether `force` replaces it).

use super::manifest::{MANIFEST, Manifest};
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// Why an output is refused when it is or holds an input.
const INPUT: &str = "is or holds an input of this command";

/// What a path holds now.
#[derive(Debug)]
pub(super) enum Existing {
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

/// What the output path `path` holds, settled (`Err`) unless it is a directory or a regular
/// file (`Ok`, its kind): one of `inputs` or a directory holding one, nothing, an entry this
/// process cannot replace ([`unreplaceable`]), a symbolic link (not followed) or a special
/// file.
fn settled(path: &Path, inputs: &[PathBuf]) -> io::Result<Result<fs::FileType, Existing>> {
    if holds_input(path, inputs) {
        return Ok(Err(foreign(INPUT, false)));
    }
    let meta = match fs::symlink_metadata(path) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Err(Existing::Missing)),
        r => r?,
    };
    if let Some(reason) = unreplaceable(path, &meta)? {
        return Ok(Err(foreign(reason, false)));
    }
    let kind = meta.file_type();
    Ok(if kind.is_symlink() {
        Err(foreign(
            "is a symbolic link (give the path it points to)",
            false,
        ))
    } else if kind.is_dir() || kind.is_file() {
        Ok(kind)
    } else {
        Err(foreign("is a device or other special file", false))
    })
}

/// Classifies the output directory path `parent/name` of subcommand `command` (symbolic links
/// are not followed).
pub(super) fn classify_dir(path: &Path, command: &str, inputs: &[PathBuf]) -> io::Result<Existing> {
    let kind = match settled(path, inputs)? {
        Ok(kind) => kind,
        Err(existing) => return Ok(existing),
    };
    Ok(if kind.is_dir() {
        ownership(path, command)?
    } else {
        foreign("is a file, not a directory", true)
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

/// Classifies a single-file output path `path` of subcommand `command`, whose record is
/// `record` (`file::record_path`): ours only if the record is a manifest of `command` that
/// lists the file's length and hash.
pub(super) fn classify_file(
    path: &Path,
    record: &Path,
    command: &str,
    inputs: &[PathBuf],
) -> io::Result<Existing> {
    let manifest = match fs::symlink_metadata(record) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => None,
        Err(e) => return Err(e),
        Ok(m) if !m.is_file() => {
            return Ok(foreign(
                format!("its record {} is not a file", record.display()),
                false,
            ));
        }
        Ok(_) => Some(match crate::input::read(record) {
            Ok(bytes) => Manifest::parse(&bytes),
            Err(e) if e.kind() == io::ErrorKind::FileTooLarge => None,
            Err(e) => return Err(e),
        }),
    };
    let kind = match settled(path, inputs)? {
        Ok(kind) => kind,
        // A record without its file (or not one of ours): replaced only with force.
        Err(Existing::Missing) if matches!(manifest, Some(None)) => {
            return Ok(foreign(
                format!(
                    "is missing, but {} beside it is not a record purcell-sim wrote",
                    record.display()
                ),
                true,
            ));
        }
        Err(existing) => return Ok(existing),
    };
    if !kind.is_file() {
        return Ok(foreign("is a directory", false));
    }
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    let len = fs::metadata(path)?.len();
    Ok(match manifest {
        None => foreign(
            format!(
                "holds data that purcell-sim did not write (no record {} of it)",
                record.display()
            ),
            true,
        ),
        Some(None) => foreign(
            format!("{} is not a record purcell-sim wrote", record.display()),
            true,
        ),
        Some(Some(m)) if m.command != command => {
            foreign(format!("is a result of `purcell-sim {}`", m.command), true)
        }
        Some(Some(m)) if m.matches(&name, len, path)? => Existing::Ours(Some(m)),
        Some(Some(_)) => foreign(
            "holds data that purcell-sim did not write (not what its record lists: changed \
             since)",
            true,
        ),
    })
}
