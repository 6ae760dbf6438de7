#!/usr/bin/env bash
# Copies this board example out of the repository, ready to build with no edit: its tracked
# files into DEST (a new directory), purcell-core and purcell-fly as packaged (`cargo
# package`) into DEST/vendor/ and patched in for crates.io in DEST/Cargo.toml (the manifest's
# dependencies by version only, as on crates.io), and the paper's gait as DEST/paper.gait,
# the default PURCELL_GAIT. tests/packaged.sh builds such a copy.
# Usage: firmware/board-stm32f4-discovery/copy-out.sh DEST
set -euo pipefail
[[ $# -eq 1 ]] || { echo "usage: copy-out.sh DEST" >&2; exit 2; }
dest=$1
board=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$board/../.." && pwd)
if [[ -e $dest ]]; then
  echo "copy-out.sh: $dest exists; give a new directory" >&2
  exit 2
fi
crates=(purcell-core purcell-fly)
args=()
for crate in "${crates[@]}"; do args+=(-p "$crate"); done
(cd "$root" && cargo package -q --no-verify --allow-dirty "${args[@]}")
mkdir -p "$dest/vendor"
(cd "$board" && git ls-files -z . ':!copy-out.sh' | xargs -0 cp --parents -t "$dest")
sed -i -E '/^purcell-/ s/, path = "[^"]*"//' "$dest/Cargo.toml"
printf '\n# The packaged crates (copy-out.sh): remove for crates.io.\n[patch.crates-io]\n' >>"$dest/Cargo.toml"
target=${CARGO_TARGET_DIR:-$root/target}
for crate in "${crates[@]}"; do
  version=$(cd "$root" && cargo metadata --format-version 1 --no-deps |
    python3 -c "import json, sys; print(next(p['version'] for p in json.load(sys.stdin)['packages'] if p['name'] == '$crate'))")
  tar -xzf "$target/package/$crate-$version.crate" -C "$dest/vendor"
  echo "$crate = { path = \"vendor/$crate-$version\" }" >>"$dest/Cargo.toml"
done
cp "$root/core/examples/paper.gait" "$dest/paper.gait"
sed -i 's|value = "../../core/examples/paper.gait"|value = "paper.gait"|' "$dest/.cargo/config.toml"
if grep -n '\.\./' "$dest/Cargo.toml" "$dest/.cargo/config.toml" >&2; then
  echo "copy-out.sh: the copy still points into the repository (above)" >&2
  exit 1
fi
echo "copied to $dest: cd $dest && cargo build --release (cargo run --release flashes a board)"
