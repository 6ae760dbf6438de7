//! The control loop as an RTIC 2 application ([`control_loop!`](crate::control_loop)): one
//! definition for the QEMU example (`firmware/mcu/examples/control_loop.rs`) and a board's
//! (`firmware/board-stm32f4-discovery/examples/control_loop.rs`), which differ only in their
//! device, clock and counter.

/// Defines the RTIC 2 application `app` of a control loop in `f32` ([`pilot`](crate::pilot)):
/// `init` runs `clocks` (with the `init::Context` named as given) for the SysTick's clock in Hz
/// and an optional tick rate (`None`: the gait's `1/h`), then [`pilot::start`](crate::pilot::start)
/// with the SysTick (exiting through `exit` with [`finish`](crate::finish)'s status if that
/// fails); the SysTick's handler, an RTIC hardware task, runs one
/// [`Status::tick`](crate::pilot::Status::tick) (one step of the law, the joints commanded, the
/// tick timed to the end of the handler) until `cycles` cycles are flown; the idle task logs
/// through [`pilot::idle`](crate::pilot::idle), counting with `counter`, and exits through
/// `exit` with the run's status.
///
/// The crate that calls it depends on `rtic` 2 (and its device crate, `device`).
///
/// ```ignore
/// purcell_fly::control_loop! {
///     device: stm32f4xx_hal::pac,
///     peripherals: true,
///     board: "stm32f4-discovery",
///     counter: purcell_fly::DwtCycles,
///     gait: include_bytes!(env!("PURCELL_GAIT")),
///     cycles: 3,
///     exit: semihosting::process::exit,
///     clocks: |cx| {
///         use stm32f4xx_hal::prelude::*;
///         use stm32f4xx_hal::rcc::{Config, RccExt};
///         let rcc = cx.device.RCC.freeze(Config::hse(8.MHz()).sysclk(168.MHz()));
///         (rcc.clocks.sysclk().raw(), None)
///     },
/// }
/// ```
#[macro_export]
macro_rules! control_loop {
    (
        device: $($device:ident)::+,
        peripherals: $peripherals:tt,
        board: $board:literal,
        counter: $counter:ty,
        gait: $gait:expr,
        cycles: $cycles:expr,
        exit: $exit:path,
        clocks: |$cx:ident| $clocks:block $(,)?
    ) => {
        #[rtic::app(device = $($device)::+, peripherals = $peripherals)]
        mod app {
            use $crate::pilot::{self, Pilot, Status, SysTickTimer};

            /// The gait flown.
            static GAIT: &[u8] = $gait;
            /// Cycles of the gait flown in a row.
            const CYCLES: u32 = $cycles;

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
            fn init($cx: init::Context) -> (Shared, Local) {
                let (clock_hz, rate_hz): (u32, Option<u32>) = $clocks;
                let mut syst = $cx.core.SYST;
                let start =
                    pilot::start::<f32, $counter>($board, GAIT, &mut syst, clock_hz, rate_hz, CYCLES);
                let (pilot, timer, counts) =
                    start.unwrap_or_else(|e| $exit($crate::finish(Err(e))));
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
                pilot::idle::<f32, $counter>(*cx.local.counts, status, $exit)
            }

            /// One tick: one step of the law, the joints commanded, timed to the end of the handler.
            #[task(binds = SysTick, shared = [status], local = [pilot, timer])]
            fn tick(mut cx: tick::Context) {
                let (pilot, timer) = (cx.local.pilot, cx.local.timer);
                cx.shared.status.lock(|s| s.tick(pilot, CYCLES, timer));
            }
        }
    };
}
