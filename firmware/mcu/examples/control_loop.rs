//! The gait as a control loop on QEMU's Cortex-M4F (`mps2-an386`), with RTIC 2: the SysTick
//! expires every `h` (the gait's step, 10 ms for the paper's gait) and its handler, an RTIC
//! hardware task, steps the law once ([`purcell_fly::pilot`]), commands the joints (recorded
//! here), and flies the gait [`CYCLES`] times in a row; the idle task logs each cycle's digest
//! and pose, then the ticks' timing, and exits through semihosting (status 0, or 1 for a gait
//! the core refuses, a failing step, or any tick that ran into the next period).
//!
//! Under `-icount shift=6` the SysTick (25 MHz) counts 8/5 per instruction, so each tick is
//! measured in instructions from the timer's expiry to the end of its handler. The idle task
//! sleeps (`wfi`), and QEMU, run with `sleep=off`, skips the idle time.
//!
//! `PURCELL_LOOP_HZ` (at build time) ticks at another rate than `1/h`: fast enough, the ticks
//! overrun and the run fails (`firmware/check.sh` checks that it does). The same loop on a
//! board: `firmware/board-stm32f4-discovery/examples/control_loop.rs`.
//!
//! Run: `cargo run -p purcell-mcu --example control_loop --target thumbv7em-none-eabihf --release`.

#![cfg_attr(target_os = "none", no_std, no_main)]

/// Cycles of the gait flown in a row.
#[cfg(target_os = "none")]
const CYCLES: u32 = 3;

#[cfg(target_os = "none")]
mod mps2 {
    //! What RTIC needs of a device crate, which QEMU's MPS2 boards lack: the NVIC's priority
    //! bits (3 on the AN386's Cortex-M4). No device interrupt is used.

    /// Priority bits of the NVIC.
    pub const NVIC_PRIO_BITS: u8 = 3;
}

#[cfg(target_os = "none")]
#[rtic::app(device = crate::mps2, peripherals = false)]
mod app {
    use crate::CYCLES;
    use defmt_semihosting as _;
    use purcell_fly::pilot::{self, Pilot, Status, SysTickTimer};
    use purcell_mcu::Systick;

    /// The gait flown: `$PURCELL_GAIT`, or the committed paper's gait (see `build.rs`).
    static GAIT: &[u8] = include_bytes!(env!("PURCELL_GAIT_FILE"));
    /// The SysTick's clock on the MPS2 boards, Hz.
    const CLOCK_HZ: u32 = 25_000_000;

    #[shared]
    struct Shared {
        status: Status<f32>,
    }

    #[local]
    struct Local {
        pilot: Pilot<'static, f32>,
        timer: SysTickTimer,
        counts: u32,
    }

    #[init]
    fn init(cx: init::Context) -> (Shared, Local) {
        let mut syst = cx.core.SYST;
        let rate_hz = option_env!("PURCELL_LOOP_HZ").and_then(|hz| hz.parse().ok());
        let start =
            pilot::start::<f32, Systick>("mps2-an386", GAIT, &mut syst, CLOCK_HZ, rate_hz, CYCLES);
        let (pilot, timer, counts) =
            start.unwrap_or_else(|e| semihosting::process::exit(purcell_fly::finish(Err(e))));
        let status = Status::default();
        (
            Shared { status },
            Local {
                pilot,
                timer,
                counts,
            },
        )
    }

    #[idle(shared = [status], local = [counts])]
    fn idle(mut cx: idle::Context) -> ! {
        let status = || cx.shared.status.lock(|s| *s);
        pilot::idle::<f32, Systick>(*cx.local.counts, status, semihosting::process::exit)
    }

    /// One tick: one step of the law, the joints commanded, timed to the end of the handler.
    #[task(binds = SysTick, shared = [status], local = [pilot, timer])]
    fn tick(mut cx: tick::Context) {
        let (pilot, timer) = (cx.local.pilot, cx.local.timer);
        cx.shared.status.lock(|s| s.tick(pilot, CYCLES, timer));
    }
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
