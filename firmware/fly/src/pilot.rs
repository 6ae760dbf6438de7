//! A gait flown as a control loop: one step of the law per tick of a periodic timer at the
//! gait's rate `1/h`, the joints commanded from each step's sample, the gait flown cycle after
//! cycle.
//!
//! The problem is left-invariant: a gait found from the identity flies the same from any pose
//! `P`, its positions becoming `P·g_k`. So every cycle replays the same gait from its start,
//! with the same costate, and the body's pose composes: after cycle `c`,
//! `P_c = P_{c−1}·g_N` (`P_0` the identity, `g_N` where one flight of the gait ends). Each
//! cycle's [`TrajectoryDigest`] is the one flight's (the gait's positions stay relative to the
//! cycle's start), so a host checks every cycle against `purcell-sim replay`, and the poses
//! against the same composition in the same precision.
//!
//! [`Pilot::tick`] is what a timer interrupt calls; timing it is the firmware's (the QEMU
//! example and the board's `control_loop` time it from the SysTick, [`TickStats`]).

use crate::{Counter, Stats, line, scaled, scaled_mean};
use core::sync::atomic::{Ordering, compiler_fence};
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::{SCB, SYST};
use purcell_core::Real;
use purcell_core::cost::RunningCost;
use purcell_core::gait::{AnyReplay, Stored, WithAnyReplay};
use purcell_core::nalgebra::Vector2;
use purcell_core::{Cost, Error, Gait, Replay, Se2, TrajectoryDigest};

/// Where the joint commands go: a motor driver on a robot, a recorder in QEMU.
pub trait Joints<S> {
    /// The joint rates `u_k` (rad/s) to hold over the coming period.
    fn set_joint_rates(&mut self, u: &Vector2<S>);
    /// The joint angles `α_{k+1}` (rad) to reach at the end of the coming period (for
    /// position-controlled joints).
    fn set_joint_angles(&mut self, alpha: &Vector2<S>);
}

/// Keeps the last commands and counts them (the QEMU example's joints; a stand-in on a board).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LastCommand<S: Real> {
    /// The last `u_k`.
    pub rates: Vector2<S>,
    /// The last `α_{k+1}`.
    pub angles: Vector2<S>,
    /// Commands received (rates and angles count once together).
    pub count: u32,
}

impl<S: Real> Joints<S> for LastCommand<S> {
    fn set_joint_rates(&mut self, u: &Vector2<S>) {
        self.rates = *u;
        self.count += 1;
    }

    fn set_joint_angles(&mut self, alpha: &Vector2<S>) {
        self.angles = *alpha;
    }
}

/// The end of one cycle of the gait.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CycleEnd<S> {
    /// Cycles flown so far, this one included (1 for the first).
    pub cycle: u32,
    /// The cycle's digest: every sample, then its final state, relative to its start.
    pub digest: TrajectoryDigest,
    /// The body's pose now, `P_c = P_{c−1}·g_N`.
    pub pose: Se2<S>,
}

/// The gait flown cycle after cycle, one step per [`Pilot::tick`], through the law of the
/// gait's cost ([`AnyReplay`]).
#[derive(Clone, Debug)]
pub struct Pilot<'a, S> {
    /// The gait's replay before its first step, checked once by the core: each cycle starts
    /// from a copy (checking the gait's checkpoints again costs about 10 000 instructions on
    /// the M4F, 15 steps, in the tick that ends a cycle).
    fresh: AnyReplay<'a, S>,
    steps: u32,
    replay: AnyReplay<'a, S>,
    digest: TrajectoryDigest,
    /// `P_{c−1}`, the pose the current cycle started from.
    start: Se2<S>,
    cycle: u32,
}

impl<'a, S: Stored> Pilot<'a, S> {
    /// A pilot at the identity pose, before the first step of the first cycle.
    ///
    /// Errors: the core's, for a gait it cannot replay in `S`.
    pub fn new(gait: Gait<'a>) -> Result<Self, Error> {
        let fresh = gait.replay_any()?;
        Ok(Pilot {
            replay: fresh.clone(),
            fresh,
            steps: gait.params().steps,
            digest: TrajectoryDigest::new(),
            start: Se2::identity(),
            cycle: 0,
        })
    }

