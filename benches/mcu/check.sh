#!/usr/bin/env bash
# Flies the firmware in QEMU on three boards and checks it against the host (issues 4, 14):
#  - M4F (mps2-an386), f32: digest and final state bit-identical to the host f32 replay of
#    the same costate, mean and largest step <= PURCELL_MCU_MAX_INSN instructions (default
#    685, issue 14's target), stack of a step <= 2048 B, no soft-float helper reachable from
#    the step;
#  - M7 (mps2-an500), f64: bit-identical to the host f64 replay, <= PURCELL_M7_MAX_INSN
#    (default 1200, a regression guard), no soft-float helper reachable from the step;
#  - M3 (mps2-an385, no FPU), f32 in software floating point: bit-identical to the host f32
#    replay (and so to the M4F), <= PURCELL_M3_MAX_INSN (default 36000, a regression guard);
#  - the M7 build run on the M4F board must exit 1 through the HardFault handler.
# Needs qemu-system-arm, defmt-print, arm-none-eabi-objdump/-size (binutils-arm-none-eabi)
# and the thumbv7em-none-eabihf and thumbv7m-none-eabi targets. Logs and listings go to
# $TARGET/mcu-check/.
set -euo pipefail
cd "$(dirname "$0")/../.."

target_dir=${CARGO_TARGET_DIR:-$PWD/target}
out=$target_dir/mcu-check
mkdir -p "$out"
objdump=${OBJDUMP:-arm-none-eabi-objdump}
size=${SIZE:-arm-none-eabi-size}
for tool in "${QEMU:-qemu-system-arm}" "${DEFMT_PRINT:-defmt-print}" "$objdump" "$size"; do
  command -v "$tool" >/dev/null || { echo "check.sh: $tool not found (see benches/mcu/README.md)" >&2; exit 1; }
done

tool() { cargo run -q -p purcell-mcu -- "$@"; }

# $1 name, $2 ELF, $3 max insn/step (mean and largest step), $4 extra `disasm` flags (the M3
# has no FPU: --soft-float lists the helpers instead of failing); then the cargo command
# that runs the firmware.
fly() {
  local name=$1 elf=$2 max=$3 disasm_flags=$4
  shift 4
  echo "--- $name: $*"
  "$@" 2>"$out/$name.stderr" | tee "$out/$name.log"
  tool check "$out/$name.log" --max-insn "$max" --max-stack 2048
  "$objdump" -d "$elf" >"$out/$name.dis"
  # shellcheck disable=SC2086
  tool disasm "$out/$name.dis" $disasm_flags | grep -v '^  reachable:'
  echo "flash: $name $("$size" -A "$elf" | awk '$1 == ".text" || $1 == ".rodata" || $1 == ".vector_table" {s[$1] = $2} END {printf ".text=%d .rodata=%d .vector_table=%d bytes", s[".text"], s[".rodata"], s[".vector_table"]}')"
}

m4f=$target_dir/thumbv7em-none-eabihf/release/purcell-mcu
m7=$target_dir/thumbv7em-none-eabihf/mcu-m7/purcell-mcu
m3=$target_dir/thumbv7m-none-eabi/release/purcell-mcu
fly m4f "$m4f" "${PURCELL_MCU_MAX_INSN:-685}" "" \
  cargo run -q -p purcell-mcu --target thumbv7em-none-eabihf --release
fly m7 "$m7" "${PURCELL_M7_MAX_INSN:-1200}" "" cargo -q mcu-m7
fly m3 "$m3" "${PURCELL_M3_MAX_INSN:-36000}" --soft-float cargo -q mcu-m3

echo "--- fault: the M7 (double-precision) build on the M4F board must exit 1 via HardFault"
set +e
PURCELL_QEMU_MACHINE=mps2-an386 PURCELL_QEMU_TIMEOUT=60 benches/mcu/qemu-run.sh "$m7" >"$out/fault.log" 2>&1
status=$?
set -e
if [[ $status -ne 1 ]] || ! grep -q '^HardFault at pc=' "$out/fault.log"; then
  echo "check.sh: expected exit 1 with a HardFault line, got status $status:" >&2
  cat "$out/fault.log" >&2
  exit 1
fi
grep '^HardFault' "$out/fault.log"
echo "mcu: 4 passed, 0 failed"
