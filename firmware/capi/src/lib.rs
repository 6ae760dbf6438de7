#![doc = include_str!("../README.md")]
#![no_std]
#![deny(missing_docs)]

// On the host the static library links std for its panic handler and unwinding (a C program
// links it with the libraries `cargo rustc -- --print native-static-libs` names); on a
// microcontroller the handler below stands in, and no panic is reachable from the API
// (firmware/c-example/check.sh finds no panic symbol in the library or the C firmware).
#[cfg(not(target_os = "none"))]
extern crate std;

mod status;
#[cfg(test)]
#[allow(
    clippy::unwrap_used,
    clippy::indexing_slicing,
    clippy::undocumented_unsafe_blocks
)]
mod tests;

use core::mem::{MaybeUninit, align_of, size_of};
use purcell_core::cost::RunningCost;
use purcell_core::gait::{AnyReplay, WithAnyReplay, WithVariant};
use purcell_core::{Cost, Gait, Replay, Sample, State, TrajectoryDigest};
pub use status::PurcellStatus;

/// `purcell_flight_open` option: keep the trajectory's digest (FNV-1a over every sample and
/// the final state, as the Rust firmware and `purcell-sim replay` print it). It adds about 200
/// instructions to a step of about 690 on a Cortex-M4F: a controller leaves it off.
pub const PURCELL_OPTION_DIGEST: u32 = 1;

/// The size of a `PurcellFlight` in 8-byte words: room for the flight on a 32-bit
/// microcontroller (456 bytes on a Cortex-M4F) and on a 64-bit host (512), with a margin
/// (checked at compile time on every target).
pub const PURCELL_FLIGHT_WORDS: usize = 80;

/// A flight's state, opaque: declare one (`static PurcellFlight flight;`), open it with
/// `purcell_flight_open`, step it with `purcell_flight_step`. Its size and alignment (8) are
/// fixed, so C allocates it statically; a zeroed one (as a static is) reports
/// `PURCELL_STATUS_NOT_OPEN` until opened.
#[repr(C)]
pub struct PurcellFlight {
    opaque: [u64; PURCELL_FLIGHT_WORDS],
}

/// A state `(α, g)` in `f32`: the shape and the pose `g = (x, y, θ)`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PurcellState {
    /// Joint angles `(α1, α2)`, radians.
    pub alpha: [f32; 2],
    /// Position `x` of the middle link, metres.
    pub x: f32,
    /// Position `y` of the middle link, metres.
    pub y: f32,
    /// `cos θ`, as the flight keeps it (the digest hashes it).
    pub cos_theta: f32,
    /// `sin θ`, as the flight keeps it (the digest hashes it).
    pub sin_theta: f32,
    /// `θ = atan2(sin θ, cos θ) ∈ ]−π, π]`, radians (computed when read).
    pub theta: f32,
}

/// One step `k` of a flight.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PurcellSample {
    /// Step index `k` (from 0).
    pub k: u32,
    /// Controls `u_k`: the joint rates over the step, rad/s (`α_{k+1} = α_k + h·u_k`).
    pub u: [f32; 2],
    /// The state `(α_k, g_k)` at the start of the step.
    pub state: PurcellState,
}

/// The gait a flight flies, and how far it is.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PurcellGaitInfo {
    /// Time step `h`, seconds: step the flight every `h` (the gait's rate is `1/h`).
    pub h: f64,
    /// Number of steps `N`.
    pub steps: u32,
    /// Steps run so far.
    pub steps_done: u32,
    /// Checkpoints in the gait's table.
    pub checkpoints: u32,
    /// Joint-limit arcs.
    pub arcs: u32,
    /// The gait file's CRC-32 (its last four bytes): a name for it in logs.
    pub crc: u32,
}

