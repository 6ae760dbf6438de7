//! `purcell-sim solve`, `solve --from` and `sweep` end to end: exit codes, outputs, and no
//! input that makes the search run without end.

use crate::common;

use common::{Solve, arg, sim_in};
use std::time::Duration;

const MINUTE: Duration = Duration::from_secs(60);

#[test]
fn the_zero_target_returns_cost_zero() {
    let dir = tempfile::tempdir().unwrap();
    let zero = Solve::paper().target("0,0,0").no_plots();
    let (r, _) = zero.out(&dir.path().join("stay")).solved(MINUTE);
    assert_eq!(r["cost"].as_f64(), Some(0.0));
    assert_eq!(r["local_min"].as_bool(), Some(true));
}

/// Inputs that made the former start generator loop for ever (no random start fitted inside
/// 90 % of the limit): now they end, the bent start with a solution, the tight limit with
/// exit 3 (no loop within 0.2 rad reaches the paper's target).
#[test]
fn starts_near_the_limit_do_not_hang() {
    let dir = tempfile::tempdir().unwrap();
    for (i, (extra, code)) in [
        (&["--alpha0", "3,0", "--seed", "1"][..], 0),
        (&["--alpha-max", "0.2", "--starts", "9"][..], 3),
    ]
    .iter()
    .enumerate()
    {
        let out = dir.path().join(format!("o{i}"));
        let o = Solve::paper()
            .no_plots()
            .out(&out)
            .with(extra)
            .run_within(2 * MINUTE);
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(*code), "{extra:?}: {e}");
        if *code == 3 {
            assert!(e.contains("no start reached the target"), "{extra:?}: {e}");
            assert!(!out.exists(), "{extra:?}");
        }
    }
}

/// A stored extremal continued to a nearby target, start shape and horizon: the result is
/// an extremal of the new problem (residual, KKT, local minimum) and costs what a full solve
/// of it costs when it is the same branch.
/// A joint limit at or past the overlap, not finite, or that the start shape already
/// violates: exit 2 at once, nothing written. One so tight that no loop reaches the target:
/// exit 3 quickly, with the best residual.
#[test]
fn bad_or_hopeless_joint_limits_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    for (extra, code, says) in [
        (
            &["--alpha-max", "3.2"][..],
            2,
            "alpha-max must be in ]0, pi[",
        ),
        (
            &["--alpha-max", "3.141592653589793"][..],
            2,
            "the links overlap at pi",
        ),
        (
            &["--alpha-max", "nan"][..],
            2,
            "alpha-max must be a finite number",
        ),
        (
            &["--alpha-max", "-1"][..],
            2,
            "alpha-max must be in ]0, pi[",
        ),
        (
            &["--alpha-max", "0.3", "--alpha0", "0.3,0"][..],
            2,
            "must be below alpha-max",
        ),
        (&["--alpha-max", "0.05"][..], 3, "best residual"),
    ] {
        let o = Solve::paper()
            .no_plots()
            .out(&out)
            .with(extra)
            .run_within(MINUTE);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(code), "{extra:?}: {stderr}");
        assert!(stderr.contains(says), "{extra:?}: {stderr}");
        assert!(!out.exists(), "{extra:?}");
    }
}

