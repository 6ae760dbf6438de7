//! Replaying a gait through the core exactly as a firmware does (`purcell_core::Gait`, its
//! stored checkpoint table, `Replay::fly`), in `f64` and `f32`: the trajectory digest, the
//! final state's bits and the terminal error (`purcell_core::TerminalError`); and the
//! per-step path of a replay (`replay --trace`).

use crate::costate_file::CostateFile;
use crate::output::path::{PathCsv, Row};
use nalgebra::Vector2;
use purcell_core::cost::RunningCost;
use purcell_core::gait::Stored;
use purcell_core::{Flight, Gait, State};
use purcell_solver::problem::{InputError, Problem, check_gait_precision};
use purcell_solver::solver::Trajectory;
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt::{Display, Write as _};

/// One replay of a gait (fields in alphabetical order, the order of the reports that hold it).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReplayReport {
    /// `max |α_N − ᾱ|`, radians (see `purcell_core::TerminalError`).
    pub alpha_error: Option<f64>,
    /// Whether the gait's checkpoints were applied (without: only those at the joint-limit
    /// arcs' exits, which the law needs; see `purcell_core::Gait::replay_without_checkpoints`).
    pub checkpoints: bool,
    /// `purcell_core::TrajectoryDigest` as `0x` and 16 hex digits (`null` if the replay failed).
    pub digest: Option<String>,
    /// The step `k` it failed at (`null` if it did not start, or did not fail).
    pub failed_at_step: Option<u32>,
    /// Why the replay stopped early, if it did.
    pub failure: Option<String>,
    /// Bits of `(α1, α2, x, y, cos θ, sin θ)` at the end, as `0x…` (widened for `f32`).
    pub final_state_bits: Option<Vec<String>>,
    /// `max |log(ḡ⁻¹ g_N)|` over its components (metres / radians).
    pub g_error: Option<f64>,
    /// `"f64"` or `"f32"`.
    pub precision: &'static str,
}

impl ReplayReport {
    /// Why the replay of `gait` stopped early, with the step and time it stopped at (`None`
    /// if it did not): every front end's message.
    pub fn failure_message(&self, gait: &Gait<'_>) -> Option<String> {
        let why = self.failure.as_ref()?;
        let with = if self.checkpoints { "with" } else { "without" };
        let which = format!("{} replay {with} checkpoints", self.precision);
        let p = gait.params();
        Some(match self.failed_at_step {
            Some(k) => format!(
                "{which} failed at step {k} of {} (t = {} s): {why}",
                p.steps,
                (f64::from(k) * p.h * 1e9).round() / 1e9
            ),
            None => format!("{which} failed before its first step: {why}"),
        })
    }
}

/// What every route to a replay checks in a stored `gait`, besides the core's own
/// validation and the step budget, before any work: its problem as input
/// ([`Problem::of_gait`]) and, where it is replayed in `f32`, every number there
/// ([`check_gait_precision`]).
pub fn check_stored(gait: &Gait<'_>, f32: bool) -> Result<(), InputError> {
    Problem::of_gait(gait.params())?;
    if f32 {
        check_gait_precision::<f32>(gait.params(), gait.checkpoints(), "f32")?;
    }
    Ok(())
}

/// Replays `gait` in `T` (`precision` names it) with the law of its cost, with or without its
/// checkpoints.
pub fn replay_gait<T: Stored>(
    gait: &Gait<'_>,
    precision: &'static str,
    checkpoints: bool,
) -> ReplayReport {
    purcell_core::with_cost!(gait.params().cost, C => {
        replay_gait_for::<T, C>(gait, precision, checkpoints)
    })
}

/// [`replay_gait`] with the law of `C`, the gait's cost.
fn replay_gait_for<T: Stored, C: RunningCost>(
    gait: &Gait<'_>,
    precision: &'static str,
    checkpoints: bool,
) -> ReplayReport {
    let replay = gait.replay_for::<T, C>(checkpoints);
    // The step that was running when a step failed.
    let mut at = 0;
    let flight = replay.and_then(|r| {
        r.fly(|r| {
            at = r.steps_done();
            r.step()
        })
    });
    match flight {
        Ok(f) => {
            let error = gait.params().terminal_error(&f.end);
            ReplayReport {
                digest: Some(digest_hex(&f)),
                final_state_bits: Some(f.final_bits().iter().map(|b| format!("{b:#x}")).collect()),
                alpha_error: Some(error.alpha),
                g_error: Some(error.g),
                ..failed(precision, checkpoints, None)
            }
        }
        Err(e) => ReplayReport {
            failed_at_step: Some(at),
            ..failed(precision, checkpoints, Some(e))
        },
    }
}

/// The path of a replay of `gait` in `T`, with or without its checkpoints, as CSV
/// ([`crate::output::path`]: `trajectory.csv`'s columns, numbers in `T`); up to the
/// failing step if the replay fails.
pub fn trace<T: Stored + Display + Default>(gait: &Gait<'_>, checkpoints: bool) -> String {
    purcell_core::with_cost!(gait.params().cost, C => trace_for::<T, C>(gait, checkpoints))
}