/// How far the final state is from the gait's target `(ᾱ, ḡ)`, in `f64`
/// (`purcell_core::TerminalError`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PurcellTerminalError {
    /// `max |α_N,i − ᾱ_i|`, radians.
    pub alpha: f64,
    /// `max |log(ḡ⁻¹ g_N)_j|`, metres or radians.
    pub g: f64,
}

/// An open flight: the gait, its replay in `f32` (the M4F's precision) and the digest.
struct Flying {
    gait: Gait<'static>,
    /// Through the law of the gait's cost.
    replay: AnyReplay<'static, f32>,
    digest: Option<TrajectoryDigest>,
    finished: bool,
}

/// What a [`PurcellFlight`] holds once opened (in place: the size of `Open` is what the
/// C caller reserves).
#[allow(clippy::large_enum_variant)]
enum Slot {
    Open(Flying),
    /// `purcell_flight_open` refused the gait: every call answers this.
    Refused(PurcellStatus),
}

/// The layout inside a [`PurcellFlight`]: `slot` is initialised when `magic` is [`MAGIC`].
#[repr(C)]
struct Stored {
    magic: u32,
    slot: MaybeUninit<Slot>,
}

/// `Stored::magic` of an opened flight ("PURC").
const MAGIC: u32 = u32::from_le_bytes(*b"PURC");

const _: () = {
    assert!(size_of::<Stored>() <= size_of::<PurcellFlight>());
    assert!(align_of::<Stored>() <= align_of::<PurcellFlight>());
};

/// `flight` as a pointer to its layout, or why it cannot be one.
fn layout(flight: *const PurcellFlight) -> Result<*mut Stored, PurcellStatus> {
    let stored = flight.cast::<Stored>().cast_mut();
    if stored.is_null() {
        Err(PurcellStatus::Null)
    } else if !stored.is_aligned() {
        Err(PurcellStatus::Misaligned)
    } else {
        Ok(stored)
    }
}

/// The slot of an opened flight.
///
/// # Safety
/// `flight` is NULL or points to a `PurcellFlight`, zeroed or opened.
unsafe fn slot(flight: *const PurcellFlight) -> Result<*mut Slot, PurcellStatus> {
    let stored = layout(flight)?;
    // SAFETY: non-null and aligned; valid by the caller's contract; any bits of a `u32` are
    // valid.
    if unsafe { (*stored).magic } != MAGIC {
        return Err(PurcellStatus::NotOpen);
    }
    // SAFETY: as above; `magic` is written with an initialised slot (`purcell_flight_open`).
    Ok(unsafe { &raw mut (*stored).slot }.cast())
}

/// The open flight behind `flight`, to read.
///
/// # Safety
/// As [`slot`], and not written elsewhere during `'f`.
unsafe fn flying<'f>(flight: *const PurcellFlight) -> Result<&'f Flying, PurcellStatus> {
    // SAFETY: an initialised slot (`slot`), not written elsewhere (the caller's contract).
    match unsafe { &*slot(flight)? } {
        Slot::Open(f) => Ok(f),
        Slot::Refused(s) => Err(*s),
    }
}

/// The open flight behind `flight`, to step.
///
/// # Safety
/// As [`slot`], and not accessed elsewhere during `'f`.
unsafe fn flying_mut<'f>(flight: *mut PurcellFlight) -> Result<&'f mut Flying, PurcellStatus> {
    // SAFETY: an initialised slot (`slot`), not accessed elsewhere (the caller's contract).
    match unsafe { &mut *slot(flight)? } {
        Slot::Open(f) => Ok(f),
        Slot::Refused(s) => Err(*s),
    }
}

/// Writes `value` to `out`, or reports a NULL `out`.
///
/// # Safety
/// `out` is NULL or valid for a write of a `T`.
unsafe fn put<T>(out: *mut T, value: Result<T, PurcellStatus>) -> PurcellStatus {
    if out.is_null() {
        return PurcellStatus::Null;
    }
    match value {
        Ok(v) => {
            // SAFETY: non-null and valid by the caller's contract.
            unsafe { out.write(v) };
            PurcellStatus::Ok
        }
        Err(s) => s,
    }
}