    /// One tick: steps the law once, commands the joints with the sample's `u_k` and the next
    /// shape `α_{k+1}`, and after the gait's last step closes the cycle (its digest and the
    /// composed pose) and restarts the gait from its start, so the next tick begins the next
    /// cycle.
    ///
    /// Errors: the core's, for a failing step.
    pub fn tick<J: Joints<S>>(&mut self, joints: &mut J) -> Result<Option<CycleEnd<S>>, Error> {
        let closed = self.replay.with_mut(Advance {
            steps: self.steps,
            digest: &mut self.digest,
            start: &mut self.start,
            cycle: &mut self.cycle,
            joints,
        })?;
        if closed.is_some() {
            self.replay = self.fresh.clone();
        }
        Ok(closed)
    }
}

/// [`Pilot::tick`] in the replay of the gait's cost, all but the restart: the effort's step
/// inlined as before the power existed, every other cost's a call ([`advance_out_of_line`]);
/// the cycle closed in each cost's own code (closed after a match on the step's result, the
/// effort's tick cost about 20 instructions more on the M4F).
struct Advance<'t, S: Real, J> {
    steps: u32,
    digest: &'t mut TrajectoryDigest,
    start: &'t mut Se2<S>,
    cycle: &'t mut u32,
    joints: &'t mut J,
}

impl<'a, S: Stored, J: Joints<S>> WithAnyReplay<'a, S> for Advance<'_, S, J> {
    type Output = Result<Option<CycleEnd<S>>, Error>;
    #[inline(always)]
    fn run<C: RunningCost>(self, replay: &mut Replay<'a, S, C>) -> Self::Output {
        let ended = if C::COST == Cost::Effort {
            advance(replay, self.steps, self.digest, self.joints)?
        } else {
            advance_out_of_line(replay, self.steps, self.digest, self.joints)?
        };
        if !ended {
            return Ok(None);
        }
        let end = replay.state();
        self.digest.push_state(end);
        *self.start = self.start.compose(&end.g);
        *self.cycle += 1;
        Ok(Some(CycleEnd {
            cycle: *self.cycle,
            digest: core::mem::take(self.digest),
            pose: *self.start,
        }))
    }
}

/// One step of [`Pilot::tick`] in a replay of the cost `C`: the sample into `digest`, the
/// joints commanded; whether it was the gait's last (`steps`-th) step.
#[inline(always)]
fn advance<S: Stored, C: RunningCost, J: Joints<S>>(
    replay: &mut Replay<'_, S, C>,
    steps: u32,
    digest: &mut TrajectoryDigest,
    joints: &mut J,
) -> Result<bool, Error> {
    // A replay always has a step left: the last one restarts it ([`Pilot::tick`]).
    let sample = replay.step()?.ok_or(Error::InvalidStep)?;
    digest.push_sample(sample);
    joints.set_joint_rates(&sample.u);
    joints.set_joint_angles(&replay.state().alpha);
    Ok(replay.steps_done() >= steps)
}

/// [`advance`] of a gait of a cost other than the effort, not inlined.
#[inline(never)]
fn advance_out_of_line<S: Stored, C: RunningCost, J: Joints<S>>(
    replay: &mut Replay<'_, S, C>,
    steps: u32,
    digest: &mut TrajectoryDigest,
    joints: &mut J,
) -> Result<bool, Error> {
    advance(replay, steps, digest, joints)
}

/// The timer counts of one period `h` on a timer clocked at `clock_hz`, rounded to nearest:
/// `None` unless it is between 2 and `max`.
pub fn period_counts(h: f64, clock_hz: u32, max: u32) -> Option<u32> {
    let counts = h * f64::from(clock_hz) + 0.5;
    (counts >= 2.0 && counts <= f64::from(max)).then_some(counts as u32)
}

/// The ticks' timing, in the timer's raw counts: each tick from the timer's expiry to the end
/// of its handler (the latency before the handler runs included), and the overruns (a tick
/// that expired again before its handler ended).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TickStats {
    /// Counts from expiry to the handler's end.
    pub ticks: Stats,
    /// Ticks whose handler ran into the next period.
    pub overruns: u32,
}

