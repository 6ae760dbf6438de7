//! The QEMU harness that measures what flies: the firmware (`src/firmware.rs`, on
//! `target_os = "none"`) flies a gait with `purcell_fly` on an emulated Cortex-M4F / M7 and
//! counts instructions per step ([`icount`]); the same crate built for the host checks it
//! ([`check`]: the log against the host's replay of the same gait, the disassembly for
//! soft-float helpers).

#![no_std]
#![deny(missing_docs)]
#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]
#![cfg_attr(
    test,
    allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)
)]

#[cfg(not(target_os = "none"))]
extern crate std;

#[cfg(not(target_os = "none"))]
pub mod check;

/// Counting instructions with the SysTick under QEMU's `-icount shift=6`.
pub mod icount {
    /// `-icount shift=6`: one instruction is `2⁶ ns` of virtual time, the MPS2 SysTick counts
    /// at 25 MHz (40 ns), so it advances `64/40 = 8/5` ticks per instruction.
    pub const TICKS_PER_INSN_NUM: u64 = 8;
    /// Denominator of [`TICKS_PER_INSN_NUM`].
    pub const TICKS_PER_INSN_DEN: u64 = 5;

    /// Instructions in `ticks` SysTick ticks under `-icount shift=6`, rounded to nearest.
    pub fn ticks_to_insns(ticks: u64) -> u64 {
        (ticks * TICKS_PER_INSN_DEN + TICKS_PER_INSN_NUM / 2) / TICKS_PER_INSN_NUM
    }

    /// Ticks elapsed on the 24-bit down-counting SysTick from `start` to `end`, modulo `2²⁴`:
    /// exact for intervals shorter than one wrap (`2²⁴` ticks, about 10 M instructions), so
    /// no wrap interrupt has to run (and be counted) inside a measured step.
    pub fn systick_elapsed(start: u32, end: u32) -> u32 {
        start.wrapping_sub(end) & 0x00FF_FFFF
    }

    #[cfg(test)]
    mod tests {
        use super::*;

        #[test]
        fn tick_conversion() {
            assert_eq!(ticks_to_insns(1600), 1000);
            assert_eq!(ticks_to_insns(1601), 1001);
            assert_eq!(ticks_to_insns(1599), 999);
            assert_eq!(systick_elapsed(100, 40), 60);
            assert_eq!(systick_elapsed(5, 0x00FF_FFF0), 0x15);
        }
    }
}
