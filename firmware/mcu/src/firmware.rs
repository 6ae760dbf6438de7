//! The QEMU firmware: flies the embedded gait with `purcell_fly` (the replay a board runs),
//! counting the instructions of every step, then measures the step's stack, flies again untimed
//! to check determinism, and exits through semihosting (status 0, or 1 on any failure: a gait
//! the core refuses, a HardFault, a panic).
//!
//! Default build (Cortex-M4F, QEMU `mps2-an386`): `f32`. Feature `m7` (Cortex-M7 with a
//! double-precision FPU, QEMU `mps2-an500`, built with `-C target-cpu=cortex-m7`): `f64`.
//! Feature `m3` (Cortex-M3 without FPU, QEMU `mps2-an385`, `thumbv7m-none-eabi`): `f32` in
//! software floating point.
//!
//! Counting: QEMU runs with `-icount shift=6`, so one instruction is 64 ns of virtual time, and
//! the SysTick, clocked at 25 MHz, advances exactly 8/5 ticks per instruction. The counter is
//! read before and after each step; differences are taken modulo its 24-bit wrap, so no
//! interrupt runs inside a measured step. A run of 1 000 `nop`s checks the conversion at
//! start-up (the firmware fails if QEMU was started without `-icount`). QEMU has no cycle
//! counter (its DWT reads 0): real hardware counts cycles, see `board-stm32f4-discovery/`.

use core::hint::black_box;
use cortex_m_rt::entry;
use defmt_semihosting as _;
use purcell_core::{Error, Gait, Replay, Sample};
use purcell_fly::Counter;
use purcell_mcu::Systick;

/// The gait flown: `$PURCELL_GAIT`, or the committed paper's gait (see `build.rs`).
static GAIT: &[u8] = include_bytes!(env!("PURCELL_GAIT_FILE"));

/// The scalar type flown on this board.
#[cfg(not(feature = "m7"))]
type S = f32;
/// The scalar type flown on this board.
#[cfg(feature = "m7")]
type S = f64;

/// The QEMU machine this build is for; the cargo runner looks for this tag in the ELF.
#[cfg(not(any(feature = "m7", feature = "m3")))]
#[used]
#[unsafe(no_mangle)]
static PURCELL_BOARD: [u8; 24] = *b"purcell-board:mps2-an386";
#[cfg(feature = "m3")]
#[used]
#[unsafe(no_mangle)]
static PURCELL_BOARD: [u8; 24] = *b"purcell-board:mps2-an385";
#[cfg(feature = "m7")]
#[used]
#[unsafe(no_mangle)]
static PURCELL_BOARD: [u8; 24] = *b"purcell-board:mps2-an500";

#[cfg(not(any(feature = "m7", feature = "m3")))]
const BOARD: &str = "mps2-an386";
#[cfg(feature = "m3")]
const BOARD: &str = "mps2-an385";
#[cfg(feature = "m7")]
const BOARD: &str = "mps2-an500";

/// Stack below the measuring function that is painted and scanned, bytes.
const STACK_WINDOW: usize = 16 * 1024;
const PAINT: u32 = 0xA5C3_5A3C;

/// Why the firmware fails (it then exits with status 1).
#[derive(Clone, Copy, Debug, defmt::Format)]
enum Failure {
    /// The core refused the gait or a step.
    Core(Error),
    /// The core peripherals were already taken.
    Peripherals,
    /// 1 000 extra `nop`s did not count as 1 000 instructions.
    Counting { nops: u64 },
    /// The stack of a step reached the bottom of the painted window.
    StackWindow,
    /// Two flights of the same gait differed.
    NotDeterministic,
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Failure::Core(e)
    }
}

/// Measures `f` on `input` (both passed through `black_box` inside the measured span, so the
/// compiler can neither hoist nor sink the work), net of `base`.
#[inline(always)]
fn measure<I, R>(base: u32, input: I, f: impl FnOnce(I) -> R) -> (u32, R) {
    let t0 = Systick::now();
    let r = black_box(f(black_box(input)));
    let t1 = Systick::now();
    (Systick::elapsed(t0, t1).saturating_sub(base), r)
}

