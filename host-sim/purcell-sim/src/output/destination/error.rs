//! Why an output was refused or could not be written.

use crate::words::{Front, Worded};
use std::io;
use std::path::{Path, PathBuf};

/// Why an output was refused or could not be written (`Display`: the command line's words).
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The path holds something the tool did not write (or must never replace).
    #[error("{}", self.words(Front::Cli))]
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

impl Worded for OutputError {
    fn words(&self, f: Front) -> String {
        match self {
            OutputError::Refused {
                path,
                reason,
                force_overrides,
            } => {
                let force = f.on("force");
                let remedy = match force_overrides {
                    true => format!("pass {force} to replace it anyway"),
                    false => format!("even with {force}"),
                };
                format!(
                    "{}: {reason}; refusing to replace it ({remedy})",
                    path.display()
                )
            }
            OutputError::Io { .. } => self.to_string(),
        }
    }
}

pub(super) fn io_error(path: &Path, what: &'static str) -> impl FnOnce(io::Error) -> OutputError {
    let path = path.to_path_buf();
    move |source| OutputError::Io { path, what, source }
}