/// `--alpha-max`: the gait stays within the limit, touching it on arcs that the report lists
/// with their multipliers' smallest value; `--from` that gait reaches a nearby target under
/// the same limit, again on arcs of it.
#[test]
fn a_joint_limit_gives_a_gait_within_it_with_its_arcs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("limited");
    let (r, _) = Solve::paper()
        .alpha_max("1.5")
        .no_plots()
        .out(&out)
        .solved(2 * MINUTE);
    assert!(r["max_abs_alpha"].as_f64().unwrap() <= 1.5 * (1.0 + 1e-13));
    assert_eq!(r["problem"]["alpha_max"].as_f64(), Some(1.5));
    let arcs = r["arcs"].as_array().unwrap();
    assert!(!arcs.is_empty());
    for a in arcs {
        let (first, last) = (a["first"].as_u64().unwrap(), a["last"].as_u64().unwrap());
        assert!(1 <= first && first <= last && last < 10_000, "{a}");
        assert!([1, 2].contains(&a["joint"].as_u64().unwrap()), "{a}");
        assert_eq!(a["sign"].as_f64().unwrap().abs(), 1.0, "{a}");
    }
    assert!(r["min_eta"].as_f64().unwrap() >= 0.0);
    assert!(r["kkt_residual"].as_f64().unwrap() <= 1e-8);
    assert_eq!(r["local_min"].as_bool(), Some(true));
    let (r, _) = Solve::paper()
        .from(&out.join("costate.json"))
        .target("0.1,0.12,0.05")
        .alpha_max("1.5")
        .no_plots()
        .out(&dir.path().join("near"))
        .solved(MINUTE);
    assert!(r["max_abs_alpha"].as_f64().unwrap() <= 1.5 * (1.0 + 1e-13));
    assert!(!r["arcs"].as_array().unwrap().is_empty());
    assert!(r["min_eta"].as_f64().unwrap() >= 0.0);
    assert!(r["residual"].as_f64().unwrap() <= 1e-10);
    assert!(r["kkt_residual"].as_f64().unwrap() <= 1e-8);
}

#[test]
fn solve_from_a_stored_extremal_reaches_a_nearby_problem() {
    let dir = tempfile::tempdir().unwrap();
    let first = dir.path().join("first");
    Solve::paper()
        .target("0.1,0,0")
        .no_plots()
        .out(&first)
        .solved(MINUTE);
    let costate = first.join("costate.json");
    let (r, _) = Solve::paper()
        .from(&costate)
        .target("0.13,0.02,0.1")
        .alpha0("0.1,-0.1")
        .horizon("80")
        .no_plots()
        .out(&dir.path().join("near"))
        .solved(MINUTE);
    assert!(r["residual"].as_f64().unwrap() <= 1e-10);
    assert!(r["kkt_residual"].as_f64().unwrap() <= 1e-8);
    assert_eq!(r["problem"]["target"][0].as_f64(), Some(0.13));
    assert_eq!(r["problem"]["steps"].as_u64(), Some(8000));
    // Reached by continuation, not by the fall-back search.
    assert!(r["search"].is_null(), "{}", r["search"]);
    // Another swimmer: the same gait continued to a drag ratio 10 % larger, by Newton.
    let (r, _) = Solve::paper()
        .from(&costate)
        .target("0.1,0,0")
        .flag("ratio", "2.2")
        .no_plots()
        .out(&dir.path().join("x"))
        .solved(MINUTE);
    assert!(r["search"].is_null(), "{}", r["search"]);
    assert_eq!(r["problem"]["ratio"].as_f64(), Some(2.2));
    assert!(r["residual"].as_f64().unwrap() <= 1e-10);
    assert!(r["local_min"].as_bool().unwrap());
}

