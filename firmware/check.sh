#!/usr/bin/env bash
# Flies the firmware in QEMU and checks it against the host:
#  1. a gait solved for another target (purcell-sim solve → export → include_bytes! through
#     PURCELL_GAIT) flies on the M4F bit-identical to `purcell-sim replay --gait … --precision
#     f32` (same digest line) and passes `purcell-mcu-check check`;
#  2. the committed constrained gait core/examples/paper-limit.gait (the paper's target within
#     |alpha_i| <= 1.5: five joint-limit arcs) flies on the M4F bit-identical to `purcell-sim
#     replay --gait … --precision f32`, within the M4F budgets, its steps on the arcs no
#     dearer than its free steps on average (every step within the per-step budget);
#  2b. the committed power-optimal gait core/examples/paper-power.gait (solve --cost power: the
#     power's law, MODEL.md §11) flies on the M4F bit-identical to `purcell-sim replay --gait …
#     --precision f32`, mean instructions per step <= PURCELL_MCU_POWER_MAX_INSN (default 830, a
#     regression guard: measured 813.5, within issue 37's 850), largest
#     <= PURCELL_MCU_POWER_MAX_STEP_INSN (default 900, measured 884);
#  3. a corrupted gait is refused on the M4F: the firmware prints the reason and exits 1;
#  4. M4F (mps2-an386), f32, the committed paper's gait: digest and final state bit-identical
#     to the host f32 flight, mean instructions per step <= PURCELL_MCU_MAX_INSN (default 685,
#     issue 14's target), largest step <= PURCELL_MCU_MAX_STEP_INSN (default 750, a regression
#     guard: a step that restores a checkpoint reads it from the gait's table), stack of a
#     step <= 2048 B, no soft-float helper reachable from the step;
#  5. M7 (mps2-an500), f64: bit-identical to the host f64 flight, mean and largest step
#     <= PURCELL_M7_MAX_INSN (default 1200, a regression guard), no soft-float helper
#     reachable from the step;
#  6. M3 (mps2-an385, no FPU), f32 in software floating point: bit-identical to the host f32
#     flight (and so to the M4F), mean and largest step <= PURCELL_M3_MAX_INSN (default
#     36000, a regression guard);
#  7. the M7 build run on the M4F board must exit 1 through the HardFault handler;
#  8. the control loop (mcu/examples/control_loop.rs, RTIC): the paper's gait flown cycle after
#     cycle from the SysTick at 1/h, every cycle's digest equal to `purcell-sim replay --gait …
#     --precision f32`'s, every cycle's pose to the host's composition (`purcell-mcu-check
#     loop`), no tick overran; the same for the power-optimal gait (paper-power.gait, the
#     power's law); ticking far faster than the step (PURCELL_LOOP_HZ) must overrun and exit 1;
#  9. the closed loop (mcu/examples/closed_loop.rs): the committed paper's gait exported with
#     its tracking table (export --tracking) flies its law and tracking law in f32 on the M4F
#     against a plant with a drag ratio 10 % larger, with the digest of `purcell-sim robustness
#     --gait … --ratio-error 0.1 --digest`; the tracking part of a step costs on average at most
#     PURCELL_TRACK_MAX_INSN (default 200, issue 26's target) instructions over the open-loop
#     step, reaches no soft-float helper, and the gains fit in 64 KiB;
# 10. the C example (c-example/check.sh): the C API's header is cbindgen's, a C firmware
#     linked against libpurcell_capi.a flies the paper's gait exported as C in QEMU with the
#     host's digest (instructions per step beside the Rust firmware's), no panic linked, and
#     the same C program on the host flies with the host's digest.
# Needs qemu-system-arm, defmt-print, arm-none-eabi-objdump/-size (binutils-arm-none-eabi)
# and the thumbv7em-none-eabihf and thumbv7m-none-eabi targets. Logs and listings go to
# $TARGET/mcu-check/. The M4F release ELF left behind is the paper's gait (step 4).
set -euo pipefail
cd "$(dirname "$0")/.."

target_dir=${CARGO_TARGET_DIR:-$PWD/target}
out=$target_dir/mcu-check
mkdir -p "$out"
objdump=${OBJDUMP:-arm-none-eabi-objdump}
size=${SIZE:-arm-none-eabi-size}
for tool in "${QEMU:-qemu-system-arm}" "${DEFMT_PRINT:-defmt-print}" "$objdump" "$size"; do
  command -v "$tool" >/dev/null || { echo "check.sh: $tool not found (see firmware/README.md)" >&2; exit 1; }
done

# The checker on the host (firmware/mcu-check/).
tool() { cargo run -q -p purcell-mcu-check -- "$@"; }
# purcell-sim in the test profile (optimised; `cargo test` has built it already).
sim() { cargo run -q --profile test -p purcell-sim -- "$@"; }
m4f_run() { cargo run -q -p purcell-mcu --target thumbv7em-none-eabihf --release; }

