#!/usr/bin/env bash
# The crates a user depends on, as crates.io and docs.rs would ship them:
#  1. `cargo package` of the crates in CRATES (together, so that one may depend on another
#     before either is published) fails on any warning;
#  2. each package, unpacked in a temporary folder outside the repository with the others
#     patched in for crates.io, compiles on its own, and so does its documentation, with every
#     feature on (as docs.rs builds it: [package.metadata.docs.rs] all-features) and warnings
#     denied;
#  3. a copy of the board example made by its copy-out.sh (its dependencies on these crates
#     by version only, the packages patched in from the copy's vendor/) builds for
#     thumbv7em-none-eabihf with no edit: nothing in the packages points back into the
#     repository.
# Run by tests/run.sh. A new user-facing crate: one word in CRATES (and in the board's
# dependencies if the board uses it).
#
# The packages are unpacked here rather than verified by `cargo package`: cargo unpacks what
# it verifies into $CARGO_HOME and reuses that, and what it built from it, for the same
# version, so a second run would verify the first run's sources.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
CRATES=(purcell-core purcell-fly purcell-capi)

target=${CARGO_TARGET_DIR:-$root/target}
args=()
for crate in "${CRATES[@]}"; do args+=(-p "$crate"); done
package=$(cargo package --no-verify "${args[@]}" --allow-dirty 2>&1) || { echo "$package"; exit 1; }
if grep -q '^warning' <<<"$package"; then
  echo "$package"
  echo "packaged.sh: cargo package warned" >&2
  exit 1
fi
grep '^ *Packaged' <<<"$package"

dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
mkdir "$dir/.cargo" "$dir/packages"
echo '[patch.crates-io]' >"$dir/.cargo/config.toml"
unpacked=()
for crate in "${CRATES[@]}"; do
  version=$(cargo metadata --format-version 1 --no-deps |
    python3 -c "import json, sys; print(next(p['version'] for p in json.load(sys.stdin)['packages'] if p['name'] == '$crate'))")
  tar -xzf "$target/package/$crate-$version.crate" -C "$dir/packages"
  unpacked+=("$dir/packages/$crate-$version")
  echo "$crate = { path = \"$dir/packages/$crate-$version\" }" >>"$dir/.cargo/config.toml"
done
# Each package compiles and documents on its own (in this folder, so the patches apply; the
# same flags for both, so their dependencies are checked once).
(
  cd "$dir"
  export RUSTFLAGS="-D warnings" RUSTDOCFLAGS="-D warnings" CARGO_TARGET_DIR=$target/packaged
  for package_dir in "${unpacked[@]}"; do
    cargo check -q --all-features --manifest-path "$package_dir/Cargo.toml"
    cargo doc -q --no-deps --all-features --manifest-path "$package_dir/Cargo.toml"
  done
)

board=$root/firmware/board-stm32f4-discovery
# What a user does (the board's README): copy-out.sh, then cargo build, no edit. Into a
# folder of its own: the patches above are not the copy's.
copy=$(mktemp -d)
trap 'rm -rf "$dir" "$copy"' EXIT
bash "$board/copy-out.sh" "$copy/board" >/dev/null
# The board's build dir (its dependencies are built already: tests/run.sh builds it first).
board_target=${CARGO_TARGET_DIR:-$board/target}
(cd "$copy/board" && CARGO_TARGET_DIR=$board_target cargo build -q --release --bins --examples)
echo "packaged: ${CRATES[*]} compile and document as packaged; a copy of the board example outside the repository builds against them"
