//! The gait as a control loop on QEMU's Cortex-M4F (`mps2-an386`), with RTIC 2: the SysTick
//! expires every `h` (the gait's step, 10 ms for the paper's gait) and its handler, an RTIC
//! hardware task, steps the law once ([`purcell_fly::pilot`]), commands the joints (recorded
//! here), and flies the gait three times in a row; the idle task logs each cycle's digest
//! and pose, then the ticks' timing, and exits through semihosting (status 0, or 1 for a gait
//! the core refuses, a failing step, or any tick that ran into the next period).
//!
//! Under `-icount shift=6` the SysTick (25 MHz) counts 8/5 per instruction, so each tick is
//! measured in instructions from the timer's expiry to the end of its handler. The idle task
//! sleeps (`wfi`), and QEMU, run with `sleep=off`, skips the idle time.
//!
//! `PURCELL_LOOP_HZ` (at build time) ticks at another rate than `1/h`: fast enough, the ticks
//! overrun and the run fails (`firmware/check.sh` checks that it does). The same loop on a
//! board: `firmware/board-stm32f4-discovery/examples/control_loop.rs`; both are
//! [`purcell_fly::control_loop!`].
//!
//! Run: `cargo run -p purcell-mcu --example control_loop --target thumbv7em-none-eabihf --release`.

#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_os = "none")]
mod mps2 {
    //! What RTIC needs of a device crate, which QEMU's MPS2 boards lack: the NVIC's priority
    //! bits (3 on the AN386's Cortex-M4). No device interrupt is used.

    /// Priority bits of the NVIC.
    pub const NVIC_PRIO_BITS: u8 = 3;
}

#[cfg(target_os = "none")]
use defmt_semihosting as _;

// The gait flown: `$PURCELL_GAIT`, or the committed paper's gait (see `build.rs`), three
// cycles in a row; the SysTick's clock on the MPS2 boards is 25 MHz.
#[cfg(target_os = "none")]
purcell_fly::control_loop! {
    device: crate::mps2,
    peripherals: false,
    board: "mps2-an386",
    counter: purcell_mcu::Systick,
    gait: include_bytes!(env!("PURCELL_GAIT_FILE")),
    cycles: 3,
    exit: semihosting::process::exit,
    clocks: |cx| { (25_000_000, option_env!("PURCELL_LOOP_HZ").and_then(|hz| hz.parse().ok())) },
}

/// The host build: how to run the example; exits with 1.
#[cfg(not(target_os = "none"))]
fn main() -> std::process::ExitCode {
    eprintln!(
        "control_loop is firmware for QEMU's Cortex-M4F board: run it with
`cargo run -p purcell-mcu --example control_loop --target thumbv7em-none-eabihf --release`
(see firmware/README.md)."
    );
    std::process::ExitCode::FAILURE
}
