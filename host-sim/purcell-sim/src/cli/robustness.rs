//! `robustness`: a stored gait flown through a plant whose parameters differ from the model's,
//! open loop (the law's controls as they are) and closed loop (the core's tracking law with
//! LQR gains along the extremal); the terminal errors, costs and joint excursions of both
//! (docs/ROBUSTNESS.md).

use super::args::{Failure, GaitInput, PrintArgs, Progress, fail, output_failure, read_gait};
use super::replay::check_stored;
use crate::budget::Work;
use crate::costate_file::CostateFile;
use crate::replan::Replanner;
use crate::robustness::{CaseReport, FlightReport, percent};
use crate::{output, plots};
use clap::Args;
use purcell_core::Gait;
use purcell_core::tracking::RECORD_VALUES;
use purcell_solver::solver::Progress as _;
use purcell_solver::tracking::{
    Control, Design, Feedforward, Mismatch, Noise, Outcome, PlanError, Table, fly_gait,
    joint_bound, nominal, table_of,
};
use serde_json::json;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

/// `robustness` flags.
#[derive(Debug, Args)]
pub struct RobustnessArgs {
    /// The gait to fly.
    #[command(flatten)]
    pub input: GaitInput,
    /// Relative error of the plant's drag ratio r (0.1: 10 % larger than the model's).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub ratio_error: f64,
    /// Relative error of the plant's drag coefficient k (cancels from the kinematics).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub drag_error: f64,
    /// Relative error E of the plant's links: (L0(1+E), L1(1-E), L2(1+E)).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub length_error: f64,
    /// Standard deviation of the measured pose's noise, each of x, y (m) and theta (rad).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub pose_noise: f64,
    /// Standard deviation of the measured joint angles' noise (rad).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub shape_noise: f64,
    /// Seed of the noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Fly the standard set of cases instead (ratio error -20..20 %, links 5 %, drag, noise)
    /// and print them as a Markdown table.
    #[arg(long, conflicts_with_all = ["ratio_error", "drag_error", "length_error",
                                      "pose_noise", "shape_noise"])]
    pub table: bool,
    /// Terminal weight of the tracking gains on each pose error (per m^2, rad^2).
    #[arg(long, default_value_t = Design::default().terminal_pose, allow_hyphen_values = true)]
    pub terminal_pose: f64,
    /// Terminal weight of the tracking gains on each joint-angle error (per rad^2).
    #[arg(long, default_value_t = Design::default().terminal_alpha, allow_hyphen_values = true)]
    pub terminal_alpha: f64,
    /// Running weight of the tracking gains on each pose error, per second.
    #[arg(long, default_value_t = Design::default().running_pose, allow_hyphen_values = true)]
    pub running_pose: f64,
    /// Running weight of the tracking gains on each joint-angle error, per second.
    #[arg(long, default_value_t = Design::default().running_alpha, allow_hyphen_values = true)]
    pub running_alpha: f64,
    /// Steps per record of the tracking table (its gains are held over them).
    #[arg(long, default_value_t = Design::default().every,
          value_parser = clap::value_parser!(u32).range(1..))]
    pub every: u32,
    /// The first step at which the tracking law uses its estimate of the drag-ratio error.
    #[arg(long, default_value_t = Design::default().estimate_from)]
    pub estimate_from: u32,
    /// Steps at the end of the gait with a record of the tracking table each.
    #[arg(long, default_value_t = Design::default().tail)]
    pub tail: u32,
    /// Extra running weight on a joint's error where the nominal joint is within --band of
    /// the joints' bound, per rad^2 per second.
    #[arg(long, default_value_t = Design::default().bound_weight, allow_hyphen_values = true)]
    pub bound_weight: f64,
    /// See --bound-weight (rad).
    #[arg(long, default_value_t = Design::default().band, allow_hyphen_values = true)]
    pub band: f64,
    /// Take the tracking table's gain on the estimated drag-ratio error from the plant's
    /// neighbouring extremal (the gait continued to r(1 +- 0.02); gaits without a joint limit)
    /// instead of the LQR's own: the plant's cheapest gait to first order (docs/ROBUSTNESS.md).
    #[arg(long)]
    pub plan: bool,
    /// Re-plan the closed loop from the measured state with the estimated drag ratio instead
    /// of the tracking law (docs/ROBUSTNESS.md, "Re-planning"); each re-plan in the report.
    #[arg(long, conflicts_with_all = ["f32", "plan"])]
    pub replan: bool,
    /// Run the law and the tracking law in f32 (the table rounded), as the Cortex-M4F would;
    /// the plant stays f64.
    #[arg(long)]
    pub f32: bool,
    /// Fly the one case closed loop in f32 with the tracking table stored in --gait (export
    /// --tracking), as the M4F firmware does (firmware/mcu/examples/closed_loop.rs), and
    /// print its digest and terminal error.
    #[arg(long, requires = "gait", conflicts_with_all = ["table", "out", "json", "replan"])]
    pub digest: bool,
    /// Print the JSON report instead of the summary.
    #[command(flatten)]
    pub print: PrintArgs,
    /// Output directory: robustness.json and the figure of the pose error over time
    /// (robustness.svg, .png); created, or replaced if it is a previous result.
    #[arg(short, long)]
    pub out: Option<PathBuf>,
    /// Replace --out even if it holds files purcell-sim did not write.
    #[arg(long)]
    pub force: bool,
}

