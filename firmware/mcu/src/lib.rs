//! What the QEMU firmware (`src/firmware.rs`) and the control-loop example
//! (`examples/control_loop.rs`) share: counting instructions with the SysTick under QEMU's
//! `-icount shift=6` (the arithmetic here, tested on the host) and, on the MCU, the counter
//! itself (`Systick`) and the fault and panic handlers (exit status 1).

#![no_std]

#[cfg(target_os = "none")]
mod mcu;
#[cfg(target_os = "none")]
pub use mcu::{Systick, start_systick};

/// `-icount shift=6`: one instruction is `2⁶ ns` of virtual time, the MPS2 SysTick counts at
/// 25 MHz (40 ns), so it advances `64/40 = 8/5` ticks per instruction.
pub const TICKS_PER_INSN_NUM: u64 = 8;
/// Denominator of [`TICKS_PER_INSN_NUM`].
pub const TICKS_PER_INSN_DEN: u64 = 5;

/// Ticks elapsed on the 24-bit down-counting SysTick from `start` to `end`, modulo `2²⁴`:
/// exact for intervals shorter than one wrap (`2²⁴` ticks, about 10 M instructions), so no
/// wrap interrupt has to run (and be counted) inside a measured step.
pub fn systick_elapsed(start: u32, end: u32) -> u32 {
    start.wrapping_sub(end) & 0x00FF_FFFF
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_count_down_and_wrap_at_24_bits() {
        assert_eq!(systick_elapsed(100, 40), 60);
        assert_eq!(systick_elapsed(5, 0x00FF_FFF0), 0x15);
        // 64 ns of virtual time per instruction, 40 ns per tick.
        assert_eq!(64 * TICKS_PER_INSN_DEN, 40 * TICKS_PER_INSN_NUM);
    }
}