# $1 name, $2 the line the log must contain; then the command that must fail with exit 1.
fails_with() {
  local name=$1 line=$2 status
  shift 2
  set +e
  PURCELL_QEMU_TIMEOUT=60 "$@" >"$out/$name.log" 2>&1
  status=$?
  set -e
  if [[ $status -ne 1 ]] || ! grep -q "$line" "$out/$name.log"; then
    echo "check.sh: $name: expected exit 1 and a line matching '$line', got status $status:" >&2
    cat "$out/$name.log" >&2
    exit 1
  fi
  grep "$line" "$out/$name.log"
}

# The M4F's instruction budgets: mean per step, largest step.
m4f_budget=(--max-insn "${PURCELL_MCU_MAX_INSN:-685}" --max-step-insn "${PURCELL_MCU_MAX_STEP_INSN:-750}")

# $1 name, $2 ELF, $3 `check` budget flags, $4 extra `disasm` flags (the M3 has no FPU:
# --soft-float lists the helpers instead of failing); then the cargo command that runs the
# firmware.
fly() {
  local name=$1 elf=$2 budget=$3 disasm_flags=$4
  shift 4
  echo "--- $name: $*"
  "$@" 2>"$out/$name.stderr" | tee "$out/$name.log"
  # shellcheck disable=SC2086
  tool check "$out/$name.log" $budget --max-stack 2048
  "$objdump" -d "$elf" >"$out/$name.dis"
  # shellcheck disable=SC2086
  tool disasm "$out/$name.dis" $disasm_flags | grep -v '^  reachable:'
  echo "flash: $name $("$size" -A "$elf" | awk '$1 == ".text" || $1 == ".rodata" || $1 == ".vector_table" {s[$1] = $2} END {printf ".text=%d .rodata=%d .vector_table=%d bytes", s[".text"], s[".rodata"], s[".vector_table"]}')"
}

