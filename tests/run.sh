#!/usr/bin/env bash
# The project's test command (see README.md). Run from anywhere; fails on the first failure.
set -euo pipefail
cd "$(dirname "$0")/.."
# Every stage builds from scratch on a fresh clone: without incremental compilation (its
# cache, and 256 codegen units per crate at opt-level 3) the host tests' workspace crates
# build in 184 CPU-s instead of 212, purcell-solver's library in 23 instead of 29.
export CARGO_INCREMENTAL=0

step() { printf '\n=== %s\n' "$*"; }

step "format"
cargo fmt --all --check
step "lints"
cargo clippy --workspace --all-targets -- -D warnings
step "docs"
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --quiet
step "tests (host)"
cargo test --workspace --exclude purcell-core
step "tests of the core, property tests with 10 000 cases each"
PROPTEST_CASES=10000 cargo test -p purcell-core
step "CasADi's step graph against MODEL.md §7's test vectors (peers/casadi_m4f/gen_step.py)"
python=${PURCELL_PYTHON:-python3}
if "$python" -c 'import casadi' 2>/dev/null; then
  "$python" -c 'import sys; sys.path.insert(0, "peers/casadi_m4f"); import gen_step; gen_step.self_check()'
  echo "gen_step.py self_check: A(0.5, -0.3) and one f64 step match MODEL.md §7"
else
  echo "skipped: $python cannot import casadi (.ci/run installs it in target/casadi-venv)"
fi
step "Python package (python/): fmt, clippy, ruff, the abi3 wheel by maturin in a fresh venv, pytest against purcell-sim"
bash python/check.sh
step "example: the committed paper's gait replayed on the host"
cargo run -q -p purcell-core --example replay_gait
step "core for the MCU (thumbv7em-none-eabihf)"
cargo build -p purcell-core --target thumbv7em-none-eabihf --release
cargo build -p purcell-core --target thumbv7em-none-eabihf --release --features defmt
msrv=$(sed -n 's/^rust-version = "\(.*\)"/\1/p' core/Cargo.toml).0
step "core and purcell-fly with their minimum Rust version $msrv (host and thumbv7em; .ci/run installs it)"
CARGO_TARGET_DIR=target/msrv cargo "+$msrv" build -q -p purcell-core --features serde
CARGO_TARGET_DIR=target/msrv cargo "+$msrv" build -q -p purcell-core -p purcell-fly --target thumbv7em-none-eabihf --features purcell-core/defmt
step "a program outside the workspace solves the paper's problem through purcell-solver"
bash tests/outside.sh
step "board example (STM32F4-Discovery at 168 MHz, flip-link; the flight and the control loop): format, lints, firmware build"
(cd firmware/board-stm32f4-discovery && cargo fmt --check &&
  cargo clippy -q --release --locked --bins --examples -- -D warnings &&
  cargo build -q --release --locked --bins --examples)
step "user-facing crates package without a warning; a copy of the board example outside the repository builds against the packages"
bash tests/packaged.sh
step "firmware in QEMU: exported gaits (solved, constrained, corrupted), M4F f32, M7 f64 and M3 soft-float f32, bit-identical to the host, budgets; the control loop; the C API example (M4F and host)"
bash firmware/check.sh
step "README.md's numbers, re-measured (tests/readme.py: a fresh solve, the committed gaits, the M4F log above)"
target_dir=${CARGO_TARGET_DIR:-target}
ruff=${PURCELL_PY_TOOLS:-$PWD/target/python-tools}/bin/ruff
cargo build -q --profile test -p purcell-sim
"$ruff" check tests/readme.py
"$ruff" format --check tests/readme.py
python3 tests/readme.py "$target_dir/debug/purcell-sim" "$target_dir/mcu-check"
step "every command the READMEs show, run as typed or by the stage above that runs it (tests/commands.py)"
"$ruff" check tests/commands.py
"$ruff" format --check tests/commands.py
python3 tests/commands.py "$target_dir/debug/purcell-sim"
fuzz_seconds=$(( (${PURCELL_FUZZ_SECONDS:=45} + 1) / 2 ))
step "fuzz the costate-file and gait-file readers for ${fuzz_seconds} s each, side by side (host-sim/purcell-sim/fuzz, nightly)"
# Unoptimised (--dev): builds in 40 % of the CPU time of a release build and still runs
# about 4 000 inputs/s; purcell-sim without its command line (fuzz/Cargo.toml). Both targets
# are built first, then run at once (each fuzzer is one process on one core); their logs are
# printed when both are done. New inputs go to a scratch corpus, not into the tree; the gait
# reader starts from the core's test gaits.
cd host-sim/purcell-sim
cargo +nightly fuzz build --dev --sanitizer none
scratch=$(mktemp -d)
pids=()
# On any exit (Ctrl-C too) a fuzzer still running is stopped and the scratch corpus removed.
trap 'kill "${pids[@]}" 2>/dev/null || true; rm -rf "$scratch"' EXIT
for target in "costate_file fuzz/seeds fuzz/costate.dict" "gait_file ../../core/tests/data fuzz/gait.dict"; do
  read -r name seeds dict <<<"$target"
  mkdir "$scratch/$name"
  cargo +nightly fuzz run "$name" --dev --sanitizer none "$scratch/$name" "$seeds" \
    -- -dict="$dict" -max_total_time="$fuzz_seconds" -max_len=4096 -rss_limit_mb=1024 \
    >"$scratch/$name.log" 2>&1 &
  pids+=("$!")
done
status=0
names=(costate_file gait_file)
for i in 0 1; do
  if wait "${pids[$i]}"; then tail -n 2 "$scratch/${names[$i]}.log"; else cat "$scratch/${names[$i]}.log"; status=1; fi
done
exit "$status"
