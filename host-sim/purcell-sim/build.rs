//! Sets `PURCELL_SIM_VERSION` for `--version`: the package's version and, in a git checkout
//! with git at hand, the commit (`0.1.0 (abc1234)`); the version alone otherwise.

use std::path::Path;
use std::process::Command;

/// `git ARGS` in this package's directory, its trimmed output if it succeeds.
fn git(args: &[&str]) -> Option<String> {
    let dir = std::env::var("CARGO_MANIFEST_DIR").ok()?;
    let out = Command::new("git")
        .args(args)
        .current_dir(dir)
        .output()
        .ok()?;
    let text = String::from_utf8(out.stdout).ok()?;
    (out.status.success() && !text.trim().is_empty()).then(|| text.trim().to_string())
}

fn main() {
    let version = env!("CARGO_PKG_VERSION");
    println!("cargo:rerun-if-changed=build.rs");
    let commit = git(&["rev-parse", "--short", "HEAD"]);
    match &commit {
        Some(c) => println!("cargo:rustc-env=PURCELL_SIM_VERSION={version} ({c})"),
        None => println!("cargo:rustc-env=PURCELL_SIM_VERSION={version}"),
    }
    if commit.is_none() {
        return;
    }
    // Run again when HEAD moves: HEAD itself, the branch it names, the packed refs.
    let branch = git(&["symbolic-ref", "-q", "HEAD"]);
    let watched = ["HEAD", branch.as_deref().unwrap_or("HEAD"), "packed-refs"];
    for name in watched {
        if let Some(path) = git(&["rev-parse", "--path-format=absolute", "--git-path", name])
            && Path::new(&path).exists()
        {
            println!("cargo:rerun-if-changed={path}");
        }
    }
}
