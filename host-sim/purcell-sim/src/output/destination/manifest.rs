//! The manifest each output directory of ours holds: every file written, with its length
//! and FNV-1a hash, so that the next run recognises the directory as ours.

use serde::{Deserialize, Serialize};
use std::fs;
use std::io;
use std::path::Path;

/// The manifest each output directory holds, naming every file the tool wrote into it.
pub const MANIFEST: &str = "purcell-sim-manifest.json";
/// The manifest's `format` tag.
const FORMAT: &str = "purcell-sim-output";
/// The only manifest version this build reads and writes.
const VERSION: u64 = 1;

/// One file as the manifest records it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Entry {
    /// Path relative to the output directory, `/`-separated.
    pub(super) name: String,
    /// Length in bytes.
    bytes: u64,
    /// FNV-1a 64 of the contents, 16 hex digits.
    fnv1a64: String,
}

impl Entry {
    pub(super) fn of(name: &str, contents: &[u8]) -> Self {
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
pub(super) struct Manifest {
    format: String,
    version: u64,
    /// `purcell-sim <version>`, for people reading it.
    written_by: String,
    /// The subcommand that wrote the directory.
    pub(super) command: String,
    pub(super) files: Vec<Entry>,
}

impl Manifest {
    pub(super) fn new(command: &str, files: Vec<Entry>) -> Self {
        Manifest {
            format: FORMAT.into(),
            version: VERSION,
            written_by: concat!("purcell-sim ", env!("CARGO_PKG_VERSION")).into(),
            command: command.into(),
            files,
        }
    }

    /// The manifest in `bytes`, if it is one of ours of this version.
    pub(super) fn parse(bytes: &[u8]) -> Option<Self> {
        crate::input::json::<Manifest>(bytes)
            .ok()
            .filter(|m| m.format == FORMAT && m.version == VERSION)
    }

    pub(super) fn to_bytes(&self) -> Vec<u8> {
        let mut text = serde_json::to_string_pretty(self).unwrap_or_default();
        text.push('\n');
        text.into_bytes()
    }

    pub(super) fn lists(&self, name: &str) -> bool {
        self.files.iter().any(|e| e.name == name)
    }

    /// Whether the file `name` of length `len` holds what we wrote (read only if the
    /// length matches one of the entries).
    pub(super) fn matches(&self, name: &str, len: u64, path: &Path) -> io::Result<bool> {
        let entries: Vec<&Entry> = self
            .files
            .iter()
            .filter(|e| e.name == name && e.bytes == len)
            .collect();
        if entries.is_empty() {
            return Ok(false);
        }
        let hash = format!("{:016x}", fnv1a64_file(path)?);
        Ok(entries.iter().any(|e| e.fnv1a64 == hash))
    }
}

/// FNV-1a, 64 bit: detects a changed file, does not resist forgery.
pub(crate) fn fnv1a64(bytes: &[u8]) -> u64 {
    fnv1a64_from(0xcbf2_9ce4_8422_2325, bytes)
}

fn fnv1a64_from(h: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(h, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// [`fnv1a64`] of a file's contents, read in blocks (bounded memory at any size).
fn fnv1a64_file(path: &Path) -> io::Result<u64> {
    use std::io::Read as _;
    let mut f = fs::File::open(path)?;
    let (mut h, mut buf) = (fnv1a64(&[]), vec![0; 1 << 16]);
    loop {
        match f.read(&mut buf)? {
            0 => return Ok(h),
            n => h = fnv1a64_from(h, buf.get(..n).unwrap_or_default()),
        }
    }
}