fn state(s: &State<f32>) -> PurcellState {
    let g = &s.g;
    PurcellState {
        alpha: [s.alpha.x, s.alpha.y],
        x: g.x(),
        y: g.y(),
        cos_theta: g.cos(),
        sin_theta: g.sin(),
        theta: g.theta(),
    }
}

fn sample(s: &Sample<f32>) -> PurcellSample {
    PurcellSample {
        k: s.k,
        u: [s.u.x, s.u.y],
        state: state(&s.state),
    }
}

/// Opens into `slot` the flight of the gait in `bytes`, checked as
/// `purcell_core::Gait::from_bytes` checks it, with its replay in `f32` of the gait's cost
/// ([`fly`]); the first error found otherwise. Not inlined, so that the reader's frame (the
/// deepest stack of a C flight) is not `purcell_flight_open`'s too.
#[inline(never)]
fn open(slot: &mut MaybeUninit<Slot>, bytes: &'static [u8], options: u32) -> PurcellStatus {
    if options & !PURCELL_OPTION_DIGEST != 0 {
        return PurcellStatus::BadOptions;
    }
    match Gait::from_bytes(bytes) {
        Ok(gait) => AnyReplay::for_cost(
            gait.params().cost,
            Fly {
                slot,
                gait,
                options,
            },
        ),
        Err(e) => e.into(),
    }
}

/// [`fly`] for the gait's cost.
struct Fly<'s> {
    slot: &'s mut MaybeUninit<Slot>,
    gait: Gait<'static>,
    options: u32,
}

impl WithVariant<'static, f32> for Fly<'_> {
    type Output = PurcellStatus;
    #[inline(always)]
    fn run<C: RunningCost>(
        self,
        any: fn(Replay<'static, f32, C>) -> AnyReplay<'static, f32>,
    ) -> PurcellStatus {
        fly(self.slot, self.gait, self.options, any)
    }
}

/// Writes the open flight of `gait`, its replay in `f32` of the cost `C` (the gait's),
/// into `slot`; the replay's error otherwise. One call per cost, not inlined, each replay
/// built in its own frame and written once.
#[inline(never)]
fn fly<C: RunningCost>(
    slot: &mut MaybeUninit<Slot>,
    gait: Gait<'static>,
    options: u32,
    any: fn(Replay<'static, f32, C>) -> AnyReplay<'static, f32>,
) -> PurcellStatus {
    match gait.replay_for(true) {
        Ok(replay) => {
            slot.write(Slot::Open(Flying {
                gait,
                replay: any(replay),
                digest: (options & PURCELL_OPTION_DIGEST != 0).then(TrajectoryDigest::new),
                finished: false,
            }));
            PurcellStatus::Ok
        }
        Err(e) => e.into(),
    }
}

/// Opens a flight of the gait file in `gait[0..len]` (`purcell-sim export`'s bytes, e.g. the
/// array `--format c` writes): checks every value as the Rust reader does, in the same order
/// (the first error found is returned; the flight then answers it to every call), and
/// prepares its replay in `f32`. `options`: 0, or `PURCELL_OPTION_DIGEST`.
///
/// # Safety
/// `flight` is NULL or points to a `PurcellFlight` not accessed elsewhere during the call;
/// `gait` is NULL or points to `len` bytes that stay valid and unchanged as long as the
/// flight is used (a `const` array in flash is).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn purcell_flight_open(
    flight: *mut PurcellFlight,
    gait: *const u8,
    len: usize,
    options: u32,
) -> PurcellStatus {
    let stored = match layout(flight) {
        Ok(s) => s,
        Err(e) => return e,
    };
    // SAFETY: non-null and aligned (`layout`), valid and not accessed elsewhere (the caller's
    // contract); any bits are a valid `MaybeUninit`.
    let slot = unsafe { &mut (*stored).slot };
    let status = if gait.is_null() {
        PurcellStatus::Null
    } else {
        // SAFETY: `len` bytes at `gait`, valid and unchanged while the flight is used.
        open(
            slot,
            unsafe { core::slice::from_raw_parts(gait, len) },
            options,
        )
    };
    if status != PurcellStatus::Ok {
        slot.write(Slot::Refused(status));
    }
    // SAFETY: as above; the slot is initialised.
    unsafe { (*stored).magic = MAGIC };
    status
}

/// Runs the next step of the control law in place: `PURCELL_STATUS_OK` (its sample is then
/// readable), `PURCELL_STATUS_FINISHED` once every step has run, or the step's error (the
/// flight then stays failed and returns it again).
///
/// # Safety
/// `flight` is NULL or points to a `PurcellFlight`, zeroed or opened, not accessed elsewhere
/// during the call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn purcell_flight_step(flight: *mut PurcellFlight) -> PurcellStatus {
    // SAFETY: the caller's contract.
    let f = match unsafe { flying_mut(flight) } {
        Ok(f) => f,
        Err(e) => return e,
    };
    let (replay, digest, finished) = (&mut f.replay, &mut f.digest, &mut f.finished);
    replay.with_mut(Step { digest, finished })
}

