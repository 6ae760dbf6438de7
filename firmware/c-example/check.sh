#!/usr/bin/env bash
# The C example, checked against the host (called by firmware/check.sh; runs alone too):
#  0. the committed header firmware/capi/include/purcell.h is what cbindgen generates;
#  1. the committed paper's gait, exported with `purcell-sim export --format c`, flown by the
#     C firmware (fly.c, mps2.c, mps2-an386.ld; arm-none-eabi-gcc, freestanding, no libc)
#     linked against the thumbv7em-none-eabihf libpurcell_capi.a, in QEMU mps2-an386 under
#     -icount: its digest line must be `purcell-sim replay --gait … --precision f32`'s, its
#     instructions per step within PURCELL_C_MAX_INSN (mean, default 720) and
#     PURCELL_C_MAX_STEP_INSN (largest, default 800), regression guards printed beside the
#     Rust firmware's figures (firmware/check.sh's M4F log, when there is one), and the run's
#     deepest stack (open, steps, digest, terminal error) within PURCELL_C_MAX_STACK (2048 B);
#  2. no panic machinery linked into the firmware, so none reachable from the API, and no
#     soft-float helper reachable from purcell_flight_step (purcell-mcu-check disasm);
#  3. the same C program built with the host's gcc against the host's libpurcell_capi.a flies
#     the paper's gait, its constrained one (paper-limit.gait, arcs) and its power-optimal one
#     (paper-power.gait, the power's law) with the host's digest,
#     and refuses the paper's with its first byte changed (exit 1, the core's reason).
# Needs cbindgen 0.29.4 (step 0 only; the Makefile builds without it), make, arm-none-eabi-gcc
# (gcc-arm-none-eabi), binutils-arm-none-eabi, qemu-system-arm, gcc (.ci/run installs them).
# Builds go to $TARGET/c-example/.
set -euo pipefail
cd "$(dirname "$0")/../.."
target_dir=${CARGO_TARGET_DIR:-$PWD/target}
out=$target_dir/c-example
rm -rf "$out"
mkdir -p "$out"
src=firmware/c-example
sim() { cargo run -q --profile test -p purcell-sim -- "$@"; }
arm_cc=${ARM_CC:-arm-none-eabi-gcc}
objdump=${OBJDUMP:-arm-none-eabi-objdump}
nm=${NM:-arm-none-eabi-nm}
for tool in "$arm_cc" "$objdump" "$nm" "${QEMU:-qemu-system-arm}" "${CC:-gcc}"; do
  command -v "$tool" >/dev/null || { echo "c-example: $tool not found (see firmware/README.md)" >&2; exit 1; }
done
warn=(-std=c11 -O2 -Wall -Wextra -Werror -I firmware/capi/include -I "$src")

# $1 name, $2 gait file: its C source in $out/$1/ (gait.c, gait.h) and the host's digest line.
export_gait() {
  mkdir -p "$out/$1"
  sim export --gait "$2" --format c --out "$out/$1/gait.c" >/dev/null
  sim replay --gait "$2" --precision f32 | grep '^digest: ' >"$out/$1/host-digest"
}
# $1 name, $2 the C flight's log: its digest line must be the host's.
same_digest() {
  local host c
  host=$(cat "$out/$1/host-digest")
  c=$(grep '^digest: ' "$2" || true)
  if [[ $host != "$c" ]]; then
    echo "c-example: $1: purcell-sim replay says '$host', the C flight '$c'" >&2
    exit 1
  fi
}

echo "--- the C API's header"
firmware/capi/header.sh --check

echo "--- C firmware on the M4F (mps2-an386): the paper's gait through libpurcell_capi.a"
# The README's build: its Makefile (the library, the gait as C, the firmware).
export_gait paper core/examples/paper.gait
make=(make -s -C "$src" BUILD="$out/paper" TARGET_DIR="$target_dir" CC="$arm_cc"
  QEMU="${QEMU:-qemu-system-arm}" PURCELL_SIM="cargo run -q --profile test -p purcell-sim --")
