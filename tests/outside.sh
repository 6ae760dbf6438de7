#!/usr/bin/env bash
# A program outside the workspace solves the paper's problem through purcell-solver (a path
# dependency, as another project would use it): prints J and checks it. Run by tests/run.sh.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
mkdir "$dir/src"
cat >"$dir/Cargo.toml" <<TOML
[package]
name = "outside"
version = "0.0.0"
edition = "2024"
publish = false

[dependencies]
purcell-solver = { path = "$root/host-sim/purcell-solver" }

[workspace]
TOML
cat >"$dir/src/main.rs" <<'RS'
use purcell_solver::problem::{Problem, Spec};
use purcell_solver::solver::{SolveOptions, solve};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let problem = Problem::new(&Spec::default())?;
    let solution = solve(&problem, &SolveOptions::default(), &|| {})?;
    let gait = &solution.extremals[solution.best];
    println!("J = {:.7}", gait.cost);
    Ok(())
}
RS
# The workspace's lock file pins the same versions.
cp "$root/Cargo.lock" "$dir/Cargo.lock"
out=$(cd "$dir" && CARGO_TARGET_DIR="$root/target/outside" cargo run -q --release)
echo "$out"
[[ $out == "J = 0.6817478" ]]
