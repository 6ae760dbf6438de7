//! Binary gait files: what `export` writes (the committed test gaits byte for byte), that
//! they replay like their costate files, that the previous versions are still read, and
//! that damaged ones, ones past the step limit and ones beyond `f32` are refused with the
//! reason. (Costate files: `costate_files.rs`.)

use crate::common;

use common::fixtures::{COSTATE_V2, core_data, data};
use common::*;
use purcell_sim::costate_file::CostateFile;
use std::path::Path;
use std::time::{Duration, Instant};

/// `replay` of `flag path` (`--costate` or `--gait`) with `extra` flags.
fn replay(flag: &str, path: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["replay", flag, arg(path)];
    args.extend_from_slice(extra);
    sim(&args)
}

/// `export` writes the binary gait of a costate file; replaying it is replaying the costate
/// file; the committed `tiny-limit` pair (a gait on its joint limit) is what `export` writes
/// today, byte for byte.
#[test]
fn export_writes_the_gait_that_replays_like_its_costate_file() {
    let dir = tempfile::tempdir().unwrap();
    let json = data("tiny-limit.costate.json");
    let gait = dir.path().join("tiny-limit.gait");
    let o = sim(&["export", "--costate", arg(&json), "--out", arg(&gait)]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("684 bytes") && stdout(&o).contains("arcs=2"),
        "{}",
        stdout(&o)
    );
    assert_eq!(
        std::fs::read(&gait).unwrap(),
        std::fs::read(core_data("tiny-limit.gait")).unwrap()
    );

    for precision in ["f32", "f64"] {
        let from_gait = replay("--gait", &gait, &["--precision", precision]);
        let from_json = replay("--costate", &json, &["--precision", precision]);
        assert_eq!(from_gait.status.code(), Some(0), "{}", stderr(&from_gait));
        assert_eq!(digests(&from_gait).len(), 1);
        assert_eq!(stdout(&from_gait), stdout(&from_json));
    }
    // The periodic checkpoints change the f32 flight (the arcs' exits are restored either way).
    let f32_without = replay("--gait", &gait, &["--precision", "f32", "--no-checkpoints"]);
    let f32_with = replay("--gait", &gait, &["--precision", "f32"]);
    assert_ne!(digests(&f32_with), digests(&f32_without));
    let all = digests(&replay("--gait", &gait, &[]));
    assert_eq!(all.len(), 4);
}

