//! What a subcommand asks of an output path ([`Claim`]).

use std::path::{Path, PathBuf};

/// What a subcommand asks of an output path: `command` writes `path`, replacing what is
/// there only as [`OutputDir::prepare`](super::OutputDir::prepare) and
/// [`OutputFile::prepare`](super::OutputFile::prepare) allow (more of it with
/// `force`), and `path` never is or holds one of `inputs`.
#[derive(Clone, Debug)]
pub struct Claim {
    /// The path as given (messages name it so).
    pub path: PathBuf,
    /// The subcommand that writes it.
    pub command: &'static str,
    /// Whether what is there may be replaced though not ours.
    pub force: bool,
    /// The command's inputs.
    pub inputs: Vec<PathBuf>,
}

impl Claim {
    /// `command` writes `path`, `force`d or not, reading `inputs`.
    pub fn new(path: &Path, command: &'static str, force: bool, inputs: &[&Path]) -> Self {
        let inputs = inputs.iter().map(|p| p.to_path_buf()).collect();
        let path = path.to_path_buf();
        Claim {
            path,
            command,
            force,
            inputs,
        }
    }
}