# $1 name, $2 gait file[, budget flags (default: the M4F's)]: flies it on the M4F
# (PURCELL_GAIT), checks the log against the host (budgets included) and the digest line against
# `purcell-sim replay --gait … --precision f32`.
fly_gait() {
  local name=$1 gait=$2
  shift 2
  local budget=("${m4f_budget[@]}")
  if (($#)); then budget=("$@"); fi
  sim replay --gait "$gait" --precision f32 | tee "$gaits/$name-host.txt"
  PURCELL_GAIT=$gait m4f_run 2>"$out/$name.stderr" | tee "$out/$name.log"
  PURCELL_GAIT=$gait tool check "$out/$name.log" "${budget[@]}" --max-stack 2048
  local host_digest mcu_digest
  host_digest=$(grep '^digest: ' "$gaits/$name-host.txt")
  mcu_digest=$(grep '^digest: ' "$out/$name.log")
  if [[ $host_digest != "$mcu_digest" ]]; then
    echo "check.sh: $name: purcell-sim replay says '$host_digest', the M4F '$mcu_digest'" >&2
    exit 1
  fi
  echo "$name: the M4F flight of $gait is bit-identical to purcell-sim replay ($mcu_digest)"
}

echo "--- gait: solve a non-default target, export, fly it on the M4F, compare with the host"
gaits=$out/gaits
rm -rf "$gaits"
mkdir -p "$gaits"
sim solve --target 0.05,0.02,0 --horizon 20 --no-plots --out "$gaits/solved" >/dev/null
sim export --costate "$gaits/solved/costate.json" --out "$gaits/solved.gait"
fly_gait gait "$gaits/solved.gait"

echo "--- constrained gait: the paper's target within |alpha_i| <= 1.5, on its joint limit on five arcs"
fly_gait limit core/examples/paper-limit.gait

echo "--- power gait: the paper's target at least power (solve --cost power, MODEL.md §11), the power's law"
fly_gait power core/examples/paper-power.gait --max-insn "${PURCELL_MCU_POWER_MAX_INSN:-830}" \
  --max-step-insn "${PURCELL_MCU_POWER_MAX_STEP_INSN:-900}"

echo "--- corrupted gait: one flipped byte in the checkpoint table must be refused (exit 1)"
cp "$gaits/solved.gait" "$gaits/corrupt.gait"
at=300
byte=$(od -An -tu1 -j$at -N1 "$gaits/corrupt.gait" | tr -d ' ')
printf "\\$(printf '%03o' $((byte ^ 1)))" | dd of="$gaits/corrupt.gait" bs=1 seek=$at conv=notrunc status=none
PURCELL_GAIT=$gaits/corrupt.gait fails_with corrupt '^gait refused: gait file checksum' m4f_run

m4f=$target_dir/thumbv7em-none-eabihf/release/purcell-mcu
m7=$target_dir/thumbv7em-none-eabihf/mcu-m7/purcell-mcu
m3=$target_dir/thumbv7m-none-eabi/release/purcell-mcu
fly m4f "$m4f" "${m4f_budget[*]}" "" m4f_run
fly m7 "$m7" "--max-insn ${PURCELL_M7_MAX_INSN:-1200}" "" cargo -q mcu-m7
fly m3 "$m3" "--max-insn ${PURCELL_M3_MAX_INSN:-36000}" --soft-float cargo -q mcu-m3

echo "--- fault: the M7 (double-precision) build on the M4F board must exit 1 via HardFault"
PURCELL_QEMU_MACHINE=mps2-an386 fails_with fault '^HardFault at pc=' firmware/mcu/qemu-run.sh "$m7"
echo "--- control loop: the paper's gait cycle after cycle from the SysTick at 1/h (RTIC), against the host"
loop_run() { cargo run -q -p purcell-mcu --example control_loop --target thumbv7em-none-eabihf --release; }
loop_run 2>"$out/loop.stderr" | tee "$out/loop.log"
tool loop "$out/loop.log" --gait core/examples/paper.gait
host_digest=$(sim replay --gait core/examples/paper.gait --precision f32 | sed -n 's/^digest: //p')
cycle_digests=$(sed -n 's/^cycle: .* digest=\(0x[0-9a-f]*\) .*/\1/p' "$out/loop.log" | sort -u)
if [[ -z $host_digest || $cycle_digests != "$host_digest" ]]; then
  echo "check.sh: loop: cycle digests '$cycle_digests', purcell-sim replay '$host_digest'" >&2
  exit 1
fi
echo "loop: every cycle's digest is purcell-sim replay's ($host_digest)"
echo "--- control loop of the power-optimal gait (the power's law), against the host"
PURCELL_GAIT=core/examples/paper-power.gait loop_run 2>"$out/loop-power.stderr" | tee "$out/loop-power.log"
tool loop "$out/loop-power.log" --gait core/examples/paper-power.gait
echo "--- control loop ticking at 100 kHz, faster than a step: must overrun and exit 1"
PURCELL_LOOP_HZ=100000 fails_with overrun '^failed: Overruns' loop_run

echo "--- closed loop: the paper's gait and its tracking table, drag ratio +10 %, on the M4F against the host"
sim export --gait core/examples/paper.gait --tracking --out "$gaits/paper-tracking.gait"
closed_run() {
  PURCELL_GAIT=$gaits/paper-tracking.gait PURCELL_RATIO_ERROR=0.1 \
    cargo run -q -p purcell-mcu --example closed_loop --target thumbv7em-none-eabihf --release
}
closed_run 2>"$out/closed.stderr" | tee "$out/closed.log"
host_digest=$(sim robustness --gait "$gaits/paper-tracking.gait" --ratio-error 0.1 --digest | grep '^closed_digest: ')
mcu_digest=$(grep '^closed_digest: ' "$out/closed.log" || true)
if [[ -z $host_digest || $host_digest != "$mcu_digest" ]] || ! grep -q '^result: ok$' "$out/closed.log"; then
  echo "check.sh: closed loop: purcell-sim robustness says '$host_digest', the M4F '$mcu_digest'" >&2
  exit 1
fi
track_mean=$(sed -n 's/^track_insn: mean=\([0-9.]*\) .*/\1/p' "$out/closed.log")
track_budget=${PURCELL_TRACK_MAX_INSN:-200}
if ! awk -v m="$track_mean" -v b="$track_budget" 'BEGIN { exit !(m != "" && m + 0 <= b + 0) }'; then
  echo "check.sh: closed loop: the tracking part costs $track_mean instructions per step, budget $track_budget" >&2
  exit 1
fi
gain_bytes=$(sed -n 's/^purcell-closed: .* gain_bytes=\([0-9]*\) .*/\1/p' "$out/closed.log")
if ((${gain_bytes:-0} == 0 || gain_bytes > 65536)); then
  echo "check.sh: closed loop: the tracking table is $gain_bytes bytes, more than 64 KiB (or none)" >&2
  exit 1
fi
"$objdump" -d "$target_dir/thumbv7em-none-eabihf/release/examples/closed_loop" >"$out/closed.dis"
tool disasm "$out/closed.dis" --root purcell_mcu_track | grep -v '^  reachable:'
echo "closed loop: bit-identical to the host ($mcu_digest), tracking $track_mean <= $track_budget instructions per step over the law's, gains $gain_bytes bytes"
bash firmware/c-example/check.sh
echo "mcu: 11 passed, 0 failed"
