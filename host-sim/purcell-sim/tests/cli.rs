//! The `purcell-sim` binary: bad input, limits, exit codes, unreachable targets, costate
//! files, connection, closed stdout. (Outputs: `outputs.rs`; random inputs: `cli_props.rs`.)

mod common;

use common::*;
use std::path::Path;
use std::process::{Output, Stdio};
use std::time::{Duration, Instant};

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The `digest: 0x…` lines of a replay's output (each `0x` and 16 hex digits).
fn digests(o: &Output) -> Vec<String> {
    let text = stdout(o);
    let lines: Vec<String> = text
        .lines()
        .filter_map(|l| l.strip_prefix("digest: "))
        .map(str::to_string)
        .collect();
    for d in &lines {
        let hex = d.strip_prefix("0x").unwrap_or_else(|| panic!("{d}"));
        assert!(
            hex.len() == 16 && hex.chars().all(|c| c.is_ascii_hexdigit()),
            "{d}"
        );
    }
    lines
}

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
    refused_before_work(&["--starts", "0"], "--starts must be 1 to 4096");
}

/// Issue 9, defect 4: no upper bounds (`--segments 100000000` aborted on allocation,
/// `--starts 1000000000` ran with no end). Every bound is refused at once with exit 2.
#[test]
fn work_is_bounded_and_refused_above_the_limits() {
    refused_before_work(&["--starts", "1000000000"], "--starts must be 1 to 4096");
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

/// [`GOOD`] in version 3 with a joint limit and one arc of joint 1 ending at its checkpoint.
const GOOD_V3: &str = r#"{"format":"purcell-costate","version":3,
 "model":{"links":[1,1,1],"drag":1,"ratio":2},"h":0.01,"steps":200,"alpha0":[0,0],
 "target":[0.1,0.1,0],"mu":[0.1,0.2,0.0],"xi0":[0.01,-0.02],"checkpoint_every":100,
 "alpha_max":0.5,"arcs":[{"joint":1,"sign":1,"first":90,"last":100}],
 "checkpoints":[{"k":100,"alpha":[0.5,-0.02],"g":[0.001,0.0,1,0],"xi":[0.01,-0.02]}]}"#;
