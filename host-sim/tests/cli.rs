//! The `purcell-sim` binary: bad input, limits, exit codes, unreachable targets, costate
//! files, connection, closed stdout. (Outputs: `outputs.rs`; random inputs: `cli_props.rs`.)

mod common;

use common::*;
use std::path::Path;
use std::process::Stdio;
use std::time::{Duration, Instant};

fn refused_before_work(extra: &[&str], needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let mut args = vec!["solve", "--out", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    let t0 = Instant::now();
    let o = sim(&args);
    assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", stderr(&o));
    assert!(stderr(&o).contains(needle), "{extra:?}: {}", stderr(&o));
    assert!(t0.elapsed() < Duration::from_secs(10), "{extra:?} did work");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn bad_inputs_are_refused_with_a_clear_message() {
    refused_before_work(&["--step", "0"], "step h must be positive");
    refused_before_work(&["--step", "-0.01"], "step h must be positive");
    refused_before_work(&["--horizon", "NaN"], "horizon must be a finite number");
    refused_before_work(&["--target", "inf,0,0"], "target must be a finite number");
    refused_before_work(&["--horizon", "100.005"], "not a whole number of steps");
    refused_before_work(&["--alpha0", "3.2,0"], "alpha0");
    refused_before_work(&["--alpha0", "0,-3.1415926536"], "alpha0");
    refused_before_work(&["--links", "1,0,1"], "link length L1 must be positive");
    refused_before_work(&["--drag", "-1"], "drag k must be positive");
    refused_before_work(&["--ratio", "0"], "drag ratio r must be positive");
    refused_before_work(&["--starts", "0"], "--starts must be 1 to 100");
    refused_before_work(&["--segments", "0"], "--segments must be 1 to 200");
}

/// Issue 9, defect 4: no upper bounds (`--segments 100000000` aborted on allocation,
/// `--starts 1000000000` ran with no end). Every bound is refused at once with exit 2.
#[test]
fn work_is_bounded_and_refused_above_the_limits() {
    refused_before_work(&["--segments", "100000000"], "--segments must be 1 to 200");
    refused_before_work(&["--starts", "1000000000"], "--starts must be 1 to 100");
    refused_before_work(
        &["--horizon", "100000", "--step", "0.01"],
        "more than solve's limit of 1000000",
    );
    refused_before_work(&["--horizon", "1e9"], "more than the limit");
}

/// Issue 9, defect 10: `solve` validates the model like `connection` (it started work and
/// exited 3 with "best residual inf"), and the message blames the connection, not the law's
/// `I − hB`. Issue 9, defect 11 for `solve`: its costate is replayed in f32.
#[test]
fn every_subcommand_validates_the_model_the_same_way() {
    let blame = "connection A(alpha) cannot be computed";
    refused_before_work(&["--links", "1e300,1,1"], blame);
    let o = sim(&["connection", "--alpha", "0.5,-0.3", "--links", "1e300,1,1"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains(blame), "{}", stderr(&o));
    assert!(!stderr(&o).contains("I - h"), "{}", stderr(&o));
    refused_before_work(&["--links", "1e39,1,1"], "in f32");
    refused_before_work(&["--step", "1e-50", "--horizon", "1e-48"], "in f32");
}

#[test]
fn unreachable_target_exits_3_with_best_residual_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("new/parents/far");
    let o = sim(&[
        "solve",
        "--target",
        "40,0,0",
        "--horizon",
        "10",
        "--starts",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("best residual"), "{}", stderr(&o));
    // No output, no staging directory, not even the parents it created.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

const GOOD: &str = r#"{"format":"purcell-costate","version":2,
 "model":{"links":[1,1,1],"drag":1,"ratio":2},"h":0.01,"steps":200,"alpha0":[0,0],
 "target":[0.1,0.1,0],"mu":[0.1,0.2,0.0],"xi0":[0.01,-0.02],"checkpoint_every":100,
 "checkpoints":[{"k":100,"alpha":[0.01,-0.02],"g":[0.001,0.0,1,0],"xi":[0.01,-0.02]}]}"#;

fn refused_file(name: &str, text: &str, needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), name, text);
    let o = sim(&["replay", "--costate", &p]);
    assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
    assert!(stderr(&o).contains(needle), "{name}: {}", stderr(&o));
}

#[test]
fn costate_files_are_read_strictly() {
    let dir = tempfile::tempdir().unwrap();
    let ok = write(dir.path(), "ok.json", GOOD);
    let o = sim(&["replay", "--costate", &ok]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(report["replays"].as_array().unwrap().len(), 4);

    let cases = [
        ("truncated.json", &GOOD[..GOOD.len() / 2], "malformed"),
        (
            "version.json",
            &GOOD.replace("\"version\":2", "\"version\":1")[..],
            "version 1",
        ),
        (
            "v1-checkpoint.json",
            &GOOD.replace("\"alpha\":[0.01,-0.02],\"g\":[0.001,0.0,1,0],", "")[..],
            "malformed",
        ),
        (
            "overlap.json",
            &GOOD.replace("[0.01,-0.02],\"g\"", "[3.2,-0.02],\"g\"")[..],
            "link-overlap",
        ),
        (
            "rotation.json",
            &GOOD.replace("[0.001,0.0,1,0]", "[0.001,0.0,1,0.5]")[..],
            "unit length",
        ),
        (
            "format.json",
            &GOOD.replace("purcell-costate", "other")[..],
            "not a costate file",
        ),
        (
            "extra.json",
            &GOOD.replace("\"h\":0.01", "\"h\":0.01,\"x\":1")[..],
            "malformed",
        ),
        (
            "beyond.json",
            &GOOD.replace("\"k\":100", "\"k\":300")[..],
            "checkpoint 1 is at k = 300",
        ),
        (
            "short.json",
            &GOOD.replace("[0.1,0.2,0.0]", "[0.1,0.2]")[..],
            "malformed",
        ),
        (
            "step.json",
            &GOOD.replace("\"h\":0.01", "\"h\":-0.01")[..],
            "step h must be positive",
        ),
    ];
    for (name, text, needle) in cases {
        refused_file(name, text, needle);
    }
}

/// Issue 9, defect 11: values outside f32 range were accepted and every f32 replay failed
/// (exit 0); a checkpoint at k = 0 silently replaced the start; `checkpoint_every` was not
/// checked against the checkpoints.
#[test]
fn costate_files_fit_f32_and_their_checkpoints_sit_where_checkpoint_every_says() {
    let cases = [
        (
            GOOD.replace("[1,1,1]", "[1e39,1,1]"),
            "links = 1e39,1.0,1.0 overflows or rounds to zero in f32",
        ),
        (
            GOOD.replace("[0.1,0.2,0.0]", "[0.1,1e39,0.0]"),
            "mu = 0.1,1e39,0.0 overflows",
        ),
        (
            GOOD.replace("\"h\":0.01", "\"h\":1e-50"),
            "step h = 1e-50 overflows or rounds to zero in f32",
        ),
        (
            GOOD.replace("\"k\":100", "\"k\":0"),
            "checkpoint 1 is at k = 0",
        ),
        (
            GOOD.replace("\"checkpoint_every\":100", "\"checkpoint_every\":50"),
            "call for 3 checkpoints",
        ),
        (
            GOOD.replace("\"checkpoint_every\":100", "\"checkpoint_every\":0"),
            "call for 0 checkpoints",
        ),
    ];
    for (text, needle) in &cases {
        refused_file("c.json", text, needle);
    }
    // An f64-only replay of a file beyond f32 range is fine.
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "mu.json",
        &GOOD.replace("[0.1,0.2,0.0]", "[1e-39,1e39,0.0]"),
    );
    let o = sim(&["replay", "--costate", &p, "--precision", "f64"]);
    assert_ne!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(!stderr(&o).contains("f32"), "{}", stderr(&o));
}

/// Issue 9, defect 7: `replay` exited 0 when every replay failed, with the failure only in
/// the JSON. Now exit 3, and stderr names the replay, the step and the reason.
#[test]
fn a_failed_replay_exits_3_naming_the_step_and_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "fast.json",
        &GOOD.replace("\"xi0\":[0.01,-0.02]", "\"xi0\":[50,-0.02]"),
    );
    let o = sim(&["replay", "--costate", &p, "--precision", "f32"]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("f32 replay with checkpoints failed at step 6 of 200 (t = 0.06 s): joint angle at or past the link-overlap limit"),
        "{e}"
    );
    // The report is still printed, with the step.
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(report["replays"][0]["failed_at_step"], 6);
    // Exit 0 only when every replay succeeds.
    let ok = write(dir.path(), "ok.json", GOOD);
    assert_eq!(sim(&["replay", "--costate", &ok]).status.code(), Some(0));
}

