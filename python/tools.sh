#!/usr/bin/env bash
# The Python tools python/check.sh builds and lints with (maturin, ruff), in a virtual
# environment of their own: target/python-tools, or $PURCELL_PY_TOOLS. Idempotent.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
tools=${PURCELL_PY_TOOLS:-$root/target/python-tools}
if "$tools/bin/maturin" --version >/dev/null 2>&1 && "$tools/bin/ruff" --version >/dev/null 2>&1; then
  exit 0
fi
python3 -m venv --clear "$tools"
"$tools/bin/pip" install -q 'maturin>=1.9,<2' 'ruff>=0.6'
