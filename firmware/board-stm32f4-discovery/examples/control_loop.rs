//! The gait as a control loop on the STM32F4-Discovery at 168 MHz, with RTIC 2: the same loop
//! as the QEMU example CI runs (`firmware/mcu/examples/control_loop.rs`, both through
//! [`purcell_fly::pilot`]). The SysTick, on the 168 MHz core clock, expires every `h` (10 ms
//! for the paper's gait); its handler steps the law once, commands the joints (recorded in
//! `Status::joints`: drive your motors from them in `tick`, or give `Pilot::tick` your driver)
//! and flies the gait [`CYCLES`] times in a row. The idle task logs each cycle's digest and pose over RTT, then the ticks in core
//! cycles (the SysTick counts the core clock, as the DWT does) from the timer's expiry to the
//! end of its handler, the margin to the period, and the overruns (any fails the run).
//!
//! Run: `cargo run --release --example control_loop`; check the log on the host with
//! `cargo run -p purcell-mcu-check -- loop board-loop.log` (see README.md).

#![no_std]
#![no_main]

use defmt_rtt as _;
use panic_probe as _;

/// Cycles of the gait flown in a row.
const CYCLES: u32 = 3;

#[rtic::app(device = stm32f4xx_hal::pac, peripherals = true)]
mod app {
    use crate::CYCLES;
    use purcell_fly::DwtCycles;
    use purcell_fly::pilot::{self, Pilot, Status, SysTickTimer};
    use stm32f4xx_hal::prelude::*;
    use stm32f4xx_hal::rcc::{Config, RccExt};

    /// The gait to fly (`PURCELL_GAIT`, `.cargo/config.toml`: the paper's gait).
    static GAIT: &[u8] = include_bytes!(env!("PURCELL_GAIT"));

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
        let rcc = cx.device.RCC.freeze(Config::hse(8.MHz()).sysclk(168.MHz()));
        let mut syst = cx.core.SYST;
        let clock_hz = rcc.clocks.sysclk().raw();
        let start = pilot::start::<f32, DwtCycles>(
            "stm32f4-discovery",
            GAIT,
            &mut syst,
            clock_hz,
            None,
            CYCLES,
        );
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
        pilot::idle::<f32, DwtCycles>(*cx.local.counts, status, semihosting::process::exit)
    }

    /// One tick: one step of the law, the joints commanded, timed to the end of the handler.
    #[task(binds = SysTick, shared = [status], local = [pilot, timer])]
    fn tick(mut cx: tick::Context) {
        let (pilot, timer) = (cx.local.pilot, cx.local.timer);
        cx.shared.status.lock(|s| s.tick(pilot, CYCLES, timer));
    }
}
