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
//! interrupt runs inside a measured step. Runs of 0, 1 000 and 2 000 `nop`s check the
//! conversion at start-up (the firmware fails if QEMU was started without `-icount`, see
//! [`self_test`]). QEMU has no cycle counter (its DWT reads 0): real hardware counts cycles,
//! see `board-stm32f4-discovery/`.

use core::hint::black_box;
use cortex_m_rt::entry;
use defmt_semihosting as _;
use purcell_core::cost::{Effort, RunningCost};
use purcell_core::{Cost, Error, Gait, Replay, Sample};
use purcell_fly::Counter;
use purcell_mcu::{Systick, TICKS_PER_INSN_DEN, TICKS_PER_INSN_NUM};

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
    /// `nops` `nop`s and the counter's read after them did not count as `nops + 1`
    /// instructions (`ticks` SysTick ticks, `insns` instructions).
    Counting { nops: u32, ticks: u32, insns: u64 },
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

/// One control step: the function whose instructions are counted and whose disassembly is
/// checked for soft-float helpers (`purcell-mcu-check disasm`).
#[inline(never)]
#[unsafe(no_mangle)]
fn purcell_mcu_step<'r>(replay: &'r mut Replay<'_, S>) -> Result<Option<&'r Sample<S>>, Error> {
    replay.step()
}

/// One control step of a gait solved for another cost than the effort (`solve --cost power`),
/// as [`purcell_mcu_step`] of the effort.
#[inline(never)]
fn cost_step<'r, C: RunningCost>(
    replay: &'r mut Replay<'_, S, C>,
) -> Result<Option<&'r Sample<S>>, Error> {
    replay.step()
}

/// SysTick ticks across `N` `nop`s: one `asm!` block reads the counter, runs the `nop`s and
/// reads it again, so the span is exactly the `N` `nop`s and the second read, wherever the code
/// lands and whatever the compiler schedules around the block.
#[inline(always)]
fn nop_ticks<const N: u32>() -> u32 {
    let (t0, t1): (u32, u32);
    // SAFETY: two reads of the SysTick's current-value register (no side effect) around
    // `nop`s; no memory written, no stack used, flags kept. `t0` is an `out`, so it is not
    // given `cvr`'s register.
    unsafe {
        core::arch::asm!(
            "ldr {t0}, [{cvr}]",
            ".rept {n}",
            "nop",
            ".endr",
            "ldr {t1}, [{cvr}]",
            cvr = in(reg) &raw const (*cortex_m::peripheral::SYST::PTR).cvr,
            t0 = out(reg) t0,
            t1 = out(reg) t1,
            n = const N,
            options(nostack, readonly, preserves_flags),
        );
    }
    Systick::elapsed(t0, t1)
}

/// Checks the counter's conversion: `N` `nop`s and the read after them (`N + 1` instructions,
/// `8(N + 1)/5` ticks of virtual time) must read as that many ticks rounded down or up, i.e.
/// `|5·ticks − 8(N + 1)| < 5`, for `N` = 0, 1 000 and 2 000.
///
/// Why a single `asm!` block: QEMU's `-icount` count is exact whatever the code layout (an
/// MMIO read ends its translation block, so the clock it reads includes every instruction
/// before it and itself), but a span timed from Rust is whatever the compiler puts between the
/// two reads. `compiler_fence` orders memory accesses only, so register-only instructions
/// can move into the span: the calibration used to time `nops::<N>()` calls from Rust, and
/// when removing `ArcSteps` from `purcell-fly` changed the register allocation of this
/// function, the `movw`/`movt` that load the next log line's index landed between the
/// 2 000-`nop` call and its second read (`call+2000nop=2006`, `Counting { nops: 1002 }`), at
/// any alignment of the `nop`s. Inside one `asm!` block nothing can be scheduled. (A step is
/// still timed from Rust, by `purcell_fly::fly` as on a board: its count may include the few
/// instructions the compiler puts around the call, the same in every step.)
fn self_test(overhead_ticks: u32) -> Result<(), Failure> {
    let runs = [
        (0, nop_ticks::<0>()),
        (1000, nop_ticks::<1000>()),
        (2000, nop_ticks::<2000>()),
    ];
    let insns = runs.map(|(_, ticks)| purcell_fly::scaled::<Systick>(u64::from(ticks)));
    defmt::println!(
        "insn_calibration: overhead_ticks={=u32} 0nop+read={=u64} 1000nop+read={=u64} 2000nop+read={=u64}",
        overhead_ticks,
        insns[0],
        insns[1],
        insns[2]
    );
    for ((nops, ticks), insns) in runs.into_iter().zip(insns) {
        let expected = TICKS_PER_INSN_NUM * u64::from(nops + 1);
        if (TICKS_PER_INSN_DEN * u64::from(ticks)).abs_diff(expected) >= TICKS_PER_INSN_DEN {
            return Err(Failure::Counting { nops, ticks, insns });
        }
    }
    Ok(())
}

/// Deepest stack use of one step over a whole replay, bytes: paints the stack below this
/// function's frame, replays, and finds the lowest word the steps overwrote.
#[inline(never)]
fn step_stack_bytes<L: RunningCost, F>(gait: &Gait<'_>, step: F) -> Result<u32, Failure>
where
    F: for<'r, 'a> Fn(&'r mut Replay<'a, S, L>) -> Result<Option<&'r Sample<S>>, Error>,
{
    let mut replay = gait.replay_for::<S, L>(true)?;
    let sp = cortex_m::register::msp::read() as usize;
    let bottom = sp - STACK_WINDOW;
    for a in (bottom..sp).step_by(4) {
        // SAFETY: free stack below the current frame, inside RAM (the window is far smaller
        // than the RAM between the statics and the stack top); nothing else uses it now.
        unsafe { core::ptr::write_volatile(a as *mut u32, PAINT) };
    }
    while step(black_box(&mut replay))?.is_some() {}
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
    // The law of the gait's cost, chosen once: each cost's step is its own code.
    // The effort's step is `purcell_mcu_step`, every other cost's `cost_step`.
    purcell_core::with_cost!(gait.params().cost, C => {
        if C::COST == Cost::Effort {
            fly_law::<Effort, _>(&gait, base, purcell_mcu_step)
        } else {
            fly_law::<C, _>(&gait, base, cost_step::<C>)
        }
    })
}

/// Flies `gait` with the law of `L` through `step` (timed), measures a step's stack, and
/// flies it again untimed: the measured flight must be the plain one.
fn fly_law<L: RunningCost, F>(gait: &Gait<'_>, base: u32, step: F) -> Result<(), Failure>
where
    F: for<'r, 'a> Fn(&'r mut Replay<'a, S, L>) -> Result<Option<&'r Sample<S>>, Error> + Copy,
{
    let flight = purcell_fly::fly::<S, Systick, L, _>(BOARD, gait, base, step)?;
    let stack = step_stack_bytes(gait, step)?;
    defmt::println!("{=str}: bytes={=u32}", purcell_fly::line::STACK, stack);
    if gait.replay_for::<S, L>(true)?.fly(Replay::step)? != flight {
        return Err(Failure::NotDeterministic);
    }
    Ok(())
}

#[entry]
fn main() -> ! {
    semihosting::process::exit(purcell_fly::finish(run()))
}
