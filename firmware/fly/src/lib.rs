//! Flies a gait on a microcontroller: the replay every firmware of this repository runs, timed
//! step by step, digested, and reported in the log lines ([`line`](mod@line)) that
//! `purcell-mcu-check` reads.
//!
//! The board example (`../board-stm32f4-discovery`, DWT cycles) and the QEMU firmware
//! (`../mcu`, instructions under `-icount`) both call [`fly`], so what CI checks in QEMU is
//! what a board runs. Copy this file into your firmware, or depend on it, with a [`Counter`]
//! for your chip.
//!
//! The lines (defmt, printed with `defmt-print --log-format '{s}'`):
//!
//! ```text
//! purcell-mcu: board=<name> scalar=<f32|f64> steps=<N> passes=<P> checkpoints=<C> arcs=<A> gait=<crc32>
//! <cycles_per_step|insn_per_step>: mean=<M.m> max=<X>
//! arc_steps: steps=<n> mean=<M.m> max=<X> free_mean=<F.f> free_max=<Y>
//! replay_total: steps=<N> units=<sum>
//! digest: 0x<16 hex digits>
//! final_state_bits: <0x…> ×6
//! ```
//!
//! and [`finish`] ends the run with `result: ok` (or `failed: <why>`). `arc_steps` splits the
//! per-step figures (same units) between the steps with a joint at rest on a joint-limit arc
//! (its `mean`, `max`; all zero for a gait without arcs) and the others (`free_…`).

#![no_std]
#![deny(missing_docs)]

use purcell_core::cost::RunningCost;
use purcell_core::gait::Stored;
use purcell_core::{Error, Flight, Gait, OnArcs, Replay, Sample};

/// The names of the log lines (`<name>: …`), the one definition for the firmware that prints
/// them and the checker that reads them.
pub mod line {
    /// `purcell-mcu: board=<name> scalar=<f32|f64> steps=<N> passes=<P> checkpoints=<C>
    /// arcs=<A> gait=<crc32>`.
    pub const HEADER: &str = "purcell-mcu";
    /// `insn_per_step: mean=<M> max=<X>` (instructions per control step, QEMU).
    pub const INSN: &str = "insn_per_step";
    /// `cycles_per_step: mean=<M> max=<X>` (cycles per control step, a board's counter).
    pub const CYCLES: &str = "cycles_per_step";
    /// `arc_steps: steps=<n> mean=<M> max=<X> free_mean=<F> free_max=<Y>` (the per-step
    /// figures of the steps with a joint at rest on a joint-limit arc, and of the others).
    pub const ARCS: &str = "arc_steps";
    /// `replay_total: steps=<N> units=<sum>` (the per-step figures' sum).
    pub const TOTAL: &str = "replay_total";
    /// `stack_step: bytes=<B>` (deepest stack use below the caller of one step, QEMU).
    pub const STACK: &str = "stack_step";
    /// `digest: <0x…>` (`purcell_core::TrajectoryDigest` of the whole flight).
    pub const DIGEST: &str = "digest";
    /// `final_state_bits: <0x…> ×6` (`α1 α2 x y cos θ sin θ` as raw bits).
    pub const FINAL: &str = "final_state_bits";
    /// `result: ok`, the last line of a successful run ([`finish`](super::finish)).
    pub const RESULT: &str = "result";
    /// The value of [`RESULT`] on success.
    pub const OK: &str = "ok";
    /// `purcell-loop: board=<name> scalar=<f32|f64> steps=<N> h=<s> period=<P> unit=<insn|cycles>
    /// cycles=<C> gait=<crc32>`, a control loop's header ([`pilot`](crate::pilot)).
    pub const LOOP: &str = "purcell-loop";
    /// `cycle: n=<c> digest=<0x…> pose_bits=<0x…> ×4 x=<m> y=<m> theta=<rad>`, the end of a cycle
    /// (`pose_bits`: `x y cos θ sin θ` of the body's pose as raw bits).
    pub const CYCLE: &str = "cycle";
    /// `ticks: unit=<insn|cycles> count=<n> mean=<M> max=<X> period=<P> margin=<P−X>
    /// overruns=<o>`, each tick from the timer's expiry to the end of its handler.
    pub const TICKS: &str = "ticks";
    /// `joints: commands=<n> rates=<u1> <u2> angles=<α1> <α2>`, the joints' last commands.
    pub const JOINTS: &str = "joints";
}