/// One control step: the function whose instructions are counted and whose disassembly is
/// checked for soft-float helpers (`purcell-mcu-check disasm`).
#[inline(never)]
#[unsafe(no_mangle)]
fn purcell_mcu_step<'r>(replay: &'r mut Replay<'_, S>) -> Result<Option<&'r Sample<S>>, Error> {
    replay.step()
}

/// `N` `nop`s (and the call's own two instructions), to check the counter's conversion.
#[inline(never)]
fn nops<const N: usize>() {
    // SAFETY: `nop` has no effect.
    unsafe {
        core::arch::asm!(".rept {n}", "nop", ".endr", n = const N, options(nomem, nostack, preserves_flags));
    }
}

/// Checks that each extra 1 000 `nop`s count as 1 000 ± 1 instructions (the call itself
/// is the same in each measurement and cancels).
fn self_test(base: u32) -> Result<(), Failure> {
    let count = |f: fn()| purcell_fly::scaled::<Systick>(u64::from(measure(base, (), |()| f()).0));
    let (n0, n1, n2) = (count(nops::<0>), count(nops::<1000>), count(nops::<2000>));
    defmt::println!(
        "insn_calibration: overhead_ticks={=u32} call+0nop={=u64} call+1000nop={=u64} call+2000nop={=u64}",
        base,
        n0,
        n1,
        n2
    );
    for nops in [n1.wrapping_sub(n0), n2.wrapping_sub(n1)] {
        if nops.abs_diff(1000) > 1 {
            return Err(Failure::Counting { nops });
        }
    }
    Ok(())
}

/// Deepest stack use of one step over a whole replay, bytes: paints the stack below this
/// function's frame, replays, and finds the lowest word the steps overwrote.
#[inline(never)]
fn step_stack_bytes(gait: &Gait<'_>) -> Result<u32, Failure> {
    let mut replay = gait.replay::<S>()?;
    let sp = cortex_m::register::msp::read() as usize;
    let bottom = sp - STACK_WINDOW;
    for a in (bottom..sp).step_by(4) {
        // SAFETY: free stack below the current frame, inside RAM (the window is far smaller
        // than the RAM between the statics and the stack top); nothing else uses it now.
        unsafe { core::ptr::write_volatile(a as *mut u32, PAINT) };
    }
    while purcell_mcu_step(black_box(&mut replay))?.is_some() {}
    let lowest = (bottom..sp)
        .step_by(4)
        // SAFETY: as above; reading back the painted words.
        .find(|&a| unsafe { core::ptr::read_volatile(a as *const u32) } != PAINT)
        .unwrap_or(sp);
    if lowest == bottom {
        return Err(Failure::StackWindow);
    }
    Ok((sp - lowest) as u32)
}

fn run() -> Result<(), Failure> {
    let mut cp = cortex_m::Peripherals::take().ok_or(Failure::Peripherals)?;
    purcell_mcu::start_systick(&mut cp.SYST);
    let base = purcell_fly::overhead::<Systick>();
    self_test(base)?;
    defmt::println!("board_tag: {=[u8]:a}", black_box(&PURCELL_BOARD)[..]);

    let gait = purcell_fly::load(GAIT)?;
    let flight = purcell_fly::fly::<S, Systick, _>(BOARD, &gait, base, purcell_mcu_step)?;
    let stack = step_stack_bytes(&gait)?;
    defmt::println!("{=str}: bytes={=u32}", purcell_fly::line::STACK, stack);
    // The measured flight must be the plain one: fly again untimed.
    if gait.replay::<S>()?.fly(Replay::step)? != flight {
        return Err(Failure::NotDeterministic);
    }
    Ok(())
}

#[entry]
fn main() -> ! {
    semihosting::process::exit(purcell_fly::finish(run()))
}