/// The standard cases of `--table`: `(ratio, length, drag, pose noise, shape noise)`.
pub const TABLE: [(f64, f64, f64, f64, f64); 14] = [
    (0.0, 0.0, 0.0, 0.0, 0.0),
    (-0.2, 0.0, 0.0, 0.0, 0.0),
    (-0.1, 0.0, 0.0, 0.0, 0.0),
    (-0.05, 0.0, 0.0, 0.0, 0.0),
    (0.05, 0.0, 0.0, 0.0, 0.0),
    (0.1, 0.0, 0.0, 0.0, 0.0),
    (0.2, 0.0, 0.0, 0.0, 0.0),
    (0.0, -0.05, 0.0, 0.0, 0.0),
    (0.0, 0.05, 0.0, 0.0, 0.0),
    (0.0, 0.0, 0.2, 0.0, 0.0),
    (0.0, 0.0, 0.0, 1e-4, 0.0),
    (0.0, 0.0, 0.0, 0.0, 1e-3),
    (0.1, 0.05, 0.0, 1e-4, 1e-3),
    (-0.1, -0.05, 0.0, 1e-4, 1e-3),
];

/// A flight's report from its outcome.
fn flight_report(gait: &Gait<'_>, r: Result<Outcome, impl ToString>) -> FlightReport {
    match r {
        Ok(o) => {
            let e = gait.params().terminal_error(&o.end);
            FlightReport {
                alpha_error: Some(e.alpha),
                g_error: Some(e.g),
                cost: Some(o.cost),
                max_abs_alpha: Some(o.max_abs_alpha),
                estimated_ratio_error: Some(o.estimate),
                failure: None,
                deviation: o.deviation,
                replans: Vec::new(),
                given_up: None,
            }
        }
        Err(e) => FlightReport::failed(e.to_string()),
    }
}

/// How the closed loop flies: the tracking law with its table (in `f32` if asked), or
/// re-planned.
enum Closed<'a> {
    Tracking(&'a Table, bool),
    Replan(&'a Replanner<'a>, &'a dyn purcell_solver::solver::Progress),
}

/// Flies one case open and closed loop.
fn fly_case(
    gait: &Gait<'_>,
    closed: &Closed<'_>,
    (mismatch, noise): (Mismatch, Noise),
) -> Result<CaseReport, Failure> {
    let p = gait.params();
    let model = p.kinematics::<f64>().map_err(|e| fail(2, e))?;
    let plant = mismatch
        .plant(&model)
        .map_err(|e| fail(2, format!("the plant: {e}")))?;
    let f32 = matches!(closed, Closed::Tracking(_, true));
    let run = |control: Control<'_>| {
        let flight = if f32 {
            fly_gait::<f32>(gait, &plant, control, &noise)
        } else {
            fly_gait::<f64>(gait, &plant, control, &noise)
        };
        Ok::<_, Failure>(flight_report(gait, flight.map_err(|e| fail(2, e))?))
    };
    let open = run(Control::Open)?;
    let closed = match closed {
        Closed::Tracking(table, _) => run(Control::Closed {
            table,
            limit: joint_bound(p.alpha_max),
        })?,
        Closed::Replan(replanner, progress) => {
            FlightReport::replanned(p, replanner.fly(&plant, &noise, *progress))
        }
    };
    Ok(CaseReport {
        ratio_error: mismatch.ratio,
        drag_error: mismatch.drag,
        length_error: mismatch.length,
        pose_noise: noise.pose,
        shape_noise: noise.shape,
        seed: noise.seed,
        open,
        closed,
    })
}

/// The cases of the flags: the one given, or [`TABLE`].
fn cases(a: &RobustnessArgs) -> Vec<(Mismatch, Noise)> {
    let case = |(ratio, length, drag, pose, shape): (f64, f64, f64, f64, f64)| {
        (
            Mismatch {
                ratio,
                drag,
                length,
            },
            Noise {
                pose,
                shape,
                seed: a.seed,
            },
        )
    };
    if a.table {
        TABLE.iter().copied().map(case).collect()
    } else {
        vec![case((
            a.ratio_error,
            a.length_error,
            a.drag_error,
            a.pose_noise,
            a.shape_noise,
        ))]
    }
}