mod control_loop;
pub mod pilot;

/// `f32` or `f64`: the name of `S` in the log lines.
pub fn scalar_name<S: Stored>() -> &'static str {
    if core::mem::size_of::<S>() == 4 {
        "f32"
    } else {
        "f64"
    }
}

/// A free-running counter that times each step.
pub trait Counter {
    /// The line that reports the figures: [`line::CYCLES`] or [`line::INSN`].
    const LINE: &'static str;
    /// Reported units per raw count, as `(numerator, denominator)`.
    const SCALE: (u64, u64) = (1, 1);
    /// The raw count now (read between compiler fences, so no work moves across it).
    fn now() -> u32;
    /// Raw counts from `start` to `end` (an up-counter that wraps at `2³²` by default).
    fn elapsed(start: u32, end: u32) -> u32 {
        end.wrapping_sub(start)
    }
}

/// Core clock cycles from the DWT cycle counter (a board's [`Counter`]; QEMU's DWT reads 0).
/// Start it first: `DCB::enable_trace`, `DWT::unlock` (Cortex-M7), `DWT::enable_cycle_counter`.
pub struct DwtCycles;

impl Counter for DwtCycles {
    const LINE: &'static str = line::CYCLES;

    #[inline(always)]
    fn now() -> u32 {
        core::sync::atomic::compiler_fence(core::sync::atomic::Ordering::SeqCst);
        let t = cortex_m::peripheral::DWT::cycle_count();
        core::sync::atomic::compiler_fence(core::sync::atomic::Ordering::SeqCst);
        t
    }
}

/// Running mean and maximum of per-step counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Number of samples.
    pub n: u32,
    /// Sum of the samples.
    pub sum: u64,
    /// Largest sample.
    pub max: u32,
}

impl Stats {
    /// Adds one sample.
    pub fn add(&mut self, x: u32) {
        self.n += 1;
        self.sum += u64::from(x);
        self.max = self.max.max(x);
    }
}

/// `raw` counts in `C`'s reported units, rounded to nearest.
pub fn scaled<C: Counter>(raw: u64) -> u64 {
    let (num, den) = C::SCALE;
    (raw * num + den / 2) / den
}

/// The mean of `stats` in `C`'s reported units, as (integer part, tenths), rounded to nearest.
pub fn scaled_mean<C: Counter>(stats: &Stats) -> (u64, u64) {
    let (num, den) = C::SCALE;
    let n = u64::from(stats.n.max(1));
    let tenths = (stats.sum * 10 * num + n * den / 2) / (n * den);
    (tenths / 10, tenths % 10)
}

/// The smallest raw count of an empty measurement (two back-to-back reads): subtracted from
/// every step's count.
pub fn overhead<C: Counter>() -> u32 {
    let mut least = u32::MAX;
    for _ in 0..16 {
        let t0 = C::now();
        let t1 = C::now();
        least = least.min(C::elapsed(t0, t1));
    }
    least
}

/// Reads the gait embedded with `include_bytes!`; a refused one is logged
/// (`gait refused: <reason>`) and its error returned.
pub fn load(bytes: &[u8]) -> Result<Gait<'_>, Error> {
    Gait::from_bytes(bytes).inspect_err(|e| defmt::error!("gait refused: {}", e))
}

