//! Issue 26, `robustness`: a stored gait through a mismatched plant, open and closed loop.

mod common;

use common::*;

const LIMIT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../core/examples/paper-limit.gait"
);

/// The JSON report of `robustness` with `args`.
fn json(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["robustness", "--gait", LIMIT, "--json"];
    all.extend_from_slice(args);
    let o = sim(&all);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    serde_json::from_slice(&o.stdout).unwrap()
}

#[test]
fn json_reports_open_and_closed_loop_and_the_closed_loop_lands_closer() {
    let r = json(&["--ratio-error", "0.1"]);
    assert_eq!(r["format"], "purcell-robustness");
    let case = &r["cases"][0];
    assert_eq!(case["ratio_error"], 0.1);
    let g = |which: &str| case[which]["g_error"].as_f64().unwrap();
    assert!(g("closed") * 10.0 <= g("open"), "{case}");
    assert!(case["closed"]["max_abs_alpha"].as_f64().unwrap() <= 1.5 + 1e-12);
    // The table of the paper's gait fits 64 KiB in f32.
    assert!(r["table_bytes_f32"].as_u64().unwrap() <= 65536);
}

#[test]
fn table_flies_every_standard_case_and_out_writes_the_figure() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("rob");
    let o = sim(&["robustness", "--gait", LIMIT, "--table", "-o", arg(&out)]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let rows = stdout(&o).lines().filter(|l| l.starts_with("| ")).count();
    assert_eq!(rows, 1 + purcell_sim::cli::robustness::TABLE.len());
    for f in ["robustness.json", "robustness.svg", "robustness.png"] {
        assert!(out.join(f).is_file(), "{f}");
    }
}

#[test]
fn bad_input_is_refused_before_any_work() {
    let o = sim(&["robustness", "--gait", LIMIT, "--pose-noise", "-1"]);
    assert_exit(&o, 2, "--pose-noise");
    let o = sim(&["robustness", "--gait", LIMIT, "--ratio-error", "-1"]);
    assert_exit(&o, 2, "plant");
    let o = sim(&["robustness", "--ratio-error", "0.1"]);
    assert_exit(&o, 2, "");
}
