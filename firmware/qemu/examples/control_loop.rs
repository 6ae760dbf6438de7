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
//! overrun and the run fails (`firmware/check.sh` checks that it does).
//!
//! Run: `cargo run -p purcell-mcu --example control_loop --target thumbv7em-none-eabihf --release`.

#![cfg_attr(target_os = "none", no_std, no_main)]

/// Cycles of the gait flown in a row.
#[cfg(target_os = "none")]
const CYCLES: u32 = 3;

#[cfg(target_os = "none")]
mod mps2 {
    //! The little RTIC needs of a device crate (QEMU's MPS2 boards have none): the NVIC's
    //! priority bits (3 on the AN386's Cortex-M4). No device interrupt is used.

    /// Priority bits of the NVIC.
    pub const NVIC_PRIO_BITS: u8 = 3;
}

#[cfg(target_os = "none")]
#[rtic::app(device = crate::mps2, peripherals = false)]
mod app {
    use crate::CYCLES;
    use defmt_semihosting as _;
    use purcell_fly::pilot::{Pilot, Status, SysTickTimer, period_counts};
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
        logged: u32,
    }

    /// The timer's period in SysTick counts: `h`, or `1/PURCELL_LOOP_HZ`.
    fn period(h: f64) -> Option<u32> {
        let h = match option_env!("PURCELL_LOOP_HZ") {
            Some(hz) => 1.0 / f64::from(hz.parse::<u32>().ok()?),
            None => h,
        };
        period_counts(h, CLOCK_HZ, SysTickTimer::MAX_COUNTS)
    }

    #[init]
    fn init(mut cx: init::Context) -> (Shared, Local) {
        let start = purcell_fly::load(GAIT)
            .and_then(|gait| Ok((gait, Pilot::new(gait)?)))
            .map_err(purcell_fly::pilot::LoopError::Core);
        let (gait, pilot) = match start {
            Ok(started) => started,
            Err(e) => semihosting::process::exit(purcell_fly::finish(Err(e))),
        };
        let Some(counts) = period(gait.params().h) else {
            defmt::error!("failed: the period is not 2 to 2^24 SysTick counts");
            semihosting::process::exit(1)
        };
        purcell_fly::pilot::log_header::<f32, Systick>("mps2-an386", &gait, counts, CYCLES);
        let timer = SysTickTimer::start(&mut cx.core.SYST, counts);
        let status = Status::default();
        let local = Local {
            pilot,
            timer,
            counts,
            logged: 0,
        };
        (Shared { status }, local)
    }

    /// Logs what the ticks report, sleeping in between; exits once the flight is over.
    #[idle(shared = [status], local = [counts, logged])]
    fn idle(mut cx: idle::Context) -> ! {
        loop {
            let status = cx.shared.status.lock(|s| *s);
            let report = purcell_fly::pilot::report::<f32, Systick>(
                &status,
                cx.local.logged,
                *cx.local.counts,
            );
            if let Some(code) = report {
                semihosting::process::exit(code);
            }
            cortex_m::asm::wfi();
        }
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
