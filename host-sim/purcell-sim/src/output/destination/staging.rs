//! Staging entries beside an output: created and locked before the work, swapped in or removed
//! after it, removed on an interrupt ([`remove_staging_on_interrupt`]), and removed by the next
//! run there if this one was killed.
//!
//! An entry is named `.purcell-sim-XXXXXXXXXXXXXXXX.tmp` (16 random hex digits) and its creator
//! holds an exclusive `flock` on it for as long as it runs; the kernel releases the lock when
//! the process ends, however it ends. Another run removes an entry only if it can take that lock
//! itself. Unlike a process id, the lock means the same in every PID namespace (containers) and,
//! on NFS, where Linux maps `flock` to byte-range locks, on every host. Where a filesystem
//! cannot lock at all, an entry is never taken for stale.

use super::disk::{self, remove_any};
use std::fs;
use std::hash::{BuildHasher, Hasher};
use std::io;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

const PREFIX: &str = ".purcell-sim-";
const SUFFIX: &str = ".tmp";

/// The staging entries this process holds, for the interrupt handler.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
/// The directories this process created for its outputs, innermost first for each output.
static CREATED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
/// Held while outputs are renamed into place: an interrupt waits for the swap to end.
static SWAP: Mutex<()> = Mutex::new(());

fn live() -> MutexGuard<'static, Vec<PathBuf>> {
    LIVE.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Creates the missing directories of `dir` ([`disk::create_parents`]) and records them
/// (innermost first): an interrupt removes those that are still empty.
pub(super) fn create_parents(dir: &Path) -> io::Result<Vec<PathBuf>> {
    let missing = disk::create_parents(dir)?;
    CREATED
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .extend(missing.iter().cloned());
    Ok(missing)
}

/// Held while a commit renames its entries into place; the interrupt handler waits for it.
pub(super) fn swap_guard() -> MutexGuard<'static, ()> {
    SWAP.lock().unwrap_or_else(PoisonError::into_inner)
}

/// A staging entry of this process, locked; dropped, it is removed.
#[derive(Debug)]
pub(super) struct Staging {
    path: PathBuf,
    /// The open entry holding the `flock` (none where the filesystem cannot lock).
    _lock: Option<fs::File>,
    /// Renamed away (into place): nothing to remove.
    done: bool,
}

impl Staging {
    /// A fresh staging directory or file in `parent`, locked and registered, after removing
    /// the stale ones there.
    pub(super) fn create(parent: &Path, directory: bool) -> io::Result<Self> {
        remove_stale(parent);
        for _ in 0..100 {
            let path = parent.join(format!("{PREFIX}{:016x}{SUFFIX}", random()));
            let made = if directory {
                fs::create_dir(&path)
            } else {
                fs::OpenOptions::new()
                    .write(true)
                    .create_new(true)
                    .open(&path)
                    .map(drop)
            };
            match made {
                Ok(()) => {}
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(e),
            }
            // Between the creation and the lock, another run may find the entry unlocked and
            // remove it: then take another name.
            match lock(&path) {
                Ok(Lock::Held(file)) if same_entry(&path, &file) => {
                    live().push(path.clone());
                    return Ok(Staging {
                        path,
                        _lock: Some(file),
                        done: false,
                    });
                }
                Ok(Lock::Unsupported) => {
                    live().push(path.clone());
                    return Ok(Staging {
                        path,
                        _lock: None,
                        done: false,
                    });
                }
                Ok(_) => continue,
                Err(e) if e.kind() == io::ErrorKind::NotFound => continue,
                Err(e) => {
                    let _ = remove_any(&path);
                    return Err(e);
                }
            }
        }
        Err(io::Error::new(
            io::ErrorKind::AlreadyExists,
            "no free temporary name",
        ))
    }

    pub(super) fn path(&self) -> &Path {
        &self.path
    }

    /// The entry was renamed into place (or removed): forget it without removing anything.
    pub(super) fn done(mut self) {
        self.done = true;
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.done {
            let _ = remove_any(&self.path);
        }
        live().retain(|p| *p != self.path);
    }
}

/// 64 random bits (std's per-process random hash keys, the time and the process id).
fn random() -> u64 {
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    h.write_u32(std::process::id());
    if let Ok(t) = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH) {
        h.write_u128(t.as_nanos());
    }
    h.finish()
}

/// The result of trying to lock an entry.
enum Lock {
    /// We hold it now.
    Held(fs::File),
    /// Another process holds it.
    Busy,
    /// The filesystem (or platform) cannot lock.
    Unsupported,
}

