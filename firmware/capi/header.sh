#!/usr/bin/env bash
# Writes the C API's header include/purcell.h from the crate's sources with cbindgen 0.29.4
# (cbindgen.toml); with --check, fails instead if the committed header differs from what the
# sources generate (CI). .ci/run installs cbindgen when it is missing.
set -euo pipefail
cd "$(dirname "$0")"
if [[ $(cbindgen --version 2>/dev/null) != "cbindgen 0.29.4" ]]; then
  echo "header.sh: needs cbindgen 0.29.4: cargo install cbindgen --locked --version 0.29.4" >&2
  exit 1
fi
header=include/purcell.h
if [[ ${1:-} == --check ]]; then
  fresh=$(mktemp)
  trap 'rm -f "$fresh"' EXIT
  cbindgen --quiet --config cbindgen.toml --output "$fresh" .
  if ! cmp -s "$fresh" "$header"; then
    diff -u "$header" "$fresh" >&2 || true
    echo "header.sh: firmware/capi/$header is not what the sources generate: run firmware/capi/header.sh" >&2
    exit 1
  fi
  echo "header.sh: firmware/capi/$header is what cbindgen generates from the sources"
else
  cbindgen --quiet --config cbindgen.toml --output "$header" .
  echo "header.sh: wrote firmware/capi/$header"
fi
