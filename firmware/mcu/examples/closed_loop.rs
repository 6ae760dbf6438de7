//! The closed loop on QEMU's Cortex-M4F (`mps2-an386`): the gait's law and its tracking law
//! ([`purcell_core::tracking`], with the tracking table stored in the gait file, `export
//! --tracking`) fly in `f32` against a plant whose drag ratio is off by `PURCELL_RATIO_ERROR`
//! (at build time; default `0.1`, 10 % larger), stepped here in `f64` (in software: it stands
//! for the swimmer, it is not the controller). The sensor reads the plant's state rounded to
//! `f32`, without noise.
//!
//! Per step `k`: the law's step ([`Replay::step`], the open loop), then the tracking part
//! (`purcell_mcu_track`: the record of step `k`, the error, the estimate at a record's first
//! step, the corrected and clamped control), each timed with the SysTick in instructions
//! (`-icount`, as `src/firmware.rs`); then the plant steps. It prints (defmt):
//!
//! ```text
//! purcell-closed: board=mps2-an386 steps=<N> records=<R> gain_bytes=<B> ratio_error=<ε> gait=<crc32>
//! law_insn: mean=<M.m> max=<X>            the open-loop step
//! track_insn: mean=<M.m> max=<X>          the extra of the closed-loop step
//! closed_digest: 0x<16 hex digits>        u_k and the plant's state per step, its final state
//! closed_error: alpha=<rad> g=<m|rad>
//! result: ok
//! ```
//!
//! The digest is `purcell-sim robustness --gait FILE --ratio-error ε --digest`'s (the host's
//! `f32` closed loop through the same plant), which `firmware/check.sh` compares.
//!
//! Run: `PURCELL_GAIT=gait-with-tracking.gait cargo run -p purcell-mcu --example closed_loop
//! --target thumbv7em-none-eabihf --release`.

#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_os = "none")]
mod flight {
    use cortex_m_rt::entry;
    use defmt_semihosting as _;
    use purcell_core::gait::{TRACKING_RECORD_LEN, TrackingCursor};
    use purcell_core::nalgebra::Vector2;
    use purcell_core::tracking::{Mismatch, Tracker, joint_bound, rounded, tracking_error};
    use purcell_core::{Error, Replay, Sample, State, TrajectoryDigest};
    use purcell_fly::{Counter, Stats, scaled, scaled_mean};
    use purcell_mcu::Systick;

    /// The gait flown: `$PURCELL_GAIT` (with a tracking table), see `build.rs`.
    static GAIT: &[u8] = include_bytes!(env!("PURCELL_GAIT_FILE"));

    /// Why the flight fails (exit status 1).
    #[derive(Clone, Copy, Debug, defmt::Format)]
    enum Failure {
        /// The core refused the gait, the plant or a step.
        Core(Error),
        /// The gait file has no tracking table (`export --tracking`).
        NoTrackingTable,
        /// `PURCELL_RATIO_ERROR` is not a number.
        RatioError,
        /// The core peripherals were already taken.
        Peripherals,
    }

    impl From<Error> for Failure {
        fn from(e: Error) -> Self {
            Failure::Core(e)
        }
    }