/// `robustness`: reads the gait, computes its gains, flies the cases; the summary (or the
/// JSON report) as printed.
pub(super) fn run_robustness(a: RobustnessArgs, quiet: bool) -> Result<String, Failure> {
    check_flags(&a)?;
    let progress = Progress::new(Instant::now(), quiet);
    if a.digest {
        return stored_flight(&a, quiet);
    }
    let (path, file) = a.input.costate_file()?;
    let refused = |e: &dyn std::fmt::Display| fail(2, format!("{}: {e}", path.display()));
    let design = design_of(&a, file.alpha_max);
    let bytes = file.to_gait().map_err(|e| refused(&e))?;
    let gait = Gait::from_bytes(&bytes).map_err(|e| refused(&e))?;
    check_stored(path, &gait, a.f32, Work::Tracking, quiet)?;
    let out = match &a.out {
        Some(dir) => Some(
            output::OutputDir::prepare(output::Claim::new(dir, "robustness", a.force, &[path]))
                .map_err(output_failure(true))?,
        ),
        None => None,
    };
    progress.phase("gains", 1, "table");
    let nominal = nominal(&gait).map_err(|e| refused(&e))?;
    let (k, source) =
        table_of(&gait, &nominal, &design).map_err(|e| refused(&format!("tracking table: {e}")))?;
    let feedforward = feedforward_json(&source);
    progress.tick();
    let nominal_cost: f64 = nominal
        .controls
        .iter()
        .map(|u| 0.5 * file.h * u.norm_squared())
        .sum();
    let cases = cases(&a);
    progress.phase("flights", cases.len(), "cases");
    let replanner = Replanner::new(gait.params(), &nominal);
    let closed = if a.replan {
        Closed::Replan(&replanner, &progress)
    } else {
        Closed::Tracking(&k, a.f32)
    };
    let reports = cases
        .into_iter()
        .map(|c| {
            let report = fly_case(&gait, &closed, c);
            progress.tick();
            report
        })
        .collect::<Result<Vec<_>, _>>()?;
    let report = json!({
        "format": "purcell-robustness", "version": 1,
        "crc": format!("{:#010x}", gait.crc()), "target": file.target,
        "alpha_max": file.alpha_max, "nominal_cost": nominal_cost,
        "precision": if a.f32 { "f32" } else { "f64" },
        "design": { "terminal_pose": design.terminal_pose,
                    "terminal_alpha": design.terminal_alpha,
                    "running_pose": design.running_pose,
                    "running_alpha": design.running_alpha,
                    "every": design.every, "estimate_from": design.estimate_from,
                    "tail": design.tail, "band": design.band,
                    "bound_weight": design.bound_weight, "feedforward": feedforward },
        "table_bytes_f32": k.records.len() * RECORD_VALUES * 4,
        "cases": reports,
    });
    let json = serde_json::to_string_pretty(&report).map_err(|e| fail(1, e))? + "\n";
    if let Some(out) = out {
        progress.phase("output", 1, "directory");
        let figure = plots::robustness::figure(&reports, file.h)
            .map_err(|e| fail(1, format!("plotting: {e}")))?;
        let mut files = plots::render::render("robustness", &figure)
            .map_err(|e| fail(1, format!("plotting: {e}")))?
            .to_vec();
        files.push(("robustness.json".into(), json.clone().into_bytes()));
        out.commit(&files).map_err(output_failure(false))?;
    }
    progress.finish();
    Ok(if a.print.json {
        json
    } else {
        text(&file, nominal_cost, &source, &reports)
    })
}

/// Where the table's gain on `ε` comes from, as the report says it.
fn feedforward_json(source: &Feedforward) -> serde_json::Value {
    match source {
        Feedforward::Extremal => json!({ "from": "extremal" }),
        Feedforward::Lqr(PlanError::Off) => json!({ "from": "lqr" }),
        Feedforward::Lqr(why) => json!({ "from": "lqr", "no_plan": why.to_string() }),
    }
}

/// The tracking law's design from the flags, for a gait within `alpha_max`.
fn design_of(a: &RobustnessArgs, alpha_max: Option<f64>) -> Design {
    Design {
        terminal_pose: a.terminal_pose,
        terminal_alpha: a.terminal_alpha,
        running_pose: a.running_pose,
        running_alpha: a.running_alpha,
        every: a.every,
        estimate_from: a.estimate_from,
        tail: a.tail,
        bound: joint_bound(alpha_max),
        band: a.band,
        bound_weight: a.bound_weight,
        plan: a.plan,
    }
}

