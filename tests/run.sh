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
cargo test --workspace
step "core for the MCU (thumbv7em-none-eabihf)"
cargo build -p purcell-core --target thumbv7em-none-eabihf --release
cargo build -p purcell-core --target thumbv7em-none-eabihf --release --features defmt
step "firmware in QEMU: M4F f32 and M7 f64, bit-identical to the host, instruction budget"
bash benches/mcu/check.sh
