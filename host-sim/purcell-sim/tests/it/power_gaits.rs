//! Issue 37: a power-optimal gait (MODEL.md §11) from `solve --cost power` to the core's law.
//! Its costate file and gait file carry the cost (version 5), and the core replays it through
//! the power's law to the target: `f64` within 1e-10, `f32` with its checkpoints within 1e-5,
//! free and on the arcs of a joint limit; its power cost, recomputed from the replay's controls
//! alone (each link's dissipation, `purcell_solver::testkit::dissipated`), is the report's.

use crate::common;

use common::*;
use purcell_core::cost::Power;
use purcell_core::{Cost, Gait, Replay, Swimmer};
use purcell_sim::costate_file::{CostateFile, VERSION_COST};
use purcell_solver::testkit::dissipated;
use std::path::Path;

/// Replays `file`'s gait through its gait file in `f64` and in `f32` (with its checkpoints):
/// the terminal errors (largest of shape and position) and the power of the `f64` replay's
/// controls, `Σ h/2·P(α_k, u_k)` with the replay's own shapes.
fn replay(file: &CostateFile) -> (f64, f64, f64) {
    let bytes = file.to_gait().unwrap();
    let gait = Gait::from_bytes(&bytes).unwrap();
    assert_eq!(gait.params().cost, Cost::Power);
    assert_eq!(bytes[8..10], purcell_core::gait::VERSION_COST.to_le_bytes());
    let p = gait.params();
    let sw = Swimmer::new(p.model.links, p.model.drag, p.model.ratio).unwrap();
    let r64 = gait.replay_for::<f64, Power>(true).unwrap();
    assert_eq!(r64.cost(), Cost::Power);
    let mut sum = 0.0;
    let mut r = r64;
    while let Some(s) = r.step().unwrap() {
        sum += dissipated(&sw, &s.state.alpha, &s.u);
    }
    let e64 = p.terminal_error(r.state());
    let end32 = gait.replay_for::<f32, Power>(true).unwrap();
    let end32 = end32.fly(Replay::step).unwrap().end;
    let e32 = p.terminal_error(&end32);
    (e64.alpha.max(e64.g), e32.alpha.max(e32.g), 0.5 * p.h * sum)
}

/// `solve --cost power` of the small problem (10 s in steps of 0.01 s to `(0.001, 0, 0)`) into
/// `out` with `flags`; its costate file and `report.json`. A checkpoint every 10 steps: its
/// `f32` replay is worse conditioned than the paper's (with one every 100 steps it ends 6e-5
/// away, the effort-optimal gait's 2e-5; with one every 10, 6e-8).
fn solve(out: &Path, flags: &[(&str, &str)]) -> (CostateFile, serde_json::Value) {
    let mut s = Solve::paper()
        .target("0.001,0,0")
        .horizon("10")
        .starts(64)
        .flag("cost", "power")
        .flag("checkpoint-every", "10")
        .no_plots()
        .out(out);
    for (name, value) in flags {
        s = s.flag(name, value);
    }
    let o = s.run();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let file = CostateFile::read(&out.join("costate.json")).unwrap();
    assert_eq!((file.version, file.cost), (VERSION_COST, Cost::Power));
    (file, report(out))
}

#[test]
fn a_power_gait_replays_through_the_power_law_free_and_on_arcs() {
    let tmp = tempfile::tempdir().unwrap();
    let (file, r) = solve(&tmp.path().join("free"), &[]);
    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    assert_eq!(r["costs"]["power"], r["cost"]);
    let (e64, e32, power) = replay(&file);
    assert!(e64 <= 1e-10 && e32 <= 1e-5, "f64 {e64:.1e}, f32 {e32:.1e}");
    let reported = f(&r["cost"]);
    assert!(
        (power - reported).abs() <= 1e-10 * reported,
        "report {reported}, the replay's controls dissipate {power}"
    );
    // No dearer in power than the effort-optimal gait.
    assert!(reported <= f(&r["costs"]["power"]));
    // Within a limit that binds: the replay runs the power's law on the arcs.
    let widest = r["extremals"][0]["max_abs_alpha"].as_f64().unwrap();
    let limit = format!("{}", 0.8 * widest);
    let (file, r) = solve(&tmp.path().join("limited"), &[("alpha-max", &limit)]);
    assert!(!file.arcs.is_empty(), "the limit binds");
    let (e64, e32, power) = replay(&file);
    assert!(
        e64 <= 1e-10 && e32 <= 1e-5,
        "on arcs: f64 {e64:.1e}, f32 {e32:.1e}"
    );
    assert!((power - f(&r["cost"])).abs() <= 1e-10 * f(&r["cost"]));
}

#[test]
fn an_unknown_cost_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let o = Solve::quick()
        .flag("cost", "speed")
        .out(&tmp.path().join("out"))
        .run();
    assert_exit(&o, 2, "unknown cost \"speed\" (one of effort, power)");
}

#[test]
fn a_costate_file_names_a_cost_only_in_version_5() {
    let tmp = tempfile::tempdir().unwrap();
    let (file, _) = solve(&tmp.path().join("out"), &[("horizon", "2")]);
    let json = file.to_json();
    assert_eq!(CostateFile::parse(&json).unwrap(), file);
    let refused = |from: &str, to: &str| {
        let text = json.replacen(from, to, 1);
        assert_ne!(text, json);
        CostateFile::parse(&text).unwrap_err().to_string()
    };
    let effort = refused("\"cost\": \"power\"", "\"cost\": \"effort\"");
    assert!(
        effort.contains("version 5 is a gait of a cost other than the effort"),
        "{effort}"
    );
    let unknown = refused("\"cost\": \"power\"", "\"cost\": \"speed\"");
    assert!(unknown.contains("malformed"), "{unknown}");
    let v3 = refused("\"version\": 5", "\"version\": 3");
    assert!(
        v3.contains("version 3 does not have the field \"cost\""),
        "{v3}"
    );
}
