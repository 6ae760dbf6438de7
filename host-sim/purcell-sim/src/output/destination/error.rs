//! Why an output was refused or could not be written.

use std::io;
use std::path::{Path, PathBuf};

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

pub(super) fn io_error(path: &Path, what: &'static str) -> impl FnOnce(io::Error) -> OutputError {
    let path = path.to_path_buf();
    move |source| OutputError::Io { path, what, source }
}