/// [`trace`] with the law of `C`, the gait's cost.
fn trace_for<T: Stored + Display + Default, C: RunningCost>(
    gait: &Gait<'_>,
    checkpoints: bool,
) -> String {
    let p = gait.params();
    let mut csv = PathCsv::new(p.h, p.steps, gait.arcs());
    let replay = gait.replay_for::<T, C>(checkpoints);
    let Ok(mut replay) = replay else {
        return csv.finish();
    };
    // The steps where the replay restores a checkpoint's `(α_k, g_k, ξ̃^{k−1})`: each one
    // with its checkpoints, the arcs' exits without.
    let restores: BTreeMap<u32, [f64; 2]> = gait
        .checkpoints()
        .filter(|c| checkpoints || gait.arcs().any(|a| a.last == c.k))
        .map(|c| (c.k, c.xi))
        .collect();
    let row = |s: &State<T>, u: Option<[T; 2]>, xi: &Vector2<T>| {
        let g = s.g.to_xytheta();
        Row {
            alpha: [s.alpha.x, s.alpha.y],
            u,
            g: [g.x, g.y, g.z],
            xi: [xi.x, xi.y],
        }
    };
    // `ξ^{k−1}`, the law's input at step `k`.
    let mut xi = *replay.xi();
    loop {
        if let Some(c) = restores.get(&replay.steps_done()) {
            xi = Vector2::new(T::from_f64(c[0]), T::from_f64(c[1]));
        }
        match replay.step() {
            Ok(Some(sample)) => {
                csv.push(&row(&sample.state, Some([sample.u.x, sample.u.y]), &xi));
                xi = sample.xi;
            }
            Ok(None) => {
                csv.push(&row(replay.state(), None, &xi));
                return csv.finish();
            }
            Err(_) => return csv.finish(),
        }
    }
}

/// The whole trajectory of an `f64` replay of `file` with its checkpoints: states, controls
/// and the costates `ξ^{k−1}` (`k = 0..=N`), e.g. to start the solver from a stored extremal.
pub fn trajectory(file: &CostateFile) -> Result<Trajectory, purcell_core::Error> {
    let bytes = file.to_gait()?;
    purcell_solver::tracking::nominal(&Gait::from_bytes(&bytes)?)
}

/// The states `(α_k, g_k)` of the `f64` replay of `file` (with its checkpoints) at every
/// `stride`-th step, `stride` chosen for about `points` of them, always with `k = 0` and
/// `k = N`; and `stride`.
pub fn gait_states(
    file: &CostateFile,
    points: usize,
) -> Result<(Vec<purcell_core::State<f64>>, usize), purcell_core::Error> {
    let t = trajectory(file)?;
    let stride = (file.steps as usize / points.max(1)).max(1);
    let last = t.states.len() - 1;
    let states = t
        .states
        .iter()
        .enumerate()
        .filter(|(k, _)| k % stride == 0 || *k == last)
        .map(|(_, s)| *s)
        .collect();
    Ok((states, stride))
}

/// `0x` and the 16 hex digits of a flight's digest.
pub fn digest_hex<T>(flight: &Flight<T>) -> String {
    format!("{:#018x}", flight.digest.value())
}

/// Replays a costate file as its binary gait (what `export` writes and firmware flies).
pub fn replay<T: Stored>(
    file: &CostateFile,
    precision: &'static str,
    checkpoints: bool,
) -> ReplayReport {
    match file.to_gait() {
        Ok(bytes) => match Gait::from_bytes(&bytes) {
            Ok(gait) => replay_gait::<T>(&gait, precision, checkpoints),
            Err(e) => failed(precision, checkpoints, Some(e)),
        },
        Err(e) => failed(precision, checkpoints, Some(e)),
    }
}

/// A report with no results, and the error that stopped the replay if there is one.
fn failed(
    precision: &'static str,
    checkpoints: bool,
    e: Option<purcell_core::Error>,
) -> ReplayReport {
    ReplayReport {
        precision,
        checkpoints,
        digest: None,
        final_state_bits: None,
        alpha_error: None,
        g_error: None,
        failure: e.map(|e| e.to_string()),
        failed_at_step: None,
    }
}

/// The four replays the `replay` command reports: f64 and f32, each with and without
/// checkpoints.
pub fn standard_replays(gait: &Gait<'_>) -> Vec<ReplayReport> {
    vec![
        replay_gait::<f64>(gait, "f64", true),
        replay_gait::<f64>(gait, "f64", false),
        replay_gait::<f32>(gait, "f32", true),
        replay_gait::<f32>(gait, "f32", false),
    ]
}

/// The `replay` command's text: a line on the gait, then per replay its `digest: 0x…` and
/// `final_state_bits:` lines (as the firmware prints them) and its terminal error.
pub fn text(gait: &Gait<'_>, reports: &[ReplayReport]) -> String {
    let p = gait.params();
    let mut s = format!(
        "gait: crc={:#010x} steps={} h={} checkpoints={} arcs={} alpha_max={} alpha0={:?}{} target={:?}\n",
        gait.crc(),
        p.steps,
        p.h,
        gait.checkpoint_count(),
        gait.arc_count(),
        p.alpha_max.map_or("none".into(), |a| a.to_string()),
        p.alpha0,
        // A transition's end shape (a loop ends where it starts).
        p.alpha_end
            .map_or(String::new(), |b| format!(" alpha_end={b:?}")),
        p.target
    );
    for r in reports {
        let with = if r.checkpoints { "with" } else { "without" };
        let _ = writeln!(s, "replay: {} {with} checkpoints", r.precision);
        if let (Some(d), Some(bits), Some(a), Some(g)) =
            (&r.digest, &r.final_state_bits, r.alpha_error, r.g_error)
        {
            let _ = writeln!(s, "digest: {d}");
            let _ = writeln!(s, "final_state_bits: {}", bits.join(" "));
            let _ = writeln!(s, "terminal_error: alpha={a:.2e} g={g:.2e}");
        }
        if let Some(f) = &r.failure {
            match r.failed_at_step {
                Some(k) => writeln!(s, "failed at step {k}: {f}"),
                None => writeln!(s, "failed: {f}"),
            }
            .ok();
        }
    }
    s
}
