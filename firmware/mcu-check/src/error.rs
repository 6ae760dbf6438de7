//! Why a host-side check failed (the one error type of the checker's modules).

use std::fmt;

/// Why a host-side check failed.
#[derive(Debug, Clone, PartialEq)]
pub enum HostError {
    /// The core refused the gait or a step failed.
    Core(purcell_core::Error),
    /// The firmware log lacks a line or a field, or a value does not parse.
    Log(String),
    /// The firmware and the host disagree, or a budget is exceeded.
    Mismatch(String),
    /// The disassembly lacks the root function, or reaches what it must not.
    Disassembly(String),
}

impl fmt::Display for HostError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            HostError::Core(e) => write!(f, "gait: {e}"),
            HostError::Log(m) => write!(f, "firmware log: {m}"),
            HostError::Mismatch(m) => write!(f, "mismatch: {m}"),
            HostError::Disassembly(m) => write!(f, "disassembly: {m}"),
        }
    }
}

impl std::error::Error for HostError {}

impl From<purcell_core::Error> for HostError {
    fn from(e: purcell_core::Error) -> Self {
        HostError::Core(e)
    }
}