/// Tries to take the exclusive lock of the entry `path` (a symbolic link is not followed:
/// an error).
#[cfg(target_os = "linux")]
fn lock(path: &Path) -> io::Result<Lock> {
    use std::os::unix::fs::OpenOptionsExt;
    use std::os::unix::io::AsRawFd;
    let file = fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK)
        .open(path)?;
    // SAFETY: a valid open descriptor; flock only changes its lock.
    if unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) } == 0 {
        return Ok(Lock::Held(file));
    }
    let e = io::Error::last_os_error();
    Ok(match e.raw_os_error() {
        Some(libc::EWOULDBLOCK) => Lock::Busy,
        Some(libc::ENOLCK | libc::EOPNOTSUPP | libc::EINVAL) => Lock::Unsupported,
        _ => return Err(e),
    })
}

#[cfg(not(target_os = "linux"))]
fn lock(_: &Path) -> io::Result<Lock> {
    Ok(Lock::Unsupported)
}

/// Whether `path` still names the entry `file` is open on.
fn same_entry(path: &Path, file: &fs::File) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (fs::symlink_metadata(path), file.metadata()) {
            (Ok(a), Ok(b)) => (a.dev(), a.ino()) == (b.dev(), b.ino()),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = (path, file);
        true
    }
}

/// Whether `name` is a staging entry's: the prefix, 16 lowercase hex digits, the suffix.
fn is_staging_name(name: &str) -> bool {
    name.strip_prefix(PREFIX)
        .and_then(|n| n.strip_suffix(SUFFIX))
        .is_some_and(|id| {
            id.len() == 16 && id.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f'))
        })
}

/// Removes the staging entries in `parent` that no running process holds (left by a run that
/// was killed); best effort.
fn remove_stale(parent: &Path) {
    let Ok(entries) = fs::read_dir(parent) else {
        return;
    };
    for entry in entries.flatten() {
        // Only directories and regular files: opening a device or a FIFO could act on it.
        let plain = entry.file_type().is_ok_and(|t| t.is_dir() || t.is_file());
        if !plain || !entry.file_name().to_str().is_some_and(is_staging_name) {
            continue;
        }
        let path = entry.path();
        // Removed while we hold its lock, so no one can be creating it under that name.
        if let Ok(Lock::Held(file)) = lock(&path)
            && same_entry(&path, &file)
        {
            let _ = remove_any(&path);
        }
    }
}

/// Installs the handler of `SIGINT`, `SIGTERM` and `SIGHUP` (Ctrl-C, `kill`, a closed
/// terminal): it waits for a swap in progress to end, removes this process's staging entries
/// and the directories it created for them that are still empty, and exits with `128 + signal` (130 for Ctrl-C). Call it first thing in `main`, before any
/// other thread starts (the signals are blocked in every thread and taken by one).
pub fn remove_staging_on_interrupt() {
    #[cfg(target_os = "linux")]
    {
        // SAFETY: sigset_t is plain data, filled by sigemptyset/sigaddset; pthread_sigmask
        // changes only this thread's mask (inherited by the threads started after it).
        let set = unsafe {
            let mut set: libc::sigset_t = std::mem::zeroed();
            libc::sigemptyset(&mut set);
            for s in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
                libc::sigaddset(&mut set, s);
            }
            if libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut()) != 0 {
                return;
            }
            set
        };
        let waiter = std::thread::Builder::new()
            .name("signals".into())
            .spawn(move || {
                let mut signal = 0;
                // SAFETY: a valid signal set and an out pointer to a local.
                while unsafe { libc::sigwait(&set, &mut signal) } != 0 {}
                let _swap = swap_guard();
                for p in live().iter() {
                    let _ = remove_any(p);
                }
                for d in CREATED
                    .lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .iter()
                {
                    let _ = fs::remove_dir(d);
                }
                std::process::exit(128 + signal);
            });
        if waiter.is_err() {
            // No thread to take them: let the signals act as before.
            // SAFETY: as above.
            unsafe { libc::pthread_sigmask(libc::SIG_UNBLOCK, &set, std::ptr::null_mut()) };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_entry_is_stale_only_when_no_one_holds_its_lock() {
        let tmp = tempfile::tempdir().unwrap();
        let held = Staging::create(tmp.path(), true).unwrap();
        let held_file = Staging::create(tmp.path(), false).unwrap();
        assert!(is_staging_name(
            &held.path().file_name().unwrap().to_string_lossy()
        ));
        // Left by a killed run: created, never locked.
        let stale = tmp.path().join(format!("{PREFIX}{:016x}{SUFFIX}", 7));
        fs::create_dir(&stale).unwrap();
        fs::write(stale.join("f"), "x").unwrap();
        // Not ours by name.
        let other = tmp.path().join(".purcell-sim-notes.tmp");
        fs::write(&other, "mine").unwrap();
        remove_stale(tmp.path());
        assert!(!stale.exists());
        assert!(held.path().exists() && held_file.path().exists() && other.exists());
        let p = held.path().to_path_buf();
        drop(held);
        assert!(!p.exists());
    }
}
