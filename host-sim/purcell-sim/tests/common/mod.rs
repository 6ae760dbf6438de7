//! The kit of the `purcell-sim` command-line tests: running the binary, each run under a
//! time limit so that no input can hang the suite, and checking what it did; `solve`'s
//! argument lists ([`Solve`]); the costate files the tests start from ([`fixtures`]).
//! (Each test crate uses a part of it.)
#![allow(dead_code, unused_imports)]

pub mod fixtures;
mod solve;

pub use solve::Solve;

use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Output, Stdio};
use std::time::{Duration, Instant};

/// Time limit of one run of the binary (the longest test run, the paper's problem, takes a
/// few seconds).
pub const LIMIT: Duration = Duration::from_secs(120);

/// The binary, with its output captured.
pub fn command(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_purcell-sim"));
    c.args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    c
}

/// Waits for `child` at most `limit`; kills it and panics ("hung") after that.
pub fn wait(mut child: Child, limit: Duration, what: &str) -> Output {
    let pipe = |r: Option<Box<dyn Read + Send>>| {
        std::thread::spawn(move || {
            let mut buf = Vec::new();
            if let Some(mut r) = r {
                let _ = r.read_to_end(&mut buf);
            }
            buf
        })
    };
    let out = pipe(
        child
            .stdout
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let err = pipe(
        child
            .stderr
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let t0 = Instant::now();
    let status: ExitStatus = loop {
        if let Some(s) = child.try_wait().expect("wait") {
            break s;
        }
        if t0.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what}: still running after {limit:?} (hung)");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    Output {
        status,
        stdout: out.join().unwrap_or_default(),
        stderr: err.join().unwrap_or_default(),
    }
}

/// Runs the binary with `args` in `dir` (the current directory if `None`) within `limit`.
pub fn sim_in(dir: Option<&Path>, args: &[&str], limit: Duration) -> Output {
    let mut c = command(args);
    if let Some(d) = dir {
        c.current_dir(d);
    }
    wait(c.spawn().expect("binary runs"), limit, &format!("{args:?}"))
}

/// Runs the binary with `args` within [`LIMIT`].
pub fn sim(args: &[&str]) -> Output {
    sim_in(None, args, LIMIT)
}

/// What the run wrote on stderr.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// What the run wrote on stdout.
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Asserts that the run exited with `code` and said `needle` on stderr (`""`: anything).
#[track_caller]
pub fn assert_exit(o: &Output, code: i32, needle: &str) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(code), "{e}");
    assert!(e.contains(needle), "{needle:?} not in: {e}");
}

/// `path` as a command-line argument (the tests' paths are UTF-8).
pub fn arg(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 path")
}

/// The JSON report of `robustness --gait gait --json` with `args` (exit 0).
pub fn robustness_json(gait: &str, args: &[&str]) -> serde_json::Value {
    let mut all = vec!["robustness", "--gait", gait, "--json"];
    all.extend_from_slice(args);
    let o = sim(&all);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    serde_json::from_slice(&o.stdout).unwrap()
}

/// The `report.json` in `dir`.
pub fn report(dir: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(dir.join("report.json")).unwrap()).unwrap()
}

/// Writes `text` to `dir/name`; its path as an argument.
pub fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    arg(&p).to_string()
}

/// The `digest: 0x…` lines of a replay's output (each `0x` and 16 hex digits).
pub fn digests(o: &Output) -> Vec<String> {
    let text = stdout(o);
    let lines: Vec<String> = text
        .lines()
        .filter_map(|l| l.strip_prefix("digest: "))
        .map(str::to_string)
        .collect();
    for d in &lines {
        let hex = d.strip_prefix("0x").unwrap_or_else(|| panic!("{d}"));
        assert!(
            hex.len() == 16 && hex.chars().all(|c| c.is_ascii_hexdigit()),
            "{d}"
        );
    }
    lines
}

/// The files directly in `dir` by name, with their contents.
pub fn read_dir(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect()
}

/// Every file under `dir` with its contents, sorted (symbolic links by their target).
pub fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    fn walk(dir: &Path, prefix: &str, out: &mut Vec<(String, Vec<u8>)>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let e = e.unwrap();
            let name = format!("{prefix}{}", e.file_name().to_string_lossy());
            let kind = e.file_type().unwrap();
            if kind.is_dir() {
                out.push((format!("{name}/"), Vec::new()));
                walk(&e.path(), &format!("{name}/"), out);
            } else if kind.is_symlink() {
                let t = std::fs::read_link(e.path()).unwrap();
                out.push((name, t.to_string_lossy().as_bytes().to_vec()));
            } else {
                out.push((name, std::fs::read(e.path()).unwrap()));
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, "", &mut out);
    out.sort();
    out
}

/// A process holding an exclusive `flock` on `path` (`flock(1)`) until dropped, as a live run
/// holds its staging entry.
pub struct LockHolder(std::process::Child);

/// Starts a [`LockHolder`] on `path` and waits until it holds the lock.
pub fn hold_lock(path: &Path) -> LockHolder {
    let ready = path.with_extension("locked");
    let child = Command::new("flock")
        .arg("--exclusive")
        .arg(path)
        .args(["sh", "-c", "touch \"$0\"; exec sleep 600"])
        .arg(&ready)
        .spawn()
        .expect("flock(1) (util-linux) runs");
    let t0 = std::time::Instant::now();
    while !ready.exists() {
        assert!(
            t0.elapsed() < Duration::from_secs(30),
            "flock(1) never locked"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    let _ = std::fs::remove_file(&ready);
    LockHolder(child)
}

impl Drop for LockHolder {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// The hidden staging entries in `dir`.
pub fn staging(dir: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let n = p.file_name().unwrap().to_string_lossy();
            n.starts_with(".purcell-sim-") && n.ends_with(".tmp")
        })
        .collect()
}

/// Runs `sh -c script` with the binary as `$0` and `args` after it, within `limit`.
pub fn shell(script: &str, args: &[&str], limit: Duration) -> Output {
    let child = Command::new("sh")
        .arg("-c")
        .arg(script)
        .arg(env!("CARGO_BIN_EXE_purcell-sim"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait(child, limit, script)
}

/// The gait at rest (`μ = 0`, `ξ = 0`: it flies every step) of `steps` steps, without
/// checkpoints, as a gait file.
pub fn gait_with_steps(steps: u32) -> Vec<u8> {
    let mut file = purcell_sim::costate_file::CostateFile::parse(fixtures::COSTATE_V2).unwrap();
    (file.gait.mu, file.gait.xi0) = ([0.0; 3], [0.0; 2]);
    file.gait.steps = steps;
    file.gait.checkpoint_every = 0;
    file.checkpoints.clear();
    file.to_gait().unwrap()
}

/// `export --tracking` of the core's small joint-limited test gait to `out` (a gait with a
/// tracking table); panics if it fails.
pub fn export_tracking(out: &Path) {
    let gait = fixtures::core_data("tiny-limit.gait");
    let o = sim(&[
        "export",
        "--gait",
        arg(&gait),
        "--tracking",
        "--out",
        arg(out),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}
