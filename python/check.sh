#!/usr/bin/env bash
# The Python package's checks (run by tests/run.sh): format and lints of the crate (its own
# workspace and lock file), the abi3 wheel built by maturin, installed in a fresh virtual
# environment with numpy, pytest, pandas, jsonschema and Dask, pytest against the
# workspace's purcell-sim, ruff.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root/python"
bash tools.sh
tools=${PURCELL_PY_TOOLS:-$root/target/python-tools}
venv=$root/target/python-venv
# maturin's own default for this crate (python/README.md installs from there).
wheels=$root/python/target/wheels

cargo fmt --check
"$tools/bin/ruff" check .
"$tools/bin/ruff" format --check .

rm -rf "$wheels"
# Clippy lints the crate (its one target, the library) while maturin builds it: clippy-driver
# is cargo's wrapper for the workspace's own crate only, and `-D warnings` goes to that crate
# alone (maturin's trailing rustc flags). A separate `cargo clippy` would check every
# dependency a second time (about 80 CPU-s of the wheel's build, cold).
RUSTC_WORKSPACE_WRAPPER=clippy-driver "$tools/bin/maturin" build -q --release --locked -o "$wheels" -- -D warnings
python3 -m venv --clear "$venv"
# pandas (Sweep.to_pandas; test_outputs reads trajectory.csv and sweep.csv with it),
# jsonschema (the JSON outputs against docs/schemas), Dask distributed (purcell.distributed's
# test on a LocalCluster) and matplotlib (the examples): about 15 s more with pip's cache warm.
"$venv/bin/pip" install -q "$wheels"/purcell-*.whl pytest pandas jsonschema 'dask[distributed]' matplotlib

# The command line the tests compare with: the workspace's, in the test profile.
(cd "$root" && cargo build -q --profile test -p purcell-sim)
target=$(cd "$root" && cargo metadata --format-version 1 --no-deps |
  python3 -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')
# Run from tests/ so that the source tree's purcell/ (no native module) is not imported.
cd tests
PURCELL_SIM=$target/debug/purcell-sim "$venv/bin/python" -m pytest -q -p no:cacheprovider --durations=8

# The examples, from the package alone (the atlas on a small lattice, short horizon, on a
# local Dask cluster of two workers): the paper's figures and the cost map.
examples=$root/target/python-examples
"$venv/bin/python" "$root/python/examples/paper_figures.py" --out "$examples/paper"
"$venv/bin/python" "$root/python/examples/atlas.py" --x=-0.1:0.1:3 --y=0:0.2:3 \
  --horizon 10 --step 0.05 --dask 2 --out "$examples/atlas"
