//! What every firmware on QEMU's boards shares (the flight, `src/firmware.rs`, and the control
//! loop, `examples/control_loop.rs`): the SysTick as an instruction counter, and the fault and
//! panic handlers that log and exit through semihosting with status 1.

use core::sync::atomic::{AtomicBool, Ordering, compiler_fence};
use cortex_m_rt::{ExceptionFrame, exception};
use purcell_fly::Counter;

/// Instructions, counted by the SysTick under `-icount shift=6` (see [`crate::systick_elapsed`]).
pub struct Systick;

impl Counter for Systick {
    const LINE: &'static str = purcell_fly::line::INSN;
    /// Instructions per tick: 5/8.
    const SCALE: (u64, u64) = (crate::TICKS_PER_INSN_DEN, crate::TICKS_PER_INSN_NUM);

    #[inline(always)]
    fn now() -> u32 {
        compiler_fence(Ordering::SeqCst);
        let t = cortex_m::peripheral::SYST::get_current();
        compiler_fence(Ordering::SeqCst);
        t
    }

    #[inline(always)]
    fn elapsed(start: u32, end: u32) -> u32 {
        crate::systick_elapsed(start, end)
    }
}

/// Starts the SysTick free-running over its 24 bits, without interrupts.
pub fn start_systick(syst: &mut cortex_m::peripheral::SYST) {
    use cortex_m::peripheral::syst::SystClkSource;
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(0x00FF_FFFF);
    syst.clear_current();
    syst.disable_interrupt();
    syst.enable_counter();
}

/// Set by the first fault or panic: a second one exits at once without logging (the logger
/// may be what failed).
static FAILING: AtomicBool = AtomicBool::new(false);

fn fail_once(log: impl FnOnce()) -> ! {
    compiler_fence(Ordering::SeqCst);
    if !FAILING.swap(true, Ordering::Relaxed) {
        log();
    }
    semihosting::process::exit(1)
}

#[exception]
unsafe fn HardFault(ef: &ExceptionFrame) -> ! {
    fail_once(|| defmt::error!("HardFault at pc={=u32:#x}", ef.pc()))
}

#[exception]
unsafe fn DefaultHandler(irqn: i16) {
    fail_once(|| defmt::error!("unexpected exception {=i16}", irqn))
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    fail_once(|| match info.location() {
        Some(l) => defmt::error!("panic at {=str}:{=u32}", l.file(), l.line()),
        None => defmt::error!("panic"),
    })
}
