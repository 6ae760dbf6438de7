//! Costate files as `replay` and `export` read them: strictly (format, version, fields,
//! duplicate keys), held to what the core's gait check and `f32` accept, and a replay that
//! fails on the way exits 3 naming the step. (Binary gait files: `gait_files.rs`.)

use crate::common;

use common::fixtures::{ARC, COSTATE_V2, COSTATE_V3};
use common::*;
use std::path::Path;
use std::process::Output;

/// The refusal of checkpoints anywhere but at every `k = M, 2M, … < N`.
const MISPLACED: &str =
    "gait checkpoints must sit at every multiple of checkpoint_every below the horizon";

/// `replay --costate` of [`COSTATE_V2`] edited (`from` → `to`), written in `dir`, with
/// `extra` flags; the file's path and the run.
fn replay_edited(dir: &Path, from: &str, to: &str, extra: &[&str]) -> (String, Output) {
    let p = write(dir, "edited.json", &COSTATE_V2.replace(from, to));
    let o = sim(&[&["replay", "--costate", &p][..], extra].concat());
    (p, o)
}

/// `replay --costate` of `text` (written as `name`) exits 2 saying `needle`.
fn refused_file(name: &str, text: &str, needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), name, text);
    let o = sim(&["replay", "--costate", &p]);
    assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
    assert!(stderr(&o).contains(needle), "{name}: {}", stderr(&o));
}