/// [`purcell_flight_step`] in the replay of the gait's cost: the effort's step inlined as
/// before the power existed (a match on the result of either would cost the effort's step 10
/// instructions on the M4F), every other cost's a call ([`step_out_of_line`]).
struct Step<'f> {
    digest: &'f mut Option<TrajectoryDigest>,
    finished: &'f mut bool,
}

impl WithAnyReplay<'static, f32> for Step<'_> {
    type Output = PurcellStatus;
    #[inline(always)]
    fn run<C: RunningCost>(self, replay: &mut Replay<'static, f32, C>) -> PurcellStatus {
        if C::COST == Cost::Effort {
            step(replay, self.digest, self.finished)
        } else {
            step_out_of_line(replay, self.digest, self.finished)
        }
    }
}

/// [`purcell_flight_step`] of a gait of the cost `C`: the digest of `Replay::fly`, every
/// sample, then the final state once.
#[inline(always)]
fn step<C: RunningCost>(
    replay: &mut Replay<'static, f32, C>,
    digest: &mut Option<TrajectoryDigest>,
    finished: &mut bool,
) -> PurcellStatus {
    match replay.step() {
        Ok(Some(sample)) => {
            if let Some(d) = digest {
                d.push_sample(sample);
            }
            PurcellStatus::Ok
        }
        Ok(None) => {
            if let Some(d) = digest.as_mut().filter(|_| !*finished) {
                d.push_state(replay.state());
            }
            *finished = true;
            PurcellStatus::Finished
        }
        Err(e) => e.into(),
    }
}

/// [`step`] of a gait of a cost other than the effort, not inlined.
#[inline(never)]
fn step_out_of_line<C: RunningCost>(
    replay: &mut Replay<'static, f32, C>,
    digest: &mut Option<TrajectoryDigest>,
    finished: &mut bool,
) -> PurcellStatus {
    step(replay, digest, finished)
}

/// Writes the last step's sample to `out`; `PURCELL_STATUS_NO_SAMPLE` before the first step.
///
/// # Safety
/// `flight` is NULL or points to a `PurcellFlight`, zeroed or opened, not written elsewhere
/// during the call; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn purcell_flight_sample(
    flight: *const PurcellFlight,
    out: *mut PurcellSample,
) -> PurcellStatus {
    // SAFETY: the caller's contract.
    let value = unsafe { flying(flight) }.and_then(|f| {
        let last = f.replay.last_sample();
        last.map(sample).ok_or(PurcellStatus::NoSample)
    });
    // SAFETY: the caller's contract.
    unsafe { put(out, value) }
}

