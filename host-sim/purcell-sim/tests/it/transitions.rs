//! `solve --alpha-end`: a gait from one shape to another (MODEL.md §12). The two transitions
//! of issue 38 solve, certified, at the cost CasADi + IPOPT finds (peers/README.md), the same
//! for other seeds, and their costate and gait files (version 4) replay through the core to the
//! end state; `--alpha-end` equal to `--alpha0` is the loop, byte for byte; a bad end shape
//! is refused before any work.

use crate::common;

use common::{Solve, arg, assert_exit, sim, stdout};
use std::path::Path;
use std::time::Duration;

const MINUTE: Duration = Duration::from_secs(60);

/// Solves `alpha0 → alpha_end` to the paper's target with `seed` into `dir`: the report.
fn transition(dir: &Path, alpha0: &str, alpha_end: &str, seed: u64) -> serde_json::Value {
    let solve = Solve::paper()
        .alpha0(alpha0)
        .flag("alpha-end", alpha_end)
        .flag("seed", &seed.to_string())
        .no_plots()
        .out(dir);
    solve.solved(MINUTE).0
}

/// The report's certificates, the costate file's version and end shape, and the replays
/// (the report's, `replay --costate` and the exported gait's `replay --gait`) landing on the
/// end shape and the target.
fn check_certified(dir: &Path, r: &serde_json::Value, end: [f64; 2], cost: f64) {
    let num = |k: &str| r[k].as_f64().unwrap();
    assert!((num("cost") - cost).abs() < 1e-6 * cost, "{}", r["cost"]);
    assert_eq!(r["local_min"].as_bool(), Some(true));
    assert_eq!(r["admissible"].as_bool(), Some(true));
    assert!(num("terminal_residual") < 1e-10 && num("kkt_residual") < 1e-9);
    assert!(num("law_residual") < 1e-9, "{}", r["law_residual"]);
    assert_eq!(r["problem"]["alpha_end"], serde_json::json!(end));
    let f32_replay = &r["replays"][2];
    assert_eq!(f32_replay["precision"], "f32");
    assert!(f32_replay["alpha_error"].as_f64().unwrap() < 1e-6);
    let costate: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("costate.json")).unwrap()).unwrap();
    assert_eq!(costate["version"], 4);
    assert_eq!(costate["alpha_end"], serde_json::json!(end));
    let gait = dir.join("gait.bin");
    let costate_path = dir.join("costate.json");
    let o = sim(&[
        "export",
        "--costate",
        arg(&costate_path),
        "--out",
        arg(&gait),
    ]);
    assert_exit(&o, 0, "");
    assert_eq!(std::fs::read(&gait).unwrap()[8], 4);
    for input in [["--costate", arg(&costate_path)], ["--gait", arg(&gait)]] {
        let o = sim(&[&["replay"][..], &input].concat());
        assert_exit(&o, 0, "");
        // With checkpoints, as firmware flies it (`replay: f32 with checkpoints`, then its
        // `terminal_error: alpha=8.21e-9 g=8.94e-9`), in f64 and f32. (Without checkpoints f32
        // drifts: 0.38 rad on the turning transition, whose path passes within 0.045 rad of
        // the overlap.)
        let out = stdout(&o);
        for precision in ["f64", "f32"] {
            let head = format!("replay: {precision} with checkpoints");
            let block = out.split(&head).nth(1).expect(&head);
            let line = block
                .lines()
                .find(|l| l.starts_with("terminal_error"))
                .unwrap();
            let value = |key: &str| -> f64 {
                let rest = line.split(key).nth(1).unwrap();
                rest.split_whitespace().next().unwrap().parse().unwrap()
            };
            assert!(
                value("alpha=") < 1e-6 && value("g=") < 1e-6,
                "{head}: {line}"
            );
        }
    }
}

#[test]
fn a_bent_swimmer_straightens_on_the_way_to_the_target() {
    let dir = tempfile::tempdir().unwrap();
    // J: CasADi + IPOPT's cheapest admissible from six starts agrees (peers/README.md).
    const J: f64 = 0.3062444;
    for seed in [0, 3] {
        let out = dir.path().join(format!("s{seed}"));
        let r = transition(&out, "1.0,0.8", "0,0", seed);
        check_certified(&out, &r, [0.0, 0.0], J);
    }
}

/// Forward to turning: from the paper's gait's shape (`0`) to the shape the turning gait
/// `solve --alpha0 0.8,-0.8 --target 0,0,0.5` starts from, reaching the paper's target.
#[test]
fn forward_to_turning_ends_where_the_turning_gait_starts() {
    let dir = tempfile::tempdir().unwrap();
    const J: f64 = 1.2532823;
    for seed in [0, 2] {
        let out = dir.path().join(format!("s{seed}"));
        let r = transition(&out, "0,0", "0.8,-0.8", seed);
        check_certified(&out, &r, [0.8, -0.8], J);
    }
}

/// `--alpha-end` equal to `--alpha0` is the loop: the same files, version 3, byte for byte.
#[test]
fn an_end_shape_equal_to_the_start_is_the_loop() {
    let dir = tempfile::tempdir().unwrap();
    let quick = Solve::quick().alpha0("0.3,0.3").no_plots();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    quick.clone().out(&a).solved(MINUTE);
    quick.flag("alpha-end", "0.3,0.3").out(&b).solved(MINUTE);
    let costate = |d: &Path| std::fs::read(d.join("costate.json")).unwrap();
    assert_eq!(costate(&a), costate(&b));
    assert!(
        String::from_utf8(costate(&a))
            .unwrap()
            .contains("\"version\": 3")
    );
    assert!(
        !String::from_utf8(costate(&a))
            .unwrap()
            .contains("alpha_end")
    );
}

/// An end shape past the overlap or the joint limit, or not two numbers: exit 2 at once.
#[test]
fn a_bad_end_shape_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    for (extra, says) in [
        (&["--alpha-end", "3.2,0"][..], "alpha-end = (3.2, 0.0) rad"),
        (
            &["--alpha-end", "1.2,0", "--alpha-max", "1.0"][..],
            "each |alpha-end_i| must be below alpha-max = 1.0",
        ),
        (&["--alpha-end", "1"][..], "--alpha-end"),
    ] {
        let o = Solve::quick().no_plots().out(&out).with(extra).run();
        assert_exit(&o, 2, says);
        assert!(!out.exists());
    }
}

/// `sweep --alpha-end`: every target's gait ends in the end shape; the report says which.
#[test]
fn a_sweep_of_transitions_reports_its_end_shape() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sweep");
    let o = sim(&[
        "sweep",
        "--x",
        "0.01:0.02:2",
        "--y",
        "0.01",
        "--horizon",
        "10",
        "--step",
        "0.01",
        "--alpha0",
        "0.3,0.3",
        "--alpha-end",
        "0,0",
        "--no-plots",
        "--out",
        arg(&out),
    ]);
    assert_exit(&o, 0, "");
    let r = common::report(&out);
    assert_eq!(r["problem"]["alpha_end"], serde_json::json!([0.0, 0.0]));
    assert_eq!(r["solved"], 2);
}
