#!/usr/bin/env bash
# The project's test command (see README.md). Run from anywhere; fails on the first failure.
set -euo pipefail
cd "$(dirname "$0")/.."

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
step "core for the MCU (thumbv7em-none-eabihf)"
cargo build -p purcell-core --target thumbv7em-none-eabihf --release
cargo build -p purcell-core --target thumbv7em-none-eabihf --release --features defmt
step "firmware in QEMU: M4F f32 and M7 f64, bit-identical to the host, instruction budget"
bash benches/mcu/check.sh
step "fuzz the costate-file reader for ${PURCELL_FUZZ_SECONDS:=60} s (host-sim/fuzz, nightly)"
# Unoptimised (--dev): builds in 40 % of the CPU time of a release build and still runs
# about 4 000 inputs/s. New inputs go to a scratch corpus, not into the tree.
corpus=$(mktemp -d)
(cd host-sim && cargo +nightly fuzz run costate_file --dev --sanitizer none "$corpus" fuzz/seeds \
  -- -dict=fuzz/costate.dict -max_total_time="$PURCELL_FUZZ_SECONDS" -max_len=4096 \
  -rss_limit_mb=1024)
rm -rf "$corpus"
