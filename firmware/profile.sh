#!/usr/bin/env bash
# Where the instructions of a control step go, exactly: runs the firmware in QEMU with one
# instruction per translation block and an execution trace of the code reachable from
# `purcell_mcu_step` (as `purcell-mcu-check disasm` finds it), counts how often each
# instruction ran over the first STEPS calls (the measured replay), and attributes every
# instruction to the innermost `purcell_core` function it was inlined from (the ELF's line
# tables, through `arm-none-eabi-addr2line -i`). Prints instructions per step by part; they
# add up to the measured `insn_per_step` mean (less the two counter reads around the call).
#   firmware/profile.sh [ELF] [STEPS]
# Default ELF: the M4F release build in $CARGO_TARGET_DIR (build it first); STEPS: 10000.
# Needs -icount like every run (the firmware checks its counter first). For the M7 build: PURCELL_QEMU_MACHINE=mps2-an500 firmware/profile.sh <mcu-m7 ELF>.
set -euo pipefail
cd "$(dirname "$0")/.."
target_dir=${CARGO_TARGET_DIR:-$PWD/target}
elf=${1:-$target_dir/thumbv7em-none-eabihf/release/purcell-mcu}
steps=${2:-10000}
machine=${PURCELL_QEMU_MACHINE:-mps2-an386}
objdump=${OBJDUMP:-arm-none-eabi-objdump}
addr2line=${ADDR2LINE:-arm-none-eabi-addr2line}
nm=${NM:-arm-none-eabi-nm}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$objdump" -d "$elf" >"$work/dis"
cargo run -q -p purcell-mcu-check -- disasm "$work/dis" | sed -n 's/^  reachable: //p' >"$work/reachable"
# Address ranges of the reachable functions: "start end name", 8-digit hex (Thumb bit cleared).
: >"$work/ranges"
while read -r addr size _ name; do
  grep -qxF "$name" "$work/reachable" || continue
  start=$((16#$addr & ~1))
  printf '%08x %08x %s\n' "$start" $((start + 16#$size)) "$name" >>"$work/ranges"
done < <("$nm" -S --defined-only "$elf" | awk '$3 == "T" || $3 == "t"')
entry=$(awk '$3 == "purcell_mcu_step" { print $1 }' "$work/ranges")
[[ -n $entry ]] || { echo "profile.sh: no purcell_mcu_step in $elf" >&2; exit 1; }
filter=$(awk '{ printf "%s0x%s..0x%s", (NR > 1 ? "," : ""), $1, $2 }' "$work/ranges")

# Trace lines look like `Trace 0: 0x... [00800400/0000334c/00000010/ff020201] symbol`.
set +o pipefail
timeout "${PURCELL_QEMU_TIMEOUT:-600}" "${QEMU:-qemu-system-arm}" -machine "$machine" \
  -nographic -monitor none -serial none -semihosting-config enable=on,target=native \
  -icount shift=6 -singlestep -d exec,nochain -dfilter "$filter" -D /dev/stdout -kernel "$elf" </dev/null 2>/dev/null |
  awk -v entry="$entry" -v steps="$steps" '
    { if (!match($0, /\[[0-9a-f]+\/[0-9a-f]+\//)) next
      pc = substr($0, RSTART + 10, 8)
      if (pc == entry && ++calls > steps) exit
      n[pc]++ }
    END { for (p in n) print "0x" p, n[p]
          print (calls > steps ? steps : calls + 0) > "'"$work/calls"'" }' >"$work/counts"
set -o pipefail
calls=$(cat "$work/calls")
[[ $calls -gt 0 ]] || { echo "profile.sh: no step ran" >&2; exit 1; }

# One addr2line block per address (inlined frames innermost first); the part is the
# innermost frame in purcell_core (or the firmware's own function; else, e.g. libm, the
# innermost frame).
cut -d' ' -f1 "$work/counts" | "$addr2line" -f -i -C -a -e "$elf" | awk '
  function emit() { if (addr != "") print addr, (part != "" ? part : first) }
  /^0x/ { emit(); addr = $1; part = ""; first = ""; next }
  /^\// || /^\?\?:/ { next }
  first == "" { first = $0 }
  part == "" && /^(purcell_core|purcell_mcu)::/ { part = $0 }
  part == "" && /^<.* as purcell_core::/ { part = $0 }
  END { emit() }' |
  sed -E 's/<impl [^>]*>:://; s/<[A-Za-z0-9_]+>//g; s/(::\{\{closure\}\})+$//' >"$work/parts"

awk -v calls="$calls" '
  NR == FNR { c[$1] = $2; next }
  { a = $1; $1 = ""; p = substr($0, 2); if (p == "") p = "(other)"
    gsub(/purcell_core::/, "", p); t[p] += c[a]; total += c[a] }
  END {
    printf "profile: steps=%d insn_per_step=%.1f (the step function and what it reaches)\n", calls, total / calls
    for (p in t) printf "  %8.1f  %s\n", t[p] / calls, p | "sort -rn"
  }' "$work/counts" "$work/parts"
