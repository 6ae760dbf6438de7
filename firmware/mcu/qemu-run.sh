#!/usr/bin/env bash
# Cargo runner for the firmware: runs ELF in QEMU, decodes its defmt log, exits with the
# firmware's semihosting status (124 on timeout).
#   qemu-run.sh ELF
# Environment: PURCELL_QEMU_MACHINE (default: from the ELF's board tag; mps2-an386 = M4F,
# mps2-an500 = M7, mps2-an385 = M3), PURCELL_QEMU_TIMEOUT seconds (default 300), QEMU (default qemu-system-arm),
# DEFMT_PRINT (default defmt-print).
set -uo pipefail
elf=${1:?usage: qemu-run.sh ELF}
machine=${PURCELL_QEMU_MACHINE:-}
if [[ -z $machine ]]; then
  if grep -aq 'purcell-board:mps2-an500' "$elf"; then
    machine=mps2-an500
  elif grep -aq 'purcell-board:mps2-an385' "$elf"; then
    machine=mps2-an385
  else
    machine=mps2-an386
  fi
fi
# -icount shift=6: one instruction = 64 ns of virtual time (the firmware counts with SysTick);
# sleep=off: while the CPU sleeps (wfi), virtual time jumps to the next timer deadline.
timeout "${PURCELL_QEMU_TIMEOUT:-300}" "${QEMU:-qemu-system-arm}" \
  -machine "$machine" -nographic -monitor none -serial none \
  -semihosting-config enable=on,target=native -icount shift=6,sleep=off -kernel "$elf" </dev/null \
  | "${DEFMT_PRINT:-defmt-print}" -e "$elf" --log-format '{s}'
status=("${PIPESTATUS[@]}")
if [[ ${status[0]} -ne 0 ]]; then
  echo "qemu-run.sh: firmware on $machine exited with status ${status[0]}" >&2
  exit "${status[0]}"
fi
exit "${status[1]}"