/// The search's evidence in `report.json`; a budget below what the stopping rule needs is
/// spent, said on stderr, and the cheapest gait found returned (exit 0).
#[test]
fn the_search_reports_its_evidence_and_a_spent_budget() {
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str, extra: &[&str]| {
        Solve::paper()
            .target("0.1,0,0")
            .no_plots()
            .out(&dir.path().join(name))
            .with(extra)
            .solved(MINUTE)
    };
    let (r, stderr) = run("default", &[]);
    let e = &r["search"];
    assert_eq!(e["rule_met"].as_bool(), Some(true), "{e}");
    assert!(!stderr.contains("warning"), "{stderr}");
    let starts = e["starts"].as_u64().unwrap();
    // The default budget without a joint limit.
    let budget = purcell_solver::solver::settings::FREE_STARTS as u64;
    assert!((128..=budget).contains(&starts), "{e}");
    assert_eq!(e["budget"].as_u64(), Some(budget));
    assert!(e["unseen_estimate"].as_f64().unwrap() <= 0.005, "{e}");
    let minima = e["minima"].as_array().unwrap();
    assert_eq!(e["distinct_minima"].as_u64(), Some(minima.len() as u64));
    // Each start reaches at most one minimum (the zero loop reaches none here).
    let hits: u64 = minima.iter().map(|m| m["hits"].as_u64().unwrap()).sum();
    assert!(hits <= starts, "{hits} hits from {starts} starts");
    // The returned gait is the cheapest admissible coarse minimum, refined.
    let coarse = minima
        .iter()
        .find(|m| m["max_abs_alpha"].as_f64().unwrap() < std::f64::consts::PI)
        .unwrap();
    let (fine, c) = (
        r["cost"].as_f64().unwrap(),
        coarse["cost"].as_f64().unwrap(),
    );
    assert!((fine / c - 1.0).abs() < 1e-2, "fine {fine}, coarse {c}");

    let (r, stderr) = run("budget", &["--starts", "32"]);
    let e = &r["search"];
    assert_eq!(e["rule_met"].as_bool(), Some(false), "{e}");
    assert_eq!(e["starts"].as_u64(), Some(32));
    assert!(
        stderr.contains("warning: the search used its budget of 32 starts"),
        "{stderr}"
    );
}

/// `--from` a gait whose branch leaves the admissible shapes on the way (the paper's gait,
/// near the links' overlap, towards a far target): said on stderr, and the global search's
/// gait returned instead, the same as `solve` alone gives.
#[test]
fn solve_from_falls_back_to_the_search_off_the_admissible_shapes() {
    let dir = tempfile::tempdir().unwrap();
    let paper = dir.path().join("paper");
    Solve::paper().no_plots().out(&paper).solved(MINUTE);
    let solve = |name: &str, from: bool| {
        let far = Solve::paper()
            .target("0.35,0,0")
            .no_plots()
            .out(&dir.path().join(name));
        let far = if from {
            far.from(&paper.join("costate.json"))
        } else {
            far
        };
        far.solved(MINUTE)
    };
    let (warm, stderr) = solve("warm", true);
    assert!(
        stderr.contains("--from reached no admissible extremal")
            && stderr.contains("solved by the global search instead"),
        "{stderr}"
    );
    assert!(!warm["search"].is_null());
    assert_eq!(warm["admissible"].as_bool(), Some(true));
    let (alone, _) = solve("alone", false);
    let (a, b) = (
        warm["cost"].as_f64().unwrap(),
        alone["cost"].as_f64().unwrap(),
    );
    assert!((a - b).abs() <= 1e-9 * b, "{a} vs {b}");
}

/// A small sweep: every target solved, the file lists each with its cost, and the map is
/// written; mirror-image targets cost the same.
#[test]
fn a_sweep_writes_its_table_and_map() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("atlas");
    let sweep = [
        "sweep",
        "--x",
        "0.05:0.15:3",
        "--y",
        "-0.1:0.1:3",
        "--theta",
        "0",
    ];
    let o = sim_in(
        None,
        &[&sweep[..], &["--out", arg(&out)]].concat(),
        3 * MINUTE,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 9);
    let cost = |x: &str, y: &str| -> f64 {
        let r = rows.iter().find(|r| r[0] == x && r[1] == y).expect("row");
        assert_eq!(r[9], "ok");
        r[3].parse().unwrap()
    };
    for x in ["0.05", "0.1", "0.15"] {
        let (up, down) = (cost(x, "0.1"), cost(x, "-0.1"));
        assert!((up - down).abs() <= 1e-9 * up, "{x}: {up} vs {down}");
    }
    let svg = std::fs::read_to_string(out.join("sweep.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
}
