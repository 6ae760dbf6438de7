//! Running the `purcell-sim` binary from tests, each run under a time limit so that no input
//! can hang the suite.
#![allow(dead_code)]

use std::io::Read;
use std::path::Path;
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

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A problem that `solve` answers in about 0.1 s (100 steps, one start).
pub const QUICK: &[&str] = &[
    "--horizon",
    "10",
    "--step",
    "0.1",
    "--target",
    "0.01,0.01,0",
    "--starts",
    "1",
];

/// `solve` of [`QUICK`] into `out`, with `extra` flags.
pub fn quick_solve(out: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["solve", "--out", out.to_str().unwrap()];
    args.extend_from_slice(QUICK);
    args.extend_from_slice(extra);
    sim(&args)
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