/// Writes the current state to `out`: `(α_k, g_k)` before step `k`, the final state
/// `(α_N, g_N)` once finished.
///
/// # Safety
/// As `purcell_flight_sample`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn purcell_flight_state(
    flight: *const PurcellFlight,
    out: *mut PurcellState,
) -> PurcellStatus {
    // SAFETY: the caller's contract.
    let value = unsafe { flying(flight) }.map(|f| state(f.replay.state()));
    // SAFETY: the caller's contract.
    unsafe { put(out, value) }
}

/// Writes the gait's parameters and the steps run so far to `out`.
///
/// # Safety
/// As `purcell_flight_sample`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn purcell_flight_info(
    flight: *const PurcellFlight,
    out: *mut PurcellGaitInfo,
) -> PurcellStatus {
    let count = |n: usize| u32::try_from(n).unwrap_or(u32::MAX);
    // SAFETY: the caller's contract.
    let value = unsafe { flying(flight) }.map(|f| PurcellGaitInfo {
        h: f.gait.params().h,
        steps: f.gait.params().steps,
        steps_done: f.replay.steps_done(),
        checkpoints: count(f.gait.checkpoint_count()),
        arcs: count(f.gait.arc_count()),
        crc: f.gait.crc(),
    });
    // SAFETY: the caller's contract.
    unsafe { put(out, value) }
}

/// Writes the digest of the whole flight to `out`: the one the Rust firmware and
/// `purcell-sim replay --precision f32` print (`digest: 0x…`). Needs a finished flight opened
/// with `PURCELL_OPTION_DIGEST`.
///
/// # Safety
/// As `purcell_flight_sample`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn purcell_flight_digest(
    flight: *const PurcellFlight,
    out: *mut u64,
) -> PurcellStatus {
    // SAFETY: the caller's contract.
    let value = unsafe { flying(flight) }.and_then(|f| match (f.digest, f.finished) {
        (None, _) => Err(PurcellStatus::NoDigest),
        (Some(_), false) => Err(PurcellStatus::NotFinished),
        (Some(d), true) => Ok(d.value()),
    });
    // SAFETY: the caller's contract.
    unsafe { put(out, value) }
}

/// Writes how far the finished flight ended from the gait's target to `out`.
///
/// # Safety
/// As `purcell_flight_sample`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn purcell_flight_terminal_error(
    flight: *const PurcellFlight,
    out: *mut PurcellTerminalError,
) -> PurcellStatus {
    // SAFETY: the caller's contract.
    let value = unsafe { flying(flight) }.and_then(|f| {
        if !f.finished {
            return Err(PurcellStatus::NotFinished);
        }
        let e = f.gait.params().terminal_error(f.replay.state());
        Ok(PurcellTerminalError {
            alpha: e.alpha,
            g: e.g,
        })
    });
    // SAFETY: the caller's contract.
    unsafe { put(out, value) }
}

/// Writes the message of `status` (any value a function returned) to `buf`, cut to
/// `cap − 1` bytes and NUL-terminated as `snprintf` does (nothing written if `cap` is 0);
/// returns the message's full length (0 for a number that is no status).
///
/// # Safety
/// `buf` is NULL (then nothing is written) or valid for `cap` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn purcell_status_message(
    status: i32,
    buf: *mut core::ffi::c_char,
    cap: usize,
) -> usize {
    let text = PurcellStatus::message(status).unwrap_or("").as_bytes();
    if !buf.is_null() && cap > 0 {
        let n = text.len().min(cap - 1);
        // SAFETY: `buf` is valid for `cap > n` bytes; `text` does not overlap it.
        unsafe {
            core::ptr::copy_nonoverlapping(text.as_ptr(), buf.cast::<u8>(), n);
            buf.add(n).write(0);
        }
    }
    text.len()
}

#[cfg(all(target_os = "none", not(test)))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    // Unreachable from the API: no panic symbol is left in the library (c-example/check.sh).
    loop {}
}