/// The flags' values every case takes: noise and weights finite and `>= 0` (exit 2, also
/// with `--digest`).
fn check_flags(a: &RobustnessArgs) -> Result<(), Failure> {
    for (name, v) in [
        ("pose-noise", a.pose_noise),
        ("shape-noise", a.shape_noise),
        ("terminal-pose", a.terminal_pose),
        ("terminal-alpha", a.terminal_alpha),
        ("running-pose", a.running_pose),
        ("running-alpha", a.running_alpha),
        ("bound-weight", a.bound_weight),
        ("band", a.band),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(fail(
                2,
                format!("--{name} must be finite and >= 0 (got {v})"),
            ));
        }
    }
    Ok(())
}

/// `--digest`: the closed-loop `f32` flight of `--gait` with its stored tracking table through
/// the plant of the flags; its digest ([`Outcome::digest`]) and terminal error.
fn stored_flight(a: &RobustnessArgs, quiet: bool) -> Result<String, Failure> {
    let path = a
        .input
        .gait
        .as_deref()
        .ok_or(fail(2, "--digest needs --gait"))?;
    let refused = |e: &dyn std::fmt::Display| fail(2, format!("{}: {e}", path.display()));
    let bytes = read_gait(path)?;
    let gait = Gait::from_bytes(&bytes).map_err(|e| refused(&e))?;
    check_stored(path, &gait, true, Work::Stored, quiet)?;
    let stored = gait.tracking().ok_or_else(|| {
        refused(&"no tracking table (write one with `purcell-sim export --gait FILE --tracking`)")
    })?;
    let table = Table::stored(&stored);
    let p = gait.params();
    let (mismatch, noise) = cases(a).into_iter().next().ok_or(fail(2, "no case"))?;
    let plant = p
        .kinematics()
        .and_then(|model| mismatch.plant(&model))
        .map_err(|e| fail(2, format!("the plant: {e}")))?;
    let closed = Control::Closed {
        table: &table,
        limit: joint_bound(p.alpha_max),
    };
    let o = fly_gait::<f32>(&gait, &plant, closed, &noise)
        .map_err(|e| refused(&e))?
        .map_err(|e| fail(1, e))?;
    let e = p.terminal_error(&o.end);
    Ok(format!(
        "closed_digest: {:#018x}\nclosed_error: alpha={:.3e} g={:.3e} estimate={:.6}\n",
        o.digest, e.alpha, e.g, o.estimate
    ))
}

/// A table cell: the value in `.1e`, or `failed`.
fn cell(v: Option<f64>) -> String {
    v.map_or("failed".into(), |v| format!("{v:.1e}"))
}

/// The summary: the gait, then a Markdown table of the cases.
fn text(
    file: &CostateFile,
    nominal_cost: f64,
    source: &Feedforward,
    reports: &[CaseReport],
) -> String {
    let feedforward = match source {
        Feedforward::Extremal => "the plant's neighbouring extremal (--plan)".to_string(),
        Feedforward::Lqr(PlanError::Off) => "the LQR's".to_string(),
        Feedforward::Lqr(why) => format!("the LQR's (no plan: {why})"),
    };
    let mut s = format!(
        "gait: steps={} target={:?} alpha_max={} nominal cost={nominal_cost:.6}\n\
         gain on the ratio error: {feedforward}\n\n",
        file.steps,
        file.target,
        file.alpha_max.map_or("none".into(), |a| a.to_string())
    );
    s += "| r | links | k | pose noise | shape noise | open: g err | open: alpha err \
          | closed: g err | closed: alpha err | open/closed (larger error) | closed cost / nominal \
          | closed max abs alpha |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for c in reports {
        let (o, k) = (&c.open, &c.closed);
        let larger = |f: &FlightReport| Some(f.g_error?.max(f.alpha_error?));
        let ratio = match (larger(o), larger(k)) {
            (Some(a), Some(b)) if b > 0.0 && a / b < 1e4 => format!("{:.0}x", a / b),
            // A landing to the solver's tolerance (`--replan`): the order of magnitude.
            (Some(a), Some(b)) if b > 0.0 => format!("{:.0e}x", a / b),
            _ => "-".into(),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {ratio} | {} | {} |",
            percent(c.ratio_error),
            percent(c.length_error),
            percent(c.drag_error),
            c.pose_noise,
            c.shape_noise,
            cell(o.g_error),
            cell(o.alpha_error),
            cell(k.g_error),
            cell(k.alpha_error),
            k.cost
                .map_or("-".into(), |v| format!("{:.4}", v / nominal_cost)),
            k.max_abs_alpha.map_or("-".into(), |v| format!("{v:.6}")),
        );
        for (which, f) in [("open", o), ("closed", k)] {
            if let Some(why) = &f.failure {
                let _ = writeln!(s, "\n{which} loop failed: {why}");
            }
        }
    }
    s
}
