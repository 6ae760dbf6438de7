//! A gait on an STM32F4-Discovery (STM32F407VG, Cortex-M4F): flies it in `f32` through
//! `purcell-core` with `purcell_fly`, times every step with the DWT cycle counter, and logs
//! over RTT (defmt) the cycles per step, the trajectory digest and the final state's bits,
//! which `purcell-mcu-check check` compares with the host's flight of the same gait.
//!
//! It runs at the chip's rated 168 MHz, set by the HAL (`stm32f4xx-hal`) from the board's 8 MHz
//! crystal (HSE) through the PLL, with 5 flash wait states behind the ART accelerator
//! (prefetch, instruction and data caches); exits through semihosting, which `probe-rs run`
//! turns into its exit status (0, or 1 on any failure). `examples/control_loop.rs` flies the
//! gait as a control loop, one step per SysTick tick at `1/h`.

#![no_std]
#![no_main]

use cortex_m::peripheral::DWT;
use cortex_m_rt::{ExceptionFrame, entry, exception};
use defmt_rtt as _;
use panic_probe as _;
use purcell_core::cost::Effort;
use purcell_core::{Error, Replay};
use purcell_fly::{Counter, DwtCycles};
use stm32f4xx_hal::pac;
use stm32f4xx_hal::prelude::*;
use stm32f4xx_hal::rcc::{Config, RccExt};

/// The gait to fly, as `purcell-sim export` wrote it: the path comes from `PURCELL_GAIT`
/// (`.cargo/config.toml`: the paper's gait). In your firmware, name the file directly:
/// `static GAIT: &[u8] = include_bytes!("../gait.bin");`.
static GAIT: &[u8] = include_bytes!(env!("PURCELL_GAIT"));

/// The name in the log's header.
const BOARD: &str = "stm32f4-discovery";

/// Why the run fails (it then exits with status 1).
#[derive(defmt::Format)]
enum Failure {
    /// The core refused the gait or a step.
    Core(Error),
    /// The core or device peripherals were already taken.
    Peripherals,
    /// The cycle counter did not advance.
    CounterStopped,
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Failure::Core(e)
    }
}

/// Starts the DWT cycle counter and checks that it counts.
fn start_cycle_counter(cp: &mut cortex_m::Peripherals) -> Result<(), Failure> {
    cp.DCB.enable_trace(); // TRCENA: powers the DWT.
    DWT::unlock(); // Cortex-M7 parts (STM32F7, H7) lock the DWT; a no-op on this Cortex-M4.
    cp.DWT.set_cycle_count(0);
    cp.DWT.enable_cycle_counter();
    let t0 = DwtCycles::now();
    for i in 0..1000u32 {
        core::hint::black_box(i);
    }
    let cycles = DwtCycles::elapsed(t0, DwtCycles::now());
    // A loop iteration takes at least one cycle: fewer means the counter is not running.
    if cycles < 1000 {
        return Err(Failure::CounterStopped);
    }
    defmt::println!(
        "cycle_counter: ok, 1000 loop iterations took {=u32} cycles",
        cycles
    );
    Ok(())
}

fn run() -> Result<(), Failure> {
    let mut cp = cortex_m::Peripherals::take().ok_or(Failure::Peripherals)?;
    let dp = pac::Peripherals::take().ok_or(Failure::Peripherals)?;
    let rcc = dp.RCC.freeze(Config::hse(8.MHz()).sysclk(168.MHz()));
    defmt::println!("clock: sysclk={=u32} Hz", rcc.clocks.sysclk().raw());
    start_cycle_counter(&mut cp)?;
    let gait = purcell_fly::load(GAIT)?;
    let overhead = purcell_fly::overhead::<DwtCycles>();
    // Each step lends its sample: command the joints with `sample.u` in your own loop
    // (examples/control_loop.rs).
    purcell_fly::fly::<f32, DwtCycles, Effort, _>(BOARD, &gait, overhead, Replay::step)?;
    Ok(())
}

#[entry]
fn main() -> ! {
    // Logs `result: ok` or `failed: <why>`; `probe-rs run` exits with the status.
    semihosting::process::exit(purcell_fly::finish(run()))
}

#[exception]
unsafe fn HardFault(ef: &ExceptionFrame) -> ! {
    defmt::error!("HardFault at pc={=u32:#x}", ef.pc());
    semihosting::process::exit(1)
}
