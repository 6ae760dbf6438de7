//! The short summaries `solve` and `sweep` print on stdout, read from the report they wrote
//! (so the two never disagree); `--json` prints the report instead.

use crate::report::{SolveReport, SweepReport};
use std::fmt::Write as _;
use std::path::Path;

/// A number of the report in `{:.1e}`, `–` where it is `null`.
fn sci(v: Option<f64>) -> String {
    v.map_or("–".into(), |x| format!("{x:.1e}"))
}

/// `said` if the flag `v` of the report is true, else `not said`.
fn flag(v: bool, said: &str) -> String {
    if v {
        said.into()
    } else {
        format!("not {said}")
    }
}

/// The last line: where the files went (figures counted, not listed).
fn wrote(out: &Path, files: &[(String, Vec<u8>)]) -> String {
    let figures = files.iter().filter(|f| f.0.ends_with(".svg")).count();
    let mut names: Vec<&str> = files
        .iter()
        .map(|f| f.0.as_str())
        .filter(|n| !n.ends_with(".svg") && !n.ends_with(".png"))
        .collect();
    let plural = if figures == 1 { "" } else { "s" };
    let counted = format!("{figures} figure{plural} .svg/.png");
    if figures > 0 {
        names.push(&counted);
    }
    format!("wrote      {}/ ({})\n", out.display(), names.join(", "))
}

/// `solve`'s summary of `report` (`report.json`), its files written to `out`, the command
/// having taken `seconds`.
pub(super) fn solve(
    report: &SolveReport,
    out: &Path,
    files: &[(String, Vec<u8>)],
    seconds: f64,
) -> String {
    let r = report;
    let b = &report.best;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "cost       J = {:.7}, extremal {} of {} ({}, {}, max |alpha_i| {:.4} rad)",
        b.cost,
        r.returned + 1,
        r.extremals.len(),
        flag(b.admissible, "admissible"),
        flag(b.local_min, "a local minimum"),
        b.max_abs_alpha,
    );
    let _ = writeln!(s, "arcs       {}", arcs(r));
    let f32_replay = r
        .replays
        .iter()
        .find(|x| x.precision == "f32" && x.checkpoints);
    let _ = writeln!(
        s,
        "residuals  terminal {} (core {}), KKT {}, law {}; f32 replay {}",
        sci(Some(b.residual)),
        sci(b.terminal_residual),
        sci(b.kkt_residual),
        sci(b.law_residual),
        f32_replay.map_or("–".into(), |x| format!(
            "{} rad, {} in g",
            sci(x.alpha_error),
            sci(x.g_error)
        )),
    );
    let _ = writeln!(
        s,
        "search     {}",
        match (&r.search, r.flown) {
            (None, Some(m)) => format!(
                "refined from a gait to the target's order-{m} root in 1/{m} of the steps, flown {m} times (the search's start loops reached no gait within the limit)"
            ),
            (None, None) => "none (from --from's extremal)".to_string(),
            (Some(e), _) => format!(
                "{} of {} starts, {} distinct minima, stopping rule {} (unseen {:.3}); {}",
                e.starts,
                e.budget,
                e.distinct_minima,
                if e.rule_met { "met" } else { "not met" },
                e.unseen_estimate,
                if r.recentred {
                    "the gait reached from one of their gaits walked back up the central \
                     path and down"
                        .to_string()
                } else {
                    let hits = r.extremals.get(r.returned).map_or(0, |x| x.hits);
                    format!("the gait reached from {hits} of them")
                },
            ),
        }
    );
    let solving = r.solve_seconds;
    let _ = writeln!(s, "time       {seconds:.2} s ({solving:.2} s solving)");
    s + &wrote(out, files)
}

/// The joint-limit arcs of `report`, the first two in full.
fn arcs(report: &SolveReport) -> String {
    let all = &report.best.arcs;
    if all.is_empty() {
        return "none on the joint limit".into();
    }
    let limit = report.problem.common.alpha_max.unwrap_or(f64::NAN);
    let mut shown: Vec<String> = all
        .iter()
        .take(2)
        .map(|a| {
            let at = limit * f64::from(a.sign);
            format!(
                "alpha{} = {at} rad, steps {}..={}",
                a.joint, a.first, a.last
            )
        })
        .collect();
    if all.len() > 2 {
        shown.push("…".into());
    }
    format!("{} on the joint limit ({})", all.len(), shown.join(", "))
}

/// `sweep`'s summary of `report` (its `report.json`), its files written to `out`, the command
/// having taken `seconds`.
pub(super) fn sweep(
    report: &SweepReport,
    out: &Path,
    files: &[(String, Vec<u8>)],
    seconds: f64,
) -> String {
    let axes = &report.axes;
    format!(
        "targets    {} ({} x, {} y, {} theta), {} solved (sweep.csv's status says how each \
         went)\ntime       {seconds:.2} s ({:.2} s solving)\n{}",
        report.targets,
        axes.x.len(),
        axes.y.len(),
        axes.theta.len(),
        report.solved,
        report.sweep_seconds,
        wrote(out, files)
    )
}