const ARC: &str = r#""arcs":[{"joint":1,"sign":1,"first":90,"last":100}],"#;

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
    assert_eq!(digests(&o).len(), 4, "{}", stdout(&o));

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
            "gait checkpoints must sit at every multiple of checkpoint_every below the horizon",
        ),
        (
            "short.json",
            &GOOD.replace("[0.1,0.2,0.0]", "[0.1,0.2]")[..],
            "malformed",
        ),
        (
            "step.json",
            &GOOD.replace("\"h\":0.01", "\"h\":-0.01")[..],
            "step h must be finite and positive",
        ),
        (
            "version4.json",
            &GOOD.replace("\"version\":2", "\"version\":4")[..],
            "version 4 (this build reads versions 2 and 3)",
        ),
        // Version 2 knows no joint limit; version 3 states it (null: none) and its arcs.
        (
            "v2-arcs.json",
            &GOOD.replace("\"h\":0.01", "\"h\":0.01,\"arcs\":[]")[..],
            "version 2 does not have the field \"arcs\"",
        ),
        (
            "v3-no-limit.json",
            &GOOD_V3.replace("\"alpha_max\":0.5,", "")[..],
            "version 3 needs the field \"alpha_max\"",
        ),
        (
            "v3-no-arcs.json",
            &GOOD_V3.replace(ARC, "")[..],
            "version 3 needs the field \"arcs\"",
        ),
        (
            "v3-joint.json",
            &GOOD_V3.replace("\"joint\":1", "\"joint\":0")[..],
            "joint-limit arc must have joint 1 or 2",
        ),
        (
            "v3-exit.json",
            &GOOD_V3.replace("\"last\":100", "\"last\":90")[..],
            "a joint-limit arc's last step has no checkpoint",
        ),
        (
            "v3-off-limit.json",
            &GOOD_V3.replace("\"alpha_max\":0.5", "\"alpha_max\":0.6")[..],
            "not on its limit",
        ),
        (
            "v3-unlimited.json",
            &GOOD_V3.replace("\"alpha_max\":0.5", "\"alpha_max\":null")[..],
            "present with arcs",
        ),
        (
            "v3-sign.json",
            &GOOD_V3.replace("\"sign\":1", "\"sign\":1.0")[..],
            "malformed",
        ),
    ];
    for (name, text, needle) in cases {
        refused_file(name, text, needle);
    }
    // The version-3 file itself, and without arcs (`"arcs": []`, `"alpha_max": null`).
    for (name, text) in [
        ("v3.json", GOOD_V3.to_string()),
        (
            "v3-free.json",
            GOOD.replace("\"version\":2", "\"version\":3")
                .replace("\"h\":0.01", "\"h\":0.01,\"alpha_max\":null,\"arcs\":[]"),
        ),
    ] {
        let p = write(dir.path(), name, &text);
        let o = sim(&["replay", "--costate", &p]);
        assert_eq!(o.status.code(), Some(0), "{name}: {}", stderr(&o));
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
            "gait checkpoints must sit at every multiple of checkpoint_every below the horizon",
        ),
        (
            GOOD.replace("\"checkpoint_every\":100", "\"checkpoint_every\":50"),
            "gait checkpoints must sit at every multiple of checkpoint_every below the horizon",
        ),
        (
            GOOD.replace("\"checkpoint_every\":100", "\"checkpoint_every\":0"),
            "gait checkpoints must sit at every multiple of checkpoint_every below the horizon",
        ),
    ];
    for (text, needle) in &cases {
        refused_file("c.json", text, needle);
    }
    // An f64-only replay of a file beyond f32 range is not refused: it runs, and the law
    // fails at its first step (a μ of 1e39 makes `I − h·B` singular), exit 3.
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "mu.json",
        &GOOD.replace("[0.1,0.2,0.0]", "[1e-39,1e39,0.0]"),
    );
    let o = sim(&["replay", "--costate", &p, "--precision", "f64"]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("f64 replay with checkpoints failed at step 0"),
        "{}",
        stderr(&o)
    );
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
    // The report is still printed, with the step, and so is `--out`'s JSON.
    assert!(
        stdout(&o).contains("failed at step 6: joint angle"),
        "{}",
        stdout(&o)
    );
    let json = dir.path().join("report.json");
    let o = sim(&[
        "replay",
        "--costate",
        &p,
        "--precision",
        "f32",
        "--out",
        json.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let report: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
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
        "alpha-max must be in ]0, pi[ rad: the links overlap at pi (got -1.0)",
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

/// `export` writes the binary gait of a costate file; replaying it is replaying the costate
/// file; the committed `tiny-limit` pair (a gait on its joint limit) is what `export` writes
/// today, byte for byte.
#[test]
fn export_writes_the_gait_that_replays_like_its_costate_file() {
    let dir = tempfile::tempdir().unwrap();
    let json = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/tiny-limit.costate.json");
    let gait = dir.path().join("tiny-limit.gait");
    let o = sim(&[
        "export",
        "--costate",
        json.to_str().unwrap(),
        "--out",
        gait.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("684 bytes") && stdout(&o).contains("arcs=2"),
        "{}",
        stdout(&o)
    );
    let committed =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../core/tests/data/tiny-limit.gait");
    assert_eq!(
        std::fs::read(&gait).unwrap(),
        std::fs::read(committed).unwrap()
    );

    for precision in ["f32", "f64"] {
        let from_gait = sim(&[
            "replay",
            "--gait",
            gait.to_str().unwrap(),
            "--precision",
            precision,
        ]);
        let from_json = sim(&[
            "replay",
            "--costate",
            json.to_str().unwrap(),
            "--precision",
            precision,
        ]);
        assert_eq!(from_gait.status.code(), Some(0), "{}", stderr(&from_gait));
        assert_eq!(digests(&from_gait).len(), 1);
        assert_eq!(stdout(&from_gait), stdout(&from_json));
    }
    // The periodic checkpoints change the f32 flight (the arcs' exits are restored either way).
    let f32_without = sim(&[
        "replay",
        "--gait",
        gait.to_str().unwrap(),
        "--precision",
        "f32",
        "--no-checkpoints",
    ]);
    let f32_with = sim(&[
        "replay",
        "--gait",
        gait.to_str().unwrap(),
        "--precision",
        "f32",
    ]);
    assert_ne!(digests(&f32_with), digests(&f32_without));
    let all = digests(&sim(&["replay", "--gait", gait.to_str().unwrap()]));
    assert_eq!(all.len(), 4);
}

/// The previous versions are still read: the version-2 costate file `tiny.costate.json` and
/// the version-1 gait `tiny-v1.gait` exported from it fly the same; exported again, the gait
/// is version 2 and flies the same too.
#[test]
fn previous_versions_are_still_read() {
    let dir = tempfile::tempdir().unwrap();
    let json = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/tiny.costate.json");
    let v1 = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../core/tests/data/tiny-v1.gait");
    let v2 = dir.path().join("tiny.gait");
    let o = sim(&[
        "export",
        "--costate",
        json.to_str().unwrap(),
        "--out",
        v2.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v2_bytes = std::fs::read(&v2).unwrap();
    assert_eq!(u16::from_le_bytes([v2_bytes[8], v2_bytes[9]]), 2);
    let replay = |flag: &str, path: &Path| {
        let o = sim(&["replay", flag, path.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        digests(&o)
    };
    let from_json = replay("--costate", &json);
    assert_eq!(from_json.len(), 4);
    assert_eq!(replay("--gait", &v1), from_json);
    assert_eq!(replay("--gait", &v2), from_json);
}

/// A damaged gait file is refused with exit 2 and the reason; `export` of a bad costate file
/// writes nothing.
#[test]
fn corrupted_gaits_are_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../core/tests/data/tiny-limit.gait"),
    )
    .unwrap();
    let mut flipped = good.clone();
    flipped[250] ^= 4;
    let mut version = good.clone();
    version[8] = 9;
    let cases: [(&str, Vec<u8>, &str); 5] = [
        ("flipped.gait", flipped, "checksum"),
        ("short.gait", good[..good.len() - 1].to_vec(), "length"),
        ("version.gait", version, "version 9"),
        ("json.gait", GOOD.as_bytes().to_vec(), "not a gait file"),
        ("empty.gait", Vec::new(), "not a gait file"),
    ];
    for (name, bytes, needle) in cases {
        let p = dir.path().join(name);
        std::fs::write(&p, bytes).unwrap();
        let o = sim(&["replay", "--gait", p.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{name}: {}", stderr(&o));
        assert!(o.stdout.is_empty());
    }
    let missing = dir.path().join("missing.gait");
    let o = sim(&["replay", "--gait", missing.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));

    let bad = write(
        dir.path(),
        "bad.json",
        &GOOD.replace("[0.001,0.0,1,0]", "[0.001,0.0,1,0.5]"),
    );
    let out = dir.path().join("bad.gait");
    let o = sim(&["export", "--costate", &bad, "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("unit length"), "{}", stderr(&o));
    assert!(!out.exists());
    let o = sim(&["replay"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
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

/// [`GOOD`] as a binary gait file, after `edit`.
fn gait_of(edit: impl FnOnce(&mut purcell_sim::costate_file::CostateFile)) -> Vec<u8> {
    let mut file = purcell_sim::costate_file::CostateFile::parse(GOOD).unwrap();
    edit(&mut file);
    file.to_gait().expect("the core's own check accepts it")
}

/// Issue 21, defect 2: `replay --gait` had no step limit (a gait patched to 2^32 − 1 steps
/// ran for 90 minutes; 10 000 001 steps were accepted). Now the costate route's limit,
/// refused at once with exit 2.
#[test]
fn gait_files_are_held_to_the_step_limit() {
    let dir = tempfile::tempdir().unwrap();
    for steps in [10_000_001, u32::MAX] {
        let p = dir.path().join(format!("{steps}.gait"));
        std::fs::write(
            &p,
            gait_of(|f| {
                f.gait.steps = steps;
                f.gait.checkpoint_every = 0;
                f.checkpoints.clear();
            }),
        )
        .unwrap();
        let t0 = Instant::now();
        let o = sim(&[
            "replay",
            "--gait",
            p.to_str().unwrap(),
            "--precision",
            "f64",
        ]);
        assert_eq!(o.status.code(), Some(2), "{steps}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("more than the limit 10000000"),
            "{steps}: {}",
            stderr(&o)
        );
        assert!(t0.elapsed() < Duration::from_secs(10), "{steps} steps ran");
    }
}

/// Issue 21, defect 4: `export` wrote gait files the f32 firmware cannot fly (exit 0), and
/// `replay --gait` of them exited 3 with wrong reasons. Both now refuse them with exit 2 and
/// the costate route's reason; an f64-only replay of such a gait still runs.
#[test]
fn export_and_replay_hold_gait_files_to_f32_like_costate_files() {
    type Edit = fn(&mut purcell_sim::costate_file::CostateFile);
    // With the exit code of the f64-only replay: 0 where it lands, 3 where the law fails on
    // the way (a μ or ξ of 1e39).
    let cases: [(Edit, &str, i32); 6] = [
        (|f| f.gait.model.links[0] = 1e39, "links = 1e39,1.0,1.0", 0),
        (
            |f| f.gait.model.links[1] = 1e-50,
            "links = 1.0,1e-50,1.0",
            0,
        ),
        (|f| f.gait.mu[1] = 1e39, "mu = 0.1,1e39,0.0", 3),
        (|f| f.gait.h = 1e-50, "step h = 1e-50", 0),
        (
            |f| f.checkpoints[0].xi[0] = 1e39,
            "xi of the checkpoint at k = 100",
            3,
        ),
        (|f| f.gait.model.drag = 1e39, "drag k = 1e39", 0),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (i, (edit, needle, f64_code)) in cases.into_iter().enumerate() {
        let mut file = purcell_sim::costate_file::CostateFile::parse(GOOD).unwrap();
        edit(&mut file);
        let json = write(dir.path(), &format!("{i}.json"), &file.to_json());
        let out = dir.path().join(format!("{i}.gait"));
        let o = sim(&["export", "--costate", &json, "--out", out.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{needle}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{needle}: {}", stderr(&o));
        assert!(stderr(&o).contains("in f32"), "{needle}: {}", stderr(&o));
        assert!(!out.exists(), "{needle}");

        std::fs::write(&out, file.to_gait().unwrap()).unwrap();
        let o = sim(&["replay", "--gait", out.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{needle}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{needle}: {}", stderr(&o));
        assert!(stderr(&o).contains("in f32"), "{needle}: {}", stderr(&o));
        let o = sim(&[
            "replay",
            "--gait",
            out.to_str().unwrap(),
            "--precision",
            "f64",
        ]);
        assert_eq!(o.status.code(), Some(f64_code), "{needle}: {}", stderr(&o));
    }
}

/// Issue 21, defect 5: duplicate keys were accepted (the last one won), and `export` turned
/// such a file into a gait with a fresh checksum.
#[test]
fn duplicate_keys_are_refused() {
    let cases = [
        GOOD.replace("\"version\":2", "\"version\":2,\"version\":3"),
        GOOD.replace(
            "\"version\":2",
            "\"format\":\"purcell-costate\",\"version\":2",
        ),
        GOOD.replace("\"xi0\"", "\"mu\":[0.1,0.2,0.0],\"xi0\""),
        GOOD.replace("\"drag\":1", "\"links\":[2,2,2],\"drag\":1"),
        GOOD.replace("\"k\":100", "\"k\":100,\"k\":100"),
    ];
    let dir = tempfile::tempdir().unwrap();
    for text in &cases {
        refused_file("dup.json", text, "duplicate key");
        let p = write(dir.path(), "dup.json", text);
        let out = dir.path().join("dup.gait");
        let o = sim(&["export", "--costate", &p, "--out", out.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{text}: {}", stderr(&o));
        assert!(stderr(&o).contains("duplicate key"), "{}", stderr(&o));
        assert!(!out.exists());
    }
}

/// Issue 21, defect 7: `sweep --alpha0 -0.5,0.3` was refused ("unexpected argument '-0'"),
/// and its help showed a default `0 0` that could not be typed back.
#[test]
fn sweep_takes_negative_shapes_and_shows_defaults_that_paste_back() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sweep");
    let help = String::from_utf8_lossy(&sim(&["sweep", "--help"]).stdout).into_owned();
    assert!(help.contains("[default: 0,0]"), "{help}");
    for alpha0 in ["-0.5,0.3", "0,0"] {
        // Parsed (the refusal is about --step, after parsing every flag).
        let o = sim(&[
            "sweep",
            "--alpha0",
            alpha0,
            "--step",
            "0",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(
            stderr(&o).contains("step h must be positive"),
            "{alpha0}: {}",
            stderr(&o)
        );
    }
    assert!(!out.exists());
}

/// `solve` and `sweep` share their problem's flags (one clap struct): a value that begins
/// with `-` is read as typed by both and refused by the same check with the same message
/// (`sweep` once refused `--horizon -inf` as an unknown flag `-i`), and nothing is written.
#[test]
fn solve_and_sweep_read_the_problem_flags_alike() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let out = out.to_str().unwrap();
    for flags in [
        ["--horizon", "-inf"],
        ["--horizon", "-1"],
        ["--step", "-nan"],
        ["--alpha-max", "-inf"],
        ["--alpha0", "-0.5,-4"],
        ["--links", "-1,1,1"],
        ["--drag", "-1"],
        ["--ratio", "-2"],
        ["--starts", "0"],
    ] {
        let solve = sim(&["solve", flags[0], flags[1], "--out", out]);
        let sweep = sim(&["sweep", flags[0], flags[1], "--out", out]);
        assert_eq!(
            solve.status.code(),
            Some(2),
            "{flags:?}: {}",
            stderr(&solve)
        );
        assert_eq!(
            sweep.status.code(),
            Some(2),
            "{flags:?}: {}",
            stderr(&sweep)
        );
        assert_eq!(stderr(&solve), stderr(&sweep), "{flags:?}");
        assert!(!stderr(&solve).contains("unexpected argument"), "{flags:?}");
    }
    assert!(!Path::new(out).exists());
}

/// The limits as the binary states them, digits grouped by spaces as in the README.
fn grouped(n: u64) -> String {
    let digits = n.to_string();
    let mut s = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            s.push(' ');
        }
        s.push(c);
    }
    s
}

/// Issue 21, defect 8: the README's exit-code table said `--starts` ≤ 100 and named a
/// `--segments` flag the binary does not have. Every limit it states is the binary's, and
/// every flag it names exists.
#[test]
fn the_readme_exit_code_table_states_the_binary_limits() {
    use purcell_sim::cli::{MAX_SOLVE_STEPS, MAX_STARTS, MAX_SWEEP_TARGETS};
    let readme =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../README.md"))
            .unwrap();
    let row = readme
        .lines()
        .find(|l| l.starts_with("| 2 | bad input"))
        .expect("the exit-code table has a row for 2");
    for limit in [
        format!("`--starts` 1 to {}", grouped(MAX_STARTS as u64)),
        format!(
            "`solve` ≤ {} steps and ≤ {} checkpoints",
            grouped(u64::from(MAX_SOLVE_STEPS)),
            grouped(u64::from(purcell_sim::cli::MAX_CHECKPOINTS))
        ),
        format!(
            "`replay` and `export` ≤ {} steps",
            grouped(purcell_solver::problem::MAX_STEPS)
        ),
        format!("`sweep` ≤ {} targets", grouped(MAX_SWEEP_TARGETS as u64)),
        format!(
            "input files ≤ {} MiB",
            purcell_sim::input::MAX_INPUT_BYTES >> 20
        ),
    ] {
        assert!(
            row.contains(&limit),
            "README's exit code 2 lacks {limit:?}: {row}"
        );
    }
    // Every number in the row is one of those, the exit code, or a float width.
    let mut known: Vec<String> = ["2", "32", "64", "1"].map(String::from).to_vec();
    known.extend([
        grouped(MAX_STARTS as u64),
        grouped(u64::from(MAX_SOLVE_STEPS)),
        grouped(u64::from(purcell_sim::cli::MAX_CHECKPOINTS)),
        grouped(purcell_solver::problem::MAX_STEPS),
        grouped(MAX_SWEEP_TARGETS as u64),
    ]);
    for number in row
        .split(|c: char| !(c.is_ascii_digit() || c == ' '))
        .map(str::trim)
        .filter(|s| !s.is_empty())
    {
        assert!(
            known.iter().any(|k| k == number),
            "README states {number:?}: {row}"
        );
    }
    // Every flag it names is a flag of some subcommand.
    let helps: String = ["solve", "sweep", "replay", "export", "field", "connection"]
        .iter()
        .map(|c| String::from_utf8_lossy(&sim(&[c, "--help"]).stdout).into_owned())
        .collect();
    for flag in row
        .split('`')
        .filter(|s| s.starts_with("--"))
        .filter_map(|s| s.split(' ').next())
    {
        assert!(
            helps.contains(&format!("{flag} ")),
            "README names {flag}, which no subcommand has"
        );
    }
}

/// `solve` of the quick problem with `target` into a fresh directory: its report.
fn quick_report(target: &str, extra: &[&str]) -> (Output, Option<serde_json::Value>) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let mut args = vec!["solve", "--out", out.to_str().unwrap(), "--no-plots"];
    args.extend_from_slice(&["--horizon", "10", "--step", "0.1", "--starts", "1"]);
    args.extend_from_slice(&["--target", target]);
    args.extend_from_slice(extra);
    let o = sim(&args);
    let report = std::fs::read(out.join("report.json"))
        .ok()
        .map(|b| serde_json::from_slice(&b).unwrap());
    (o, report)
}

/// Issue 21 (lower): `--target 0.1,0.1,6.283185307179586` exited 3; the angle is taken
/// modulo 2π into ]−π, π], and `--help` says so.
#[test]
fn the_target_angle_is_taken_modulo_two_pi() {
    let (o, zero) = quick_report("0.01,0.01,0", &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let (o, turn) = quick_report("0.01,0.01,6.283185307179586", &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let (zero, turn) = (zero.unwrap(), turn.unwrap());
    assert_eq!(turn["problem"]["target"][2], 0.0);
    assert_eq!(turn["cost"], zero["cost"]);
    let help = String::from_utf8_lossy(&sim(&["solve", "--help"]).stdout).into_owned();
    assert!(help.contains("modulo 2 pi into ]-pi, pi]"), "{help}");
}

/// Issue 21 (lower): `--checkpoint-every` ≥ N silently wrote no checkpoints. Given, it must
/// be below N (or 0); the default gives none on a short horizon; and no spacing may make
/// the costate file too large to read back.
#[test]
fn an_explicit_checkpoint_spacing_is_below_the_horizon() {
    for every in ["100", "150"] {
        let (o, report) = quick_report("0.01,0.01,0", &["--checkpoint-every", every]);
        assert_eq!(o.status.code(), Some(2), "{every}: {}", stderr(&o));
        assert!(
            stderr(&o).contains(&format!(
                "--checkpoint-every {every} is not below the horizon's 100 steps"
            )),
            "{}",
            stderr(&o)
        );
        assert!(report.is_none());
    }
    for every in [
        &["--checkpoint-every", "0"][..],
        &["--checkpoint-every", "50"],
        &[],
    ] {
        let (o, _) = quick_report("0.01,0.01,0", every);
        assert_eq!(o.status.code(), Some(0), "{every:?}: {}", stderr(&o));
    }
    refused_before_work(
        &["--horizon", "10000", "--checkpoint-every", "1"],
        "more than the limit 100000",
    );
}

/// Issue 21 (lower): a flag given twice was concatenated (`--alpha 0.1 --alpha 0.2` was
/// the shape `0.1,0.2`). It is a usage error now, lists and numbers alike.
#[test]
fn a_flag_given_twice_is_refused() {
    for args in [
        &["connection", "--alpha", "0.1", "--alpha", "0.2"][..],
        &[
            "connection",
            "--alpha",
            "0.1,0.2",
            "--links",
            "1,1",
            "--links",
            "1",
        ],
        &[
            "connection",
            "--alpha",
            "0.1,0.2",
            "--drag",
            "1",
            "--drag",
            "2",
        ],
    ] {
        let o = sim(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("cannot be used multiple times"),
            "{args:?}: {}",
            stderr(&o)
        );
    }
}

/// Issue 21 (lower): a system that refuses threads made the search panic (exit 101). It is
/// exit 1 with the reason. (Run as `nobody` limited to one process, where the test is root
/// and util-linux's `prlimit` and `setpriv` are there.)
#[test]
#[cfg(target_os = "linux")]
fn no_worker_threads_is_exit_1_not_a_panic() {
    use std::os::unix::fs::PermissionsExt;
    let have = |tool: &str| {
        std::process::Command::new(tool)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    };
    if unsafe { libc::geteuid() } != 0 || !have("prlimit") || !have("setpriv") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::set_permissions(dir.path(), std::fs::Permissions::from_mode(0o777)).unwrap();
    let out = dir.path().join("out");
    let mut c = std::process::Command::new("prlimit");
    c.args([
        "--nproc=1",
        "setpriv",
        "--reuid=65534",
        "--regid=65534",
        "--clear-groups",
    ])
    .arg(env!("CARGO_BIN_EXE_purcell-sim"))
    .args([
        "solve",
        "--out",
        out.to_str().unwrap(),
        "--no-plots",
        "--horizon",
        "10",
    ])
    .args(["--step", "0.1", "--starts", "1", "--target", "0.01,0.01,0"])
    .stdin(Stdio::null())
    .stdout(Stdio::piped())
    .stderr(Stdio::piped());
    let o = wait(c.spawn().unwrap(), LIMIT, "solve without threads");
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("cannot start worker threads"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists());
}
