//! The `purcell-sim` binary: bad input, unreachable targets, costate files, connection.

use std::path::Path;
use std::process::{Command, Output};

fn sim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_purcell-sim"))
        .args(args)
        .output()
        .expect("binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

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
    let o = sim(&args);
    assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", stderr(&o));
    assert!(stderr(&o).contains(needle), "{extra:?}: {}", stderr(&o));
    assert!(!out.exists());
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
}

#[test]
fn unreachable_target_exits_nonzero_with_best_residual_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("far");
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
    assert!(!out.exists());
    // No temporary directory left behind either.
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
            "order.json",
            &GOOD.replace("\"k\":100", "\"k\":300")[..],
            "strictly increasing",
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
    ];
    for (name, text, needle) in cases {
        let p = write(dir.path(), name, text);
        let o = sim(&["replay", "--costate", &p]);
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{name}: {}", stderr(&o));
    }
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
    ] {
        assert!(text.contains(needle), "{needle}");
    }
}

/// `export` writes the binary gait of a costate file; replaying it is replaying the costate
/// file; the committed `tiny` pair is what `export` writes today, byte for byte.
#[test]
fn export_writes_the_gait_that_replays_like_its_costate_file() {
    let dir = tempfile::tempdir().unwrap();
    let json = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/tiny.costate.json");
    let gait = dir.path().join("tiny.gait");
    let o = sim(&[
        "export",
        "--costate",
        json.to_str().unwrap(),
        "--out",
        gait.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stdout(&o).contains("312 bytes"), "{}", stdout(&o));
    let committed = Path::new(env!("CARGO_MANIFEST_DIR")).join("../core/tests/data/tiny.gait");
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
    // Checkpoints change the f32 flight, not the f64 one (they are the f64 replay's states).
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
    assert_eq!((all.len(), &all[0]), (4, &all[1]));
}

/// A damaged gait file is refused with exit 2 and the reason; `export` of a bad costate file
/// writes nothing.
#[test]
fn corrupted_gaits_are_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let good =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("../core/tests/data/tiny.gait"))
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