    /// The open-loop step: the law's.
    #[inline(never)]
    #[unsafe(no_mangle)]
    fn purcell_mcu_law<'r>(
        replay: &'r mut Replay<'_, f32>,
    ) -> Result<Option<&'r Sample<f32>>, Error> {
        replay.step()
    }

    /// What the tracking law needs besides a step's sample and measurement.
    struct Loop<'a> {
        tracker: Tracker<f32>,
        cursor: TrackingCursor<'a>,
        /// The joints' bound and `h`.
        limit: f32,
        h: f32,
    }

    /// The tracking part of a closed-loop step: the instructions it adds to the open loop,
    /// and the function `purcell-mcu-check disasm --root purcell_mcu_track` checks for
    /// soft-float helpers.
    #[inline(never)]
    #[unsafe(no_mangle)]
    fn purcell_mcu_track(
        l: &mut Loop<'_>,
        sample: &Sample<f32>,
        measured: &State<f32>,
    ) -> Result<Vector2<f32>, Error> {
        let (record, first) = l.cursor.at(sample.k);
        let e = tracking_error(&sample.state, measured);
        if first {
            l.tracker.update(record, &e);
        }
        l.tracker
            .control(record, &sample.u, &e, &measured.alpha, Some(l.limit), l.h)
    }

    /// Raw SysTick counts of `f`, net of `base`.
    #[inline(always)]
    fn timed<R>(base: u32, f: impl FnOnce() -> R) -> (u32, R) {
        let t0 = Systick::now();
        let r = f();
        let t1 = Systick::now();
        (Systick::elapsed(t0, t1).saturating_sub(base), r)
    }

    fn run() -> Result<(), Failure> {
        let mut cp = cortex_m::Peripherals::take().ok_or(Failure::Peripherals)?;
        purcell_mcu::start_systick(&mut cp.SYST);
        let base = purcell_fly::overhead::<Systick>();
        let ratio = option_env!("PURCELL_RATIO_ERROR")
            .unwrap_or("0.1")
            .parse::<f64>()
            .map_err(|_| Failure::RatioError)?;
        let gait = purcell_fly::load(GAIT)?;
        let table = gait.tracking().ok_or(Failure::NoTrackingTable)?;
        let p = gait.params();
        let mismatch = Mismatch {
            ratio,
            ..Mismatch::default()
        };
        let plant = mismatch.plant(&p.kinematics()?)?;
        defmt::println!(
            "purcell-closed: board=mps2-an386 steps={=u32} records={=usize} gain_bytes={=usize} ratio_error={=f64} gait={=u32:#010x}",
            p.steps,
            table.len(),
            table.len() * TRACKING_RECORD_LEN,
            ratio,
            gait.crc()
        );
        let mut l = Loop {
            tracker: Tracker::new(),
            cursor: table.cursor(),
            limit: joint_bound(p.alpha_max) as f32,
            h: p.h as f32,
        };
        let mut replay = gait.replay::<f32>()?;
        let mut state = p.start::<f64>();
        let (mut digest, mut law, mut track) =
            (TrajectoryDigest::new(), Stats::default(), Stats::default());
        loop {
            let (n, sample) = timed(base, || purcell_mcu_law(&mut replay));
            let Some(sample) = sample?.copied() else {
                break;
            };
            law.add(n);
            let measured = rounded::<f32>(&state);
            let (n, u) = timed(base, || purcell_mcu_track(&mut l, &sample, &measured));
            track.add(n);
            let u = u?.map(f64::from);
            digest.push(u.x);
            digest.push(u.y);
            digest.push_state(&state);
            state = plant.step(&state, &u)?;
        }
        digest.push_state(&state);
        for (name, stats) in [("law_insn", &law), ("track_insn", &track)] {
            let (mean, tenths) = scaled_mean::<Systick>(stats);
            let max = scaled::<Systick>(u64::from(stats.max));
            defmt::println!(
                "{=str}: mean={=u64}.{=u64} max={=u64}",
                name,
                mean,
                tenths,
                max
            );
        }
        let e = p.terminal_error(&state);
        defmt::println!("closed_digest: {=u64:#018x}", digest.value());
        defmt::println!("closed_error: alpha={=f64} g={=f64}", e.alpha, e.g);
        Ok(())
    }

    #[entry]
    fn main() -> ! {
        semihosting::process::exit(purcell_fly::finish(run()))
    }
}

/// The host build: how to run the example; exits with 1.
#[cfg(not(target_os = "none"))]
fn main() -> std::process::ExitCode {
    eprintln!(
        "closed_loop is firmware for QEMU's Cortex-M4F board: run it with
`PURCELL_GAIT=FILE cargo run -p purcell-mcu --example closed_loop --target thumbv7em-none-eabihf --release`
(see firmware/README.md)."
    );
    std::process::ExitCode::FAILURE
}