#[test]
fn connection_prints_the_model_test_vector() {
    let o = sim(&["connection", "--alpha", "0.5,-0.3"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let a = |r: usize, c: usize| v["A"][r][c].as_f64().unwrap();
    assert!((a(0, 0) + 0.0524221297521321).abs() < 1e-13);
    assert!((a(2, 1) - 0.261512677482497).abs() < 1e-13);
    let d = v["dA_dalpha2"][1][0].as_f64().unwrap();
    assert!((d - 7.14311629219022e-05).abs() < 1e-13);
    let o = sim(&["connection", "--alpha", "3.2,0"]);
    assert_eq!(o.status.code(), Some(2));
}

/// Issue 9, defect 12: negative numbers as typed (`--alpha -0.5,0.3` failed with
/// "unexpected argument '-0' found"), and defaults printed as they can be typed back
/// (`0.1 0.1 0` could not).
#[test]
fn negative_numbers_work_as_typed_and_help_defaults_paste_back() {
    let spaced = sim(&["connection", "--alpha", "-0.5,0.3"]);
    assert_eq!(spaced.status.code(), Some(0), "{}", stderr(&spaced));
    let joined = sim(&["connection", "--alpha=-0.5,0.3"]);
    assert_eq!(spaced.stdout, joined.stdout);
    // Parsed (the refusal is our validation's, after parsing every number).
    refused_before_work(
        &[
            "--alpha0",
            "-0.5,0.3",
            "--target",
            "-0.1,0,0",
            "--alpha-max",
            "-1",
        ],
        "alpha-max must be in ]0, pi] rad (got -1.0)",
    );
    let help = String::from_utf8_lossy(&sim(&["solve", "--help"]).stdout).into_owned();
    for (flag, default) in [
        ("--target", "0.1,0.1,0"),
        ("--alpha0", "0,0"),
        ("--links", "1,1,1"),
    ] {
        assert!(
            help.contains(&format!("[default: {default}]")),
            "{flag}: {help}"
        );
        // Pasted back, each parses (the refusal is about --step).
        refused_before_work(&[flag, default, "--step", "0"], "step h must be positive");
    }
}

#[test]
fn help_explains_units() {
    let o = sim(&["solve", "--help"]);
    let text = String::from_utf8_lossy(&o.stdout);
    for needle in [
        "metres",
        "seconds",
        "radians",
        "--alpha-max",
        "--checkpoint-every",
        "--force",
    ] {
        assert!(text.contains(needle), "{needle}");
    }
}

/// Issue 9, defect 9: a closed stdout panicked (exit 101 with a backtrace). A closed pipe
/// ends quietly with exit 0; a full disk is an I/O error, exit 1, said on stderr.
#[test]
fn a_closed_or_full_stdout_does_not_panic() {
    let mut c = command(&["connection", "--alpha", "0.5,-0.3"]);
    let mut child = c.spawn().unwrap();
    drop(child.stdout.take()); // the reader is gone before anything is written
    let o = wait(child, LIMIT, "connection | (closed)");
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stderr(&o).is_empty(), "{}", stderr(&o));

    let full = std::fs::OpenOptions::new().write(true).open("/dev/full");
    if let Ok(full) = full {
        let mut c = command(&["connection", "--alpha", "0.5,-0.3"]);
        c.stdout(Stdio::from(full));
        let o = wait(c.spawn().unwrap(), LIMIT, "connection >/dev/full");
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        assert!(
            stderr(&o).contains("error: writing to stdout"),
            "{}",
            stderr(&o)
        );
        assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
    }
}