/// The previous versions are still read: the version-2 costate file `tiny.costate.json` and
/// the version-1 gait `tiny-v1.gait` exported from it fly the same; exported again, the gait
/// is version 2 and flies the same too.
#[test]
fn previous_versions_are_still_read() {
    let dir = tempfile::tempdir().unwrap();
    let json = data("tiny.costate.json");
    let v1 = core_data("tiny-v1.gait");
    let v2 = dir.path().join("tiny.gait");
    let o = sim(&["export", "--costate", arg(&json), "--out", arg(&v2)]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v2_bytes = std::fs::read(&v2).unwrap();
    assert_eq!(u16::from_le_bytes([v2_bytes[8], v2_bytes[9]]), 2);
    let flown = |flag: &str, path: &Path| {
        let o = replay(flag, path, &[]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        digests(&o)
    };
    let from_json = flown("--costate", &json);
    assert_eq!(from_json.len(), 4);
    assert_eq!(flown("--gait", &v1), from_json);
    assert_eq!(flown("--gait", &v2), from_json);
}

/// A damaged gait file is refused with exit 2 and the reason; `export` of a bad costate file
/// writes nothing.
#[test]
fn corrupted_gaits_are_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read(core_data("tiny-limit.gait")).unwrap();
    let mut flipped = good.clone();
    flipped[250] ^= 4;
    let mut version = good.clone();
    version[8] = 9;
    let cases: [(&str, Vec<u8>, &str); 5] = [
        ("flipped.gait", flipped, "checksum"),
        ("short.gait", good[..good.len() - 1].to_vec(), "length"),
        ("version.gait", version, "version 9"),
        (
            "json.gait",
            COSTATE_V2.as_bytes().to_vec(),
            "not a binary gait file",
        ),
        ("empty.gait", Vec::new(), "not a gait file"),
    ];
    for (name, bytes, needle) in cases {
        let p = dir.path().join(name);
        std::fs::write(&p, bytes).unwrap();
        let o = replay("--gait", &p, &[]);
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{name}: {}", stderr(&o));
        assert!(o.stdout.is_empty());
    }
    let o = replay("--gait", &dir.path().join("missing.gait"), &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));

    let bad = write(
        dir.path(),
        "bad.json",
        &COSTATE_V2.replace("[0.001,0.0,1,0]", "[0.001,0.0,1,0.5]"),
    );
    let out = dir.path().join("bad.gait");
    let o = sim(&["export", "--costate", &bad, "--out", arg(&out)]);
    assert_exit(&o, 2, "unit length");
    assert!(!out.exists());
    let o = sim(&["replay"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

/// [`COSTATE_V2`] as a binary gait file, after `edit`.
fn gait_of(edit: impl FnOnce(&mut CostateFile)) -> Vec<u8> {
    let mut file = CostateFile::parse(COSTATE_V2).unwrap();
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
        let o = replay("--gait", &p, &["--precision", "f64"]);
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
    type Edit = fn(&mut CostateFile);
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
        let mut file = CostateFile::parse(COSTATE_V2).unwrap();
        edit(&mut file);
        let json = write(dir.path(), &format!("{i}.json"), &file.to_json());
        let out = dir.path().join(format!("{i}.gait"));
        let o = sim(&["export", "--costate", &json, "--out", arg(&out)]);
        assert_eq!(o.status.code(), Some(2), "{needle}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{needle}: {}", stderr(&o));
        assert!(stderr(&o).contains("in f32"), "{needle}: {}", stderr(&o));
        assert!(!out.exists(), "{needle}");

        std::fs::write(&out, file.to_gait().unwrap()).unwrap();
        let o = replay("--gait", &out, &[]);
        assert_eq!(o.status.code(), Some(2), "{needle}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{needle}: {}", stderr(&o));
        assert!(stderr(&o).contains("in f32"), "{needle}: {}", stderr(&o));
        let o = replay("--gait", &out, &["--precision", "f64"]);
        assert_eq!(o.status.code(), Some(f64_code), "{needle}: {}", stderr(&o));
    }
}

/// Issue 24: one meaning per flag name, `--costate` a costate file and `--gait` a binary
/// gait file in `replay` and `field` alike (`field --gait` took a costate file, and a gait
/// file there failed on "stream did not contain valid UTF-8"). Each file handed to the
/// other flag is refused naming the right one; `field` draws a gait file as its costate file.
#[test]
fn costate_and_gait_mean_the_same_files_everywhere() {
    let (json, gait) = (
        data("tiny-limit.costate.json"),
        core_data("tiny-limit.gait"),
    );
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("field");
    for (cmd, flag, file, says) in [
        (
            "replay",
            "--costate",
            &gait,
            "a binary gait file (export's output)",
        ),
        (
            "export",
            "--costate",
            &gait,
            "replay, field and export take it as --gait",
        ),
        (
            "replay",
            "--gait",
            &json,
            "a costate file (JSON), not a binary gait file",
        ),
        ("field", "--gait", &json, "pass it as --costate"),
        (
            "field",
            "--costate",
            &gait,
            "a binary gait file (export's output)",
        ),
    ] {
        let o = sim(&[cmd, flag, arg(file), "-o", arg(&out)]);
        assert_exit(&o, 2, says);
        assert!(!out.exists());
    }
    let field = |flag: &str, file: &Path, out: &Path| {
        let o = sim(&["field", flag, arg(file), "-o", arg(out)]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        read_dir(out)
    };
    let from_gait = field("--gait", &gait, &out);
    let from_json = field("--costate", &json, &dir.path().join("json"));
    for name in ["field.csv", "field.svg"] {
        assert!(from_gait[name] == from_json[name], "{name}");
    }
}

/// The bytes of the array a `--format c` source defines.
fn c_array_bytes(c: &str) -> Vec<u8> {
    let (_, body) = c.split_once("] = {").unwrap();
    body.split("0x")
        .skip(1)
        .map(|t| u8::from_str_radix(&t[..2], 16).unwrap())
        .collect()
}

/// `export --format c` writes the gait file's bytes as a C array (`.c`) and its declaration
/// (`.h` beside it), from a costate file or a gait file; its own files are replaced, anything
/// else only with --force; --out must name the `.c` file.
#[test]
fn export_format_c_writes_the_gait_files_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let json = data("tiny-limit.costate.json");
    let gait = dir.path().join("tiny.gait");
    let c = dir.path().join("tiny-limit.c");
    let h = dir.path().join("tiny-limit.h");
    let o = sim(&["export", "--costate", arg(&json), "--out", arg(&gait)]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let bytes = std::fs::read(&gait).unwrap();
    for (flag, input) in [("--costate", &json), ("--gait", &gait)] {
        let o = sim(&[
            "export",
            flag,
            arg(input),
            "--format",
            "c",
            "--out",
            arg(&c),
        ]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        assert!(stdout(&o).contains("684 bytes"), "{}", stdout(&o));
        let source = std::fs::read_to_string(&c).unwrap();
        assert!(source.contains("#include \"tiny-limit.h\"\n"));
        assert!(source.contains("_Alignas(8) const uint8_t tiny_limit[TINY_LIMIT_LEN] = {"));
        assert_eq!(c_array_bytes(&source), bytes);
        let header = std::fs::read_to_string(&h).unwrap();
        assert!(header.contains("#define TINY_LIMIT_LEN 684u\n"), "{header}");
        assert!(header.contains("extern const uint8_t tiny_limit[TINY_LIMIT_LEN];"));
    }
    let to_c = |out: &Path, extra: &[&str]| {
        let args = [
            "export",
            "--gait",
            arg(&gait),
            "--format",
            "c",
            "--out",
            arg(out),
        ];
        sim(&[&args[..], extra].concat())
    };
    std::fs::write(&h, "/* mine */\n").unwrap();
    assert_exit(&to_c(&c, &[]), 2, "--force");
    assert_eq!(std::fs::read(&h).unwrap(), b"/* mine */\n");
    assert_eq!(to_c(&c, &["--force"]).status.code(), Some(0));
    let header = std::fs::read_to_string(&h).unwrap();
    assert!(header.contains("TINY_LIMIT_LEN"));
    let o = to_c(&h, &[]);
    assert_exit(&o, 2, "--out must end in .c");
}

/// The gait-file fuzz target's seed with a tracking table (issue 34): the committed
/// `core/tests/data/tiny-tracking.gait` is what `export --tracking` writes today for
/// [`COSTATE_V2`] cut to 30 steps without checkpoints (2 524 bytes, under the fuzzer's
/// 4 096), and `robustness --digest` flies it.
#[test]
fn the_tracking_seed_is_what_export_writes() {
    let dir = tempfile::tempdir().unwrap();
    let short = dir.path().join("short.gait");
    std::fs::write(
        &short,
        gait_of(|f| {
            f.gait.steps = 30;
            f.gait.checkpoint_every = 0;
            f.checkpoints.clear();
        }),
    )
    .unwrap();
    let out = dir.path().join("tracking.gait");
    let o = sim(&[
        "export",
        "--gait",
        arg(&short),
        "--tracking",
        "--out",
        arg(&out),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let seed = core_data("tiny-tracking.gait");
    assert_eq!(std::fs::read(&out).unwrap(), std::fs::read(&seed).unwrap());
    let o = sim(&["robustness", "--gait", arg(&seed), "--digest"]);
    assert_exit(&o, 0, "");
    assert!(
        stdout(&o).starts_with("closed_digest: 0x"),
        "{}",
        stdout(&o)
    );
}
