//! Issue 26, `robustness`: a stored gait through a mismatched plant, open and closed loop.

use crate::common;

use common::*;

const LIMIT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../core/examples/paper-limit.gait"
);

/// The JSON report of `robustness` of the constrained paper gait with `args`.
fn json(args: &[&str]) -> serde_json::Value {
    robustness_json(LIMIT, args)
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

/// `export --tracking` adds the tracking table (a version-3 gait of 64 KiB of gains at most);
/// `robustness --digest` flies it closed loop in f32 and lands where `--f32` does; a gait
/// without a table is refused with the command that makes one.
#[test]
fn export_tracking_then_digest_flies_the_stored_table() {
    let tmp = tempfile::tempdir().unwrap();
    let gait = tmp.path().join("limit-tracking.gait");
    let o = sim(&["export", "--gait", LIMIT, "--tracking", "--out", arg(&gait)]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("tracking records=595"),
        "{}",
        stdout(&o)
    );
    let bytes = std::fs::read(&gait).unwrap();
    let table = purcell_core::Gait::from_bytes(&bytes)
        .unwrap()
        .tracking()
        .unwrap();
    assert!(table.len() * purcell_core::gait::TRACKING_RECORD_LEN <= 65536);
    let o = sim(&[
        "robustness",
        "--gait",
        arg(&gait),
        "--ratio-error",
        "0.1",
        "--digest",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let out = stdout(&o);
    let field = |name: &str| -> f64 {
        let at = out.find(name).unwrap() + name.len();
        out[at..]
            .split_whitespace()
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    assert!(out.starts_with("closed_digest: 0x"), "{out}");
    let r = json(&["--ratio-error", "0.1", "--f32"]);
    let closed = &r["cases"][0]["closed"];
    for (name, key) in [(" g=", "g_error"), ("alpha=", "alpha_error")] {
        let expected = closed[key].as_f64().unwrap();
        assert!(
            (field(name) - expected).abs() <= 1e-3 * expected,
            "{out} vs {closed}"
        );
    }
    let o = sim(&[
        "robustness",
        "--gait",
        LIMIT,
        "--ratio-error",
        "0.1",
        "--digest",
    ]);
    assert_exit(&o, 2, "export --gait FILE --tracking");
}

/// `--plan`: `export --tracking --plan` stores the neighbouring extremal's gain, which
/// `robustness --digest` flies as `robustness --plan --f32` computes it; a gait with a joint
/// limit keeps the LQR's, said in the line printed; `--plan` needs `--tracking`.
#[test]
fn a_plan_table_is_stored_and_flies_as_computed() {
    let paper = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../core/examples/paper.gait"
    );
    let tmp = tempfile::tempdir().unwrap();
    // `export --tracking --plan` of `from` into `out`, which says `says`.
    let export = |from: &str, out: &std::path::Path, says: &str| {
        let o = sim(&[
            "export",
            "--gait",
            from,
            "--tracking",
            "--plan",
            "--out",
            arg(out),
        ]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        assert!(stdout(&o).contains(says), "{}", stdout(&o));
    };
    let gait = tmp.path().join("paper-plan.gait");
    export(paper, &gait, "gain on the ratio error: extremal");
    let o = sim(&[
        "robustness",
        "--gait",
        arg(&gait),
        "--ratio-error",
        "0.05",
        "--digest",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let printed = stdout(&o);
    let g: f64 = printed
        .split(" g=")
        .nth(1)
        .unwrap()
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let o = sim(&[
        "robustness",
        "--gait",
        paper,
        "--ratio-error",
        "0.05",
        "--plan",
        "--f32",
        "--json",
    ]);
    let r: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(r["design"]["feedforward"]["from"], "extremal");
    let expected = r["cases"][0]["closed"]["g_error"].as_f64().unwrap();
    assert!(
        (g - expected).abs() <= 1e-3 * expected,
        "{printed} vs {expected}"
    );
    let limited = tmp.path().join("limit-plan.gait");
    export(LIMIT, &limited, "LQR (no plan: the gait has a joint limit)");
    let o = sim(&["export", "--gait", paper, "--plan", "--out", arg(&limited)]);
    assert_eq!(o.status.code(), Some(2));
}
