//! The filesystem steps of an output: resolving the path, creating missing parents, synced
//! writes, keeping permissions, and `renameat2` (exchange, rename without replacing).

use super::error::{OutputError, io_error};
use std::ffi::OsString;
use std::fs;
use std::io::{self, Write as _};
use std::path::{Path, PathBuf};

/// `(parent, name)` of an output path; `.`, `..` and the like are resolved first.
pub(super) fn split(path: &Path) -> Result<(PathBuf, OsString), OutputError> {
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
pub(super) fn create_parents(dir: &Path) -> io::Result<Vec<PathBuf>> {
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
pub(super) fn remove_empty_dirs(dirs: &[PathBuf]) {
    for d in dirs {
        let _ = fs::remove_dir(d);
    }
}

/// Gives `staging` the permissions of `old`, the entry it replaces, if of the same kind (best
/// effort).
pub(super) fn keep_permissions(staging: &Path, old: &Path) {
    if let (Ok(old), Ok(new)) = (fs::symlink_metadata(old), fs::symlink_metadata(staging))
        && old.file_type() == new.file_type()
    {
        let _ = fs::set_permissions(staging, old.permissions());
    }
}

pub(super) fn write_synced(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let mut f = fs::File::create(path)?;
    f.write_all(bytes)?;
    f.sync_all()
}

/// Flushes a directory's entries to disk (best effort: not every platform can).
pub(super) fn sync_dir(dir: &Path) {
    if let Ok(d) = fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

/// Swaps two paths in one step (`renameat2(RENAME_EXCHANGE)`); `Unsupported` where the
/// platform or filesystem cannot.
pub(super) fn exchange(a: &Path, b: &Path) -> io::Result<()> {
    rename2(a, b, RENAME_EXCHANGE)
}

/// Renames `from` to `to` only if `to` does not exist; `Unsupported` where impossible.
pub(super) fn rename_no_replace(from: &Path, to: &Path) -> io::Result<()> {
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

/// Removes a file, a symbolic link or a whole directory.
pub(super) fn remove_any(path: &Path) -> io::Result<()> {
    if fs::symlink_metadata(path)?.is_dir() {
        fs::remove_dir_all(path)
    } else {
        fs::remove_file(path)
    }
}

/// Every non-directory entry under `dir`, as `/`-separated relative names (innermost
/// directories listed in `dirs`, deepest first).
pub(super) fn walk(
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