/// A version-2 file replays in the four standard flights; cut short, of another version or
/// format, with an unknown, short or invalid field, or with checkpoints of version 1 or
/// past the horizon, it is refused with the reason.
#[test]
fn version_2_costate_files_are_read_strictly() {
    let dir = tempfile::tempdir().unwrap();
    let ok = write(dir.path(), "ok.json", COSTATE_V2);
    let o = sim(&["replay", "--costate", &ok]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(digests(&o).len(), 4, "{}", stdout(&o));

    refused_file(
        "truncated.json",
        &COSTATE_V2[..COSTATE_V2.len() / 2],
        "malformed",
    );
    let checkpoint_v1 = "\"alpha\":[0.01,-0.02],\"g\":[0.001,0.0,1,0],";
    for (name, from, to, needle) in [
        (
            "version.json",
            "\"version\":2",
            "\"version\":1",
            "version 1",
        ),
        ("v1-checkpoint.json", checkpoint_v1, "", "malformed"),
        (
            "overlap.json",
            "[0.01,-0.02],\"g\"",
            "[3.2,-0.02],\"g\"",
            "link-overlap",
        ),
        (
            "rotation.json",
            "[0.001,0.0,1,0]",
            "[0.001,0.0,1,0.5]",
            "unit length",
        ),
        (
            "format.json",
            "purcell-costate",
            "other",
            "not a costate file",
        ),
        (
            "extra.json",
            "\"h\":0.01",
            "\"h\":0.01,\"x\":1",
            "malformed",
        ),
        ("beyond.json", "\"k\":100", "\"k\":300", MISPLACED),
        ("short.json", "[0.1,0.2,0.0]", "[0.1,0.2]", "malformed"),
        (
            "step.json",
            "\"h\":0.01",
            "\"h\":-0.01",
            "step h must be finite and positive",
        ),
        (
            "version6.json",
            "\"version\":2",
            "\"version\":6",
            "version 6 (this build reads versions 2, 3, 4 and 5)",
        ),
        (
            "v2-cost.json",
            "\"h\":0.01",
            "\"h\":0.01,\"cost\":\"power\"",
            "version 2 does not have the field \"cost\"",
        ),
        (
            "v2-end.json",
            "\"h\":0.01",
            "\"h\":0.01,\"alpha_end\":[0.5,0]",
            "version 2 does not have the field \"alpha_end\"",
        ),
        // Version 2 knows no joint limit.
        (
            "v2-arcs.json",
            "\"h\":0.01",
            "\"h\":0.01,\"arcs\":[]",
            "version 2 does not have the field \"arcs\"",
        ),
    ] {
        refused_file(name, &COSTATE_V2.replace(from, to), needle);
    }
}

/// Version 3 states its joint limit (`null`: none) and its arcs, both required; an arc of
/// another joint, without its exit's checkpoint, off its limit, without a limit, or with a
/// non-integer sign is refused. The file itself, and one without arcs, replay.
#[test]
fn version_3_costate_files_state_their_joint_limit_and_arcs() {
    for (name, from, to, needle) in [
        (
            "v3-no-limit.json",
            "\"alpha_max\":0.5,",
            "",
            "version 3 needs the field \"alpha_max\"",
        ),
        (
            "v3-no-arcs.json",
            ARC,
            "",
            "version 3 needs the field \"arcs\"",
        ),
        (
            "v3-joint.json",
            "\"joint\":1",
            "\"joint\":0",
            "joint-limit arc must have joint 1 or 2",
        ),
        (
            "v3-exit.json",
            "\"last\":100",
            "\"last\":90",
            "a joint-limit arc's last step has no checkpoint",
        ),
        (
            "v3-off-limit.json",
            "\"alpha_max\":0.5",
            "\"alpha_max\":0.6",
            "not on its limit",
        ),
        (
            "v3-unlimited.json",
            "\"alpha_max\":0.5",
            "\"alpha_max\":null",
            "present with arcs",
        ),
        ("v3-sign.json", "\"sign\":1", "\"sign\":1.0", "malformed"),
    ] {
        refused_file(name, &COSTATE_V3.replace(from, to), needle);
    }
    // The version-3 file itself, and without arcs (`"arcs": []`, `"alpha_max": null`).
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in [
        ("v3.json", COSTATE_V3.to_string()),
        (
            "v3-free.json",
            COSTATE_V2
                .replace("\"version\":2", "\"version\":3")
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
    for (from, to, needle) in [
        (
            "[1,1,1]",
            "[1e39,1,1]",
            "links = 1e39,1.0,1.0 overflows or rounds to zero in f32",
        ),
        (
            "[0.1,0.2,0.0]",
            "[0.1,1e39,0.0]",
            "mu = 0.1,1e39,0.0 overflows",
        ),
        (
            "\"h\":0.01",
            "\"h\":1e-50",
            "step h = 1e-50 overflows or rounds to zero in f32",
        ),
        ("\"k\":100", "\"k\":0", MISPLACED),
        (
            "\"checkpoint_every\":100",
            "\"checkpoint_every\":50",
            MISPLACED,
        ),
        (
            "\"checkpoint_every\":100",
            "\"checkpoint_every\":0",
            MISPLACED,
        ),
    ] {
        refused_file("c.json", &COSTATE_V2.replace(from, to), needle);
    }
    // An f64-only replay of a file beyond f32 range is not refused: it runs, and the law
    // fails at its first step (a μ of 1e39 makes `I − h·B` singular), exit 3.
    let dir = tempfile::tempdir().unwrap();
    let mu = ("[0.1,0.2,0.0]", "[1e-39,1e39,0.0]");
    let (_, o) = replay_edited(dir.path(), mu.0, mu.1, &["--precision", "f64"]);
    assert_exit(&o, 3, "f64 replay with checkpoints failed at step 0");
    assert!(!stderr(&o).contains("f32"), "{}", stderr(&o));
}

/// Issue 9, defect 7: `replay` exited 0 when every replay failed, with the failure only in
/// the JSON. Now exit 3, and stderr names the replay, the step and the reason.
#[test]
fn a_failed_replay_exits_3_naming_the_step_and_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let xi0 = ("\"xi0\":[0.01,-0.02]", "\"xi0\":[50,-0.02]");
    let (p, o) = replay_edited(dir.path(), xi0.0, xi0.1, &["--precision", "f32"]);
    assert_exit(
        &o,
        3,
        "f32 replay with checkpoints failed at step 6 of 200 (t = 0.06 s): joint angle at or \
         past the link-overlap limit",
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
        arg(&json),
    ]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let report: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    assert_eq!(report["replays"][0]["failed_at_step"], 6);
    // Exit 0 only when every replay succeeds.
    let ok = write(dir.path(), "ok.json", COSTATE_V2);
    assert_eq!(sim(&["replay", "--costate", &ok]).status.code(), Some(0));
}

/// Issue 21, defect 5: duplicate keys were accepted (the last one won), and `export` turned
/// such a file into a gait with a fresh checksum.
#[test]
fn duplicate_keys_are_refused() {
    let cases = [
        ("\"version\":2", "\"version\":2,\"version\":3"),
        (
            "\"version\":2",
            "\"format\":\"purcell-costate\",\"version\":2",
        ),
        ("\"xi0\"", "\"mu\":[0.1,0.2,0.0],\"xi0\""),
        ("\"drag\":1", "\"links\":[2,2,2],\"drag\":1"),
        ("\"k\":100", "\"k\":100,\"k\":100"),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (from, to) in cases {
        let text = COSTATE_V2.replace(from, to);
        refused_file("dup.json", &text, "duplicate key");
        let p = write(dir.path(), "dup.json", &text);
        let out = dir.path().join("dup.gait");
        let o = sim(&["export", "--costate", &p, "--out", arg(&out)]);
        assert_eq!(o.status.code(), Some(2), "{text}: {}", stderr(&o));
        assert!(stderr(&o).contains("duplicate key"), "{}", stderr(&o));
        assert!(!out.exists());
    }
}