impl TickStats {
    /// Adds one tick: `counts` since its expiry, `overran` if the next one has expired since.
    pub fn add(&mut self, counts: u32, overran: bool) {
        self.ticks.add(counts);
        self.overruns += u32::from(overran);
    }
}

/// What the timer's handler shares with the idle loop that logs: the last cycle closed, the
/// ticks' timing, the joints' last commands, and how the flight ended.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Status<S: Real> {
    /// The last cycle closed.
    pub last: Option<CycleEnd<S>>,
    /// The ticks' timing.
    pub ticks: TickStats,
    /// The joints' last commands. On a robot, drive the motors from them after each
    /// [`Status::tick`], or call [`Pilot::tick`] with your driver's [`Joints`].
    pub joints: LastCommand<S>,
    /// `Some` once the flight is over: all cycles flown, or the core's error.
    pub end: Option<Result<(), Error>>,
}

impl<S: Stored> Status<S> {
    /// Runs one tick of `pilot` (nothing once the flight is over), commanding `self.joints`,
    /// ends the flight after `cycles` cycles or at an error, and times the tick by `timer`
    /// (call it last in the timer's handler).
    pub fn tick(&mut self, pilot: &mut Pilot<'_, S>, cycles: u32, timer: &SysTickTimer) {
        if self.end.is_some() {
            return;
        }
        match pilot.tick(&mut self.joints) {
            Ok(None) => {}
            Ok(Some(end)) => {
                self.last = Some(end);
                if end.cycle >= cycles {
                    self.end = Some(Ok(()));
                }
            }
            Err(e) => self.end = Some(Err(e)),
        }
        let (counts, overran) = timer.since_expiry();
        self.ticks.add(counts, overran);
    }
}

/// The SysTick as the loop's timer, on the core clock: it expires every `counts` clocks and
/// its handler runs the tick; how far it has counted down since tells the time since the
/// expiry, and its pending bit, set again, an overrun.
#[derive(Clone, Copy, Debug)]
pub struct SysTickTimer {
    reload: u32,
}

impl SysTickTimer {
    /// Largest period in clocks (a 24-bit reload).
    pub const MAX_COUNTS: u32 = 1 << 24;

    /// Starts the SysTick expiring every `counts` core clocks (2 to [`Self::MAX_COUNTS`], as
    /// [`period_counts`] gives), its interrupt enabled.
    pub fn start(syst: &mut SYST, counts: u32) -> Self {
        let reload = counts.clamp(2, Self::MAX_COUNTS) - 1;
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(reload);
        syst.clear_current();
        syst.enable_interrupt();
        syst.enable_counter();
        SysTickTimer { reload }
    }

    /// Clocks since the last expiry, and whether the timer has expired again since (an
    /// overrun, when called at the end of its handler).
    #[inline(always)]
    pub fn since_expiry(&self) -> (u32, bool) {
        compiler_fence(Ordering::SeqCst);
        let now = SYST::get_current();
        let overran = SCB::is_pendst_pending();
        (self.reload.wrapping_sub(now), overran)
    }
}

/// Why a control loop fails.
#[derive(Clone, Copy, Debug, PartialEq, defmt::Format)]
pub enum LoopError {
    /// The core refused the gait or a step.
    Core(Error),
    /// Ticks ran into the next period.
    Overruns(u32),
    /// The period is not 2 to [`SysTickTimer::MAX_COUNTS`] clocks.
    Period,
}

/// Starts a control loop on the SysTick clocked at `clock_hz`: reads the gait (`bytes`, as
/// `include_bytes!` embeds it), checks it replays in `S`, logs the header, and starts the
/// timer at the gait's rate `1/h` (or `rate_hz`); returns the pilot, the timer and its period
/// in clocks.
///
/// Errors: the core's for the gait, [`LoopError::Period`] for a period the SysTick cannot
/// count.
pub fn start<S: Stored, C: Counter>(
    board: &str,
    bytes: &'static [u8],
    syst: &mut SYST,
    clock_hz: u32,
    rate_hz: Option<u32>,
    cycles: u32,
) -> Result<(Pilot<'static, S>, SysTickTimer, u32), LoopError> {
    let gait = crate::load(bytes).map_err(LoopError::Core)?;
    let pilot = Pilot::new(gait).map_err(LoopError::Core)?;
    let h = rate_hz.map_or(gait.params().h, |hz| 1.0 / f64::from(hz.max(1)));
    let counts = period_counts(h, clock_hz, SysTickTimer::MAX_COUNTS).ok_or(LoopError::Period)?;
    log_header::<S, C>(board, &gait, counts, cycles);
    Ok((pilot, SysTickTimer::start(syst, counts), counts))
}

