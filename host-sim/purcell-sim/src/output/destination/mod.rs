//! Where results go, without ever losing a user's data: the one place every subcommand
//! writes its outputs through ([`OutputDir`] for a directory of files, [`OutputFile`] for one
//! file).
//!
//! - **Ours or nothing.** An existing output directory is replaced only if it is a previous
//!   result of ours: it holds our manifest ([`MANIFEST`], which names every file we wrote with
//!   its length and FNV-1a hash) and nothing else than those files, byte for byte as we wrote
//!   them (an empty directory holds nothing to lose and is replaced too). An existing single
//!   file is replaced only if its record beside it (`file`) lists exactly its contents, and
//!   a directory or file only by the subcommand that wrote it. Anything else is refused before any
//!   work ([`OutputError::Refused`]), unless `force`; symbolic links (`LINK/` included),
//!   device nodes and other special files, a directory where a file goes, a mount point,
//!   what this process cannot replace (another user's entry in a sticky directory, an
//!   immutable or unwritable directory) and a path that is or holds an input of the command
//!   (after symbolic links, `.` and `..`) are refused even then.
//! - **Checked before the work.** `prepare` creates the staging directory or file next to
//!   the path (and any missing parent directories), which proves the path can be written
//!   before a long computation; if the command fails, dropping the value removes what it
//!   created, and an interrupt removes it too (`staging`). Staging entries of runs that were
//!   killed (no process holds their lock) are removed then too.
//! - **Atomic.** `commit` writes everything into the staging entry, re-checks the path (it
//!   may have changed during the work), and swaps it in with one rename: a directory by
//!   `renameat2(RENAME_EXCHANGE)`, after which the old contents (now under the staging name)
//!   are removed; a file by `rename`, which replaces atomically. The new entry keeps the
//!   permissions of the one it replaces. Where the filesystem cannot exchange, the new files
//!   are renamed into the existing directory one by one under a manifest that lists the old
//!   and the new files at every moment: the path never goes missing, and a run interrupted
//!   half-way leaves a directory that the next run recognises as ours. Several single files
//!   ([`OutputFile::commit_all`]) are all written before any is renamed.
//!
//! Modules: `dir` writes a directory ([`OutputDir`]), `file` a single file ([`OutputFile`])
//! with its record; `classify` tells what a path holds now (missing, ours, or foreign and
//! why), `manifest` is the record that makes a directory or a file ours, `staging` the locked
//! staging entries and the interrupt handler, `disk` the filesystem steps (missing parents,
//! synced writes, `renameat2`), `error` the error ([`OutputError`]).

mod claim;
mod classify;
mod dir;
mod disk;
mod error;
mod file;
mod manifest;
mod staging;
#[cfg(test)]
mod tests;

pub use claim::Claim;
pub use dir::OutputDir;
pub use error::OutputError;
pub use file::OutputFile;
pub use manifest::MANIFEST;
pub(crate) use manifest::fnv1a64;
pub use staging::remove_staging_on_interrupt;