"${make[@]}"
lib=$target_dir/thumbv7em-none-eabihf/release/libpurcell_capi.a
elf=$out/paper/c-example.elf
timeout "${PURCELL_QEMU_TIMEOUT:-300}" "${make[@]}" run 2>&1 | tee "$out/m4f.log"
same_digest paper "$out/m4f.log"
read -r mean max < <(sed -n 's/^insn_per_step: mean=\([0-9.]*\) max=\([0-9]*\).*/\1 \2/p' "$out/m4f.log")
stack=$(sed -n 's/^stack: bytes=\([0-9]*\).*/\1/p' "$out/m4f.log")
max_mean=${PURCELL_C_MAX_INSN:-720} max_step=${PURCELL_C_MAX_STEP_INSN:-800}
max_stack=${PURCELL_C_MAX_STACK:-2048}
if ! awk -v m="$mean" -v x="$max" -v s="$stack" -v bm="$max_mean" -v bx="$max_step" -v bs="$max_stack" \
  'BEGIN { exit !(m != "" && m <= bm && x <= bx && s != "" && s <= bs) }'; then
  echo "c-example: instructions per step mean=$mean max=$max, stack $stack B: over the budget" \
    "(mean $max_mean, largest $max_step, stack $max_stack B)" >&2
  exit 1
fi
rust=$(grep -h '^insn_per_step: ' "$target_dir/mcu-check/m4f.log" 2>/dev/null || echo "not measured (run firmware/check.sh)")
echo "instructions per step, paper's gait on the M4F: C through libpurcell_capi.a mean=$mean max=$max (budget $max_mean, $max_step); Rust firmware ${rust#insn_per_step: }"
echo "flash: c-example $(arm-none-eabi-size -A "$elf" | awk '$1 == ".text" || $1 == ".rodata" {s[$1] = $2} END {printf ".text=%d .rodata=%d bytes", s[".text"], s[".rodata"]}'); libpurcell_capi.a $(stat -c %s "$lib") bytes"

echo "--- the API's code in the C firmware: no panic machinery linked at all, a hard-float step"
# The linker keeps only what is reachable from the vector table (--gc-sections): no symbol
# naming a panic means no panic path from any function of the API. (With LTO the library
# itself has none either: its one object holds only what the API reaches.)
if "$nm" "$elf" "$lib" 2>/dev/null | grep -i panic >&2; then
  echo "c-example: panic machinery in the C firmware or libpurcell_capi.a (above)" >&2
  exit 1
fi
echo "no panic symbol among the $("$nm" "$elf" | wc -l) symbols of the C firmware, nor in libpurcell_capi.a"
"$objdump" -d "$elf" >"$out/c-example.dis"
cargo run -q -p purcell-mcu-check -- disasm "$out/c-example.dis" --root purcell_flight_step | grep -v '^  reachable:'

echo "--- the same C program on the host, against the host's libpurcell_capi.a"
# Built with purcell-sim, so that the core's features are the ones it was built with (nothing
# rebuilt); the libraries the host's Rust std needs, as
# `cargo rustc -p purcell-capi -- --print native-static-libs` lists them on Linux.
cargo build -q --profile test -p purcell-sim -p purcell-capi
host_lib=$target_dir/debug/libpurcell_capi.a
native=(-lgcc_s -lutil -lrt -lpthread -lm -ldl -lc)
export_gait limit core/examples/paper-limit.gait
export_gait power core/examples/paper-power.gait
for name in paper limit power; do
  "${CC:-gcc}" "${warn[@]}" -I "$out/$name" -o "$out/$name/host" "$src/host.c" "$src/fly.c" \
    "$out/$name/gait.c" "$host_lib" "${native[@]}"
  "$out/$name/host" | tee "$out/$name/host.log"
  same_digest "$name" "$out/$name/host.log"
done
# A gait whose first byte is not the magic's: refused through the API, with the core's reason.
mkdir -p "$out/refused"
cp "$out/paper/gait.h" "$out/refused/"
sed '0,/^    0x50,/s//    0x51,/' "$out/paper/gait.c" >"$out/refused/gait.c"
"${CC:-gcc}" "${warn[@]}" -I "$out/refused" -o "$out/refused/host" "$src/host.c" "$src/fly.c" \
  "$out/refused/gait.c" "$host_lib" "${native[@]}"
status=0
"$out/refused/host" >"$out/refused/host.log" || status=$?
if [[ $status -ne 1 ]] || ! grep -q '^failed: not a gait file (bad magic) (status -110)$' "$out/refused/host.log"; then
  echo "c-example: a gait without its magic: expected exit 1 and its reason, got status $status:" >&2
  cat "$out/refused/host.log" >&2
  exit 1
fi
cat "$out/refused/host.log"
echo "c-example: ok (header, M4F firmware, host program, a refused gait)"