/// Flies `gait` in `S` with its checkpoints and the law of `L`, the gait's cost
/// ([`Gait::replay_for`]; [`purcell_core::cost::Effort`] for the paper's): prints the header, runs every step through `step`
/// (normally [`Replay::step`], or a non-inlined wrapper of it to find in a disassembly) timed
/// by `C` net of `overhead` raw counts, then prints the per-step figures, the total, the
/// digest and the final state's bits.
///
/// Errors: the core's, for a gait it cannot replay in `S` or with `L`, or a failing step.
pub fn fly<'a, S, C, L, F>(
    board: &str,
    gait: &Gait<'a>,
    overhead: u32,
    mut step: F,
) -> Result<Flight<S>, Error>
where
    S: Stored,
    C: Counter,
    L: RunningCost,
    F: for<'r> FnMut(&'r mut Replay<'a, S, L>) -> Result<Option<&'r Sample<S>>, Error>,
{
    let replay = gait.replay_for::<S, L>(true)?;
    defmt::println!(
        "{=str}: board={=str} scalar={=str} steps={=u32} passes={=usize} checkpoints={=usize} arcs={=usize} gait={=u32:#010x}",
        line::HEADER,
        board,
        scalar_name::<S>(),
        gait.params().steps,
        S::PASSES.count,
        gait.checkpoint_count(),
        gait.arc_count(),
        gait.crc()
    );
    let (mut stats, mut free, mut on_arcs) = (Stats::default(), Stats::default(), Stats::default());
    let flight = replay.fly(|r| {
        let t0 = C::now();
        let item = step(r);
        let t1 = C::now();
        let stepped = item.map(|sample| sample.is_some());
        let r: &Replay<'a, S, L> = r;
        if let Ok(true) = stepped {
            let units = C::elapsed(t0, t1).saturating_sub(overhead);
            stats.add(units);
            let on_arc = r.on_arcs() != OnArcs::NONE;
            (if on_arc { &mut on_arcs } else { &mut free }).add(units);
        }
        stepped.map(|stepped| r.last_sample().filter(|_| stepped))
    })?;
    let (mean, tenths) = scaled_mean::<C>(&stats);
    defmt::println!(
        "{=str}: mean={=u64}.{=u64} max={=u64}",
        C::LINE,
        mean,
        tenths,
        scaled::<C>(u64::from(stats.max))
    );
    let ((arc_mean, arc_tenths), (free_mean, free_tenths)) =
        (scaled_mean::<C>(&on_arcs), scaled_mean::<C>(&free));
    defmt::println!(
        "{=str}: steps={=u32} mean={=u64}.{=u64} max={=u64} free_mean={=u64}.{=u64} free_max={=u64}",
        line::ARCS,
        on_arcs.n,
        arc_mean,
        arc_tenths,
        scaled::<C>(u64::from(on_arcs.max)),
        free_mean,
        free_tenths,
        scaled::<C>(u64::from(free.max))
    );
    defmt::println!(
        "{=str}: steps={=u32} units={=u64}",
        line::TOTAL,
        stats.n,
        scaled::<C>(stats.sum)
    );
    defmt::println!("{=str}: {=u64:#018x}", line::DIGEST, flight.digest.value());
    let b = flight.final_bits();
    defmt::println!(
        "{=str}: {=u64:#x} {=u64:#x} {=u64:#x} {=u64:#x} {=u64:#x} {=u64:#x}",
        line::FINAL,
        b[0],
        b[1],
        b[2],
        b[3],
        b[4],
        b[5]
    );
    Ok(flight)
}

/// Ends a run: logs `result: ok`, or `failed: <why>` for an error, and returns the exit status
/// for the caller's exit (0 on success, 1 on failure).
pub fn finish<E: defmt::Format>(run: Result<(), E>) -> i32 {
    match run {
        Ok(()) => {
            defmt::println!("{=str}: {=str}", line::RESULT, line::OK);
            0
        }
        Err(e) => {
            defmt::error!("failed: {}", e);
            1
        }
    }
}