/// The idle loop: logs what `status` (a copy of the status the ticks share) reports
/// ([`report`]), sleeping between ticks, and calls `exit` with the run's status once the
/// flight is over.
pub fn idle<S: Stored, C: Counter>(
    counts: u32,
    mut status: impl FnMut() -> Status<S>,
    exit: fn(i32) -> !,
) -> ! {
    let mut logged = 0;
    loop {
        if let Some(code) = report::<S, C>(&status(), &mut logged, counts) {
            exit(code)
        }
        cortex_m::asm::wfi();
    }
}

/// Logs the loop's header line (`purcell-loop: …`, [`line::LOOP`]).
pub fn log_header<S: Stored, C: Counter>(board: &str, gait: &Gait<'_>, counts: u32, cycles: u32) {
    let p = gait.params();
    defmt::println!(
        "{=str}: board={=str} scalar={=str} steps={=u32} h={=f64} period={=u64} unit={=str} cycles={=u32} gait={=u32:#010x}",
        line::LOOP,
        board,
        crate::scalar_name::<S>(),
        p.steps,
        p.h,
        scaled::<C>(u64::from(counts)),
        unit::<C>(),
        cycles,
        gait.crc()
    );
}

/// `insn` or `cycles`: what `C` counts.
fn unit<C: Counter>() -> &'static str {
    if C::LINE == line::INSN {
        "insn"
    } else {
        "cycles"
    }
}

/// Called by the idle loop with a copy of the status: logs the cycle it has not logged yet
/// (`cycle: …`) and, once the flight is over, the ticks (`ticks: …`, against the period of
/// `counts` raw counts), the joints' last commands and the result; then returns the exit
/// status ([`finish`](crate::finish)): 0, or 1 for an error of the core or any overrun.
pub fn report<S: Stored, C: Counter>(
    status: &Status<S>,
    logged: &mut u32,
    counts: u32,
) -> Option<i32> {
    if let Some(c) = &status.last
        && c.cycle > *logged
    {
        let g = &c.pose;
        let bits = [g.x(), g.y(), g.cos(), g.sin()].map(S::to_bits);
        defmt::println!(
            "{=str}: n={=u32} digest={=u64:#018x} pose_bits={=u64:#x} {=u64:#x} {=u64:#x} {=u64:#x} x={=f64} y={=f64} theta={=f64}",
            line::CYCLE,
            c.cycle,
            c.digest.value(),
            bits[0],
            bits[1],
            bits[2],
            bits[3],
            g.x().to_f64(),
            g.y().to_f64(),
            g.theta().to_f64()
        );
        *logged = c.cycle;
    }
    let end = status.end?;
    let t = &status.ticks;
    let (mean, tenths) = scaled_mean::<C>(&t.ticks);
    let (max, period) = (
        scaled::<C>(u64::from(t.ticks.max)),
        scaled::<C>(u64::from(counts)),
    );
    defmt::println!(
        "{=str}: unit={=str} count={=u32} mean={=u64}.{=u64} max={=u64} period={=u64} margin={=i64} overruns={=u32}",
        line::TICKS,
        unit::<C>(),
        t.ticks.n,
        mean,
        tenths,
        max,
        period,
        period as i64 - max as i64,
        t.overruns
    );
    let j = &status.joints;
    defmt::println!(
        "{=str}: commands={=u32} rates={=f64} {=f64} angles={=f64} {=f64}",
        line::JOINTS,
        j.count,
        j.rates.x.to_f64(),
        j.rates.y.to_f64(),
        j.angles.x.to_f64(),
        j.angles.y.to_f64()
    );
    let overruns = match t.overruns {
        0 => Ok(()),
        n => Err(LoopError::Overruns(n)),
    };
    Some(crate::finish(end.map_err(LoopError::Core).and(overruns)))
}
