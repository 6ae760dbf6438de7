//! The gait as a control loop on the STM32F4-Discovery at 168 MHz, with RTIC 2: the same loop
//! as the QEMU example CI runs (`firmware/mcu/examples/control_loop.rs`), both
//! [`purcell_fly::control_loop!`] over [`purcell_fly::pilot`]. The SysTick, on the 168 MHz
//! core clock, expires every `h` (10 ms for the paper's gait); its handler steps the law once,
//! commands the joints (recorded in `Status::joints`; for your motors, write the app out from
//! the macro and give `Pilot::tick` your driver in its `tick`) and flies the gait three times
//! in a row. The idle task logs each cycle's digest and pose over RTT, then the ticks in core
//! cycles (the SysTick counts the core clock, as the DWT does) from the timer's expiry to the
//! end of its handler, the margin to the period, and the overruns (any fails the run).
//!
//! Run: `cargo run --release --example control_loop`; check the log on the host with
//! `cargo run -p purcell-mcu-check -- loop board-loop.log` (see README.md).

#![no_std]
#![no_main]

use defmt_rtt as _;
use panic_probe as _;

// The gait to fly (`PURCELL_GAIT`, `.cargo/config.toml`: the paper's gait), three cycles in a
// row; the SysTick on the core clock, 168 MHz from the 8 MHz HSE.
purcell_fly::control_loop! {
    device: stm32f4xx_hal::pac,
    peripherals: true,
    board: "stm32f4-discovery",
    counter: purcell_fly::DwtCycles,
    gait: include_bytes!(env!("PURCELL_GAIT")),
    cycles: 3,
    exit: semihosting::process::exit,
    clocks: |cx| {
        use stm32f4xx_hal::prelude::*;
        use stm32f4xx_hal::rcc::{Config, RccExt};
        let rcc = cx.device.RCC.freeze(Config::hse(8.MHz()).sysclk(168.MHz()));
        (rcc.clocks.sysclk().raw(), None)
    },
}
