//! `purcell-sim solve`, `solve --from` and `sweep` end to end: exit codes, outputs, and no
//! input that makes the search run without end.

mod common;

use std::path::Path;
use std::process::Output;
use std::time::Duration;

/// Runs the binary; fails the test if it is still running after `limit`.
fn sim(args: &[&str], limit: Duration) -> Output {
    common::sim_in(None, args, limit)
}

fn report(dir: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(dir.join("report.json")).unwrap()).unwrap()
}

const MINUTE: Duration = Duration::from_secs(60);

#[test]
fn the_zero_target_returns_cost_zero() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("stay");
    let o = sim(
        &[
            "solve",
            "--target",
            "0,0,0",
            "--no-plots",
            "--out",
            out.to_str().unwrap(),
        ],
        MINUTE,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(&out);
    assert_eq!(r["cost"].as_f64(), Some(0.0));
    assert_eq!(r["local_min"].as_bool(), Some(true));
}

/// Inputs that made the former start generator loop for ever (no random start fitted inside
/// 90 % of the limit): now they end, with a solution or exit 3.
#[test]
fn starts_near_the_limit_do_not_hang() {
    let dir = tempfile::tempdir().unwrap();
    for (i, extra) in [
        &["--alpha0", "3,0", "--seed", "1"][..],
        &["--alpha-max", "0.2", "--starts", "9"][..],
    ]
    .iter()
    .enumerate()
    {
        let out = dir.path().join(format!("o{i}"));
        let mut args = vec!["solve", "--no-plots", "--out", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        let o = sim(&args, 2 * MINUTE);
        let code = o.status.code();
        assert!(code == Some(0) || code == Some(3), "{extra:?}: {code:?}");
    }
}

/// A stored extremal continued to a nearby target, start shape and horizon: the result is
/// an extremal of the new problem (residual, KKT, local minimum) and costs what a full solve
/// of it costs when it is the same branch.
#[test]
fn solve_from_a_stored_extremal_reaches_a_nearby_problem() {
    let dir = tempfile::tempdir().unwrap();
    let first = dir.path().join("first");
    let o = sim(
        &[
            "solve",
            "--target",
            "0.1,0,0",
            "--no-plots",
            "--out",
            first.to_str().unwrap(),
        ],
        MINUTE,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let costate = first.join("costate.json");
    let near = dir.path().join("near");
    let o = sim(
        &[
            "solve",
            "--from",
            costate.to_str().unwrap(),
            "--target",
            "0.13,0.02,0.1",
            "--alpha0",
            "0.1,-0.1",
            "--horizon",
            "80",
            "--no-plots",
            "--out",
            near.to_str().unwrap(),
        ],
        MINUTE,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(&near);
    assert!(r["residual"].as_f64().unwrap() <= 1e-10);
    assert!(r["kkt_residual"].as_f64().unwrap() <= 1e-8);
    assert_eq!(r["problem"]["target"][0].as_f64(), Some(0.13));
    assert_eq!(r["problem"]["steps"].as_u64(), Some(8000));
    // Another swimmer: refused before any work.
    let o = sim(
        &[
            "solve",
            "--from",
            costate.to_str().unwrap(),
            "--ratio",
            "3",
            "--out",
            dir.path().join("x").to_str().unwrap(),
        ],
        MINUTE,
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("another swimmer"));
}

/// A small sweep: every target solved, the file lists each with its cost, and the map is
/// written; mirror-image targets cost the same.
#[test]
fn a_sweep_writes_its_table_and_map() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("atlas");
    let o = sim(
        &[
            "sweep",
            "--x",
            "0.05:0.15:3",
            "--y",
            "-0.1:0.1:3",
            "--theta",
            "0",
            "--out",
            out.to_str().unwrap(),
        ],
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
