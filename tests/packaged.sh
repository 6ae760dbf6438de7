#!/usr/bin/env bash
# The crates a user depends on, as crates.io and docs.rs would ship them:
#  1. `cargo package` of each crate in CRATES (together, so that one may depend on another
#     before either is published) fails on any warning, and so does their documentation with
#     every feature on (docs.rs builds it so: [package.metadata.docs.rs] all-features);
#  2. a copy of the board example (firmware/board-stm32f4-discovery) in a temporary folder
#     outside the repository, its dependencies on these crates by version only and patched to
#     the unpacked packages (target/package/<crate>-<version>/), builds for
#     thumbv7em-none-eabihf: nothing in the packages points back into the repository.
# Run by tests/run.sh. A new user-facing crate: one word in CRATES (and in the board's
# dependencies if the board uses it).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
CRATES=(purcell-core purcell-fly)

target=${CARGO_TARGET_DIR:-$root/target}
args=()
for crate in "${CRATES[@]}"; do args+=(-p "$crate"); done
package=$(cargo package "${args[@]}" --allow-dirty 2>&1) || { echo "$package"; exit 1; }
if grep -q '^warning' <<<"$package"; then
  echo "$package"
  echo "packaged.sh: cargo package warned" >&2
  exit 1
fi
grep '^ *Packaged' <<<"$package"
RUSTDOCFLAGS="-D warnings" cargo doc -q --no-deps --all-features "${args[@]}"

dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
board=$root/firmware/board-stm32f4-discovery
cp -r "$board/." "$dir/"
rm -rf "$dir/target"
# The repository's path dependencies go; each packaged crate comes in through a patch.
sed -i -E '/^purcell-/ s/, path = "[^"]*"//' "$dir/Cargo.toml"
if grep -q 'path = ' "$dir/Cargo.toml"; then
  echo "packaged.sh: the board's manifest still has a path dependency:" >&2
  grep 'path = ' "$dir/Cargo.toml" >&2
  exit 1
fi
echo '[patch.crates-io]' >>"$dir/Cargo.toml"
for crate in "${CRATES[@]}"; do
  version=$(cargo metadata --format-version 1 --no-deps |
    python3 -c "import json, sys; print(next(p['version'] for p in json.load(sys.stdin)['packages'] if p['name'] == '$crate'))")
  echo "$crate = { path = \"$target/package/$crate-$version\" }" >>"$dir/Cargo.toml"
done
# The board's build dir (its dependencies are built already, tests/run.sh builds it first).
board_target=${CARGO_TARGET_DIR:-$board/target}
(cd "$dir" && PURCELL_GAIT=$root/core/examples/paper.gait CARGO_TARGET_DIR=$board_target \
  cargo build -q --release --bins --examples)
echo "packaged: a copy of the board example outside the repository builds against ${CRATES[*]} as packaged"
