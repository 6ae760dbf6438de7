//! The `purcell-sim` command line: bad input and limits refused before any work, number
//! flags and their defaults, help, exit codes, connection, closed stdout. (No solution:
//! `exit3.rs`; costate files: `costate_files.rs`; gait files: `gait_files.rs`; outputs:
//! `outputs.rs`; random inputs: `cli_props.rs`.)

use crate::common;

use common::*;
use std::path::Path;
use std::process::{Output, Stdio};
use std::time::{Duration, Instant};

/// `solve` of the paper's problem with `extra` flags exits 2 saying `needle`, at once and
/// writing nothing.
fn refused_before_work(extra: &[&str], needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let t0 = Instant::now();
    let o = Solve::paper().out(&out).with(extra).run();
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
    assert_exit(&o, 2, blame);
    assert!(!stderr(&o).contains("I - h"), "{}", stderr(&o));
    refused_before_work(&["--links", "1e39,1,1"], "in f32");
    refused_before_work(&["--step", "1e-50", "--horizon", "1e-48"], "in f32");
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
            arg(&out),
        ]);
        assert_exit(&o, 2, "step h must be positive");
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
    let out = arg(&out);
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
    use purcell_sim::spec::{MAX_SOLVE_STEPS, MAX_STARTS, MAX_SWEEP_TARGETS};
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
            grouped(u64::from(purcell_sim::spec::MAX_CHECKPOINTS))
        ),
        format!(
            "`replay`, `export`, `robustness` and `field` ≤ {} steps",
            grouped(purcell_solver::problem::MAX_STEPS)
        ),
        format!("a nonzero target ≥ {:e}", purcell_sim::spec::MIN_TARGET),
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
        grouped(u64::from(purcell_sim::spec::MAX_CHECKPOINTS)),
        grouped(purcell_solver::problem::MAX_STEPS),
        grouped(MAX_SWEEP_TARGETS as u64),
    ]);
    // 1e-6: its digits.
    let min_target = format!("{:e}", purcell_sim::spec::MIN_TARGET);
    known.extend(
        min_target
            .split(|c: char| !c.is_ascii_digit())
            .filter(|s| !s.is_empty())
            .map(String::from),
    );
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
    let o = Solve::quick()
        .target(target)
        .no_plots()
        .out(&out)
        .with(extra)
        .run();
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
        let says = format!("--checkpoint-every {every} is not below the horizon's 100 steps");
        assert_exit(&o, 2, &says);
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
/// the shape `0.1,0.2`). It is a usage error now, lists and numbers alike (a list is
/// parsed whole as given, so one of the wrong length says that first).
#[test]
fn a_flag_given_twice_is_refused() {
    for (flags, needle) in [
        (
            &["--alpha", "0.1", "--alpha", "0.2"][..],
            "takes 2 comma-separated numbers (got 1)",
        ),
        (
            &["--alpha", "0.1,0.2", "--alpha", "0.3,0.4"],
            "cannot be used multiple times",
        ),
        (
            &["--alpha", "0.1,0.2", "--links", "1,1,1", "--links", "1,1,1"],
            "cannot be used multiple times",
        ),
        (
            &["--alpha", "0.1,0.2", "--drag", "1", "--drag", "2"],
            "cannot be used multiple times",
        ),
    ] {
        let args = [&["connection"][..], flags].concat();
        assert_exit(&sim(&args), 2, needle);
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
    .args(Solve::quick().no_plots().out(&out).args())
    .stdin(Stdio::null())
    .stdout(Stdio::piped())
    .stderr(Stdio::piped());
    let o = wait(c.spawn().unwrap(), LIMIT, "solve without threads");
    assert_exit(&o, 1, "cannot start worker threads");
    assert!(!out.exists());
}

/// `solve --help` and `sweep --help` state the solver's default budgets of `--starts`.
#[test]
fn the_help_states_the_default_budgets() {
    use purcell_solver::solver::settings::{FREE_STARTS, LIMITED_STARTS};
    let default = format!("[default: {FREE_STARTS}, {LIMITED_STARTS} with --alpha-max]");
    for command in ["solve", "sweep"] {
        let help = String::from_utf8_lossy(&sim(&[command, "--help"]).stdout).into_owned();
        assert!(
            help.contains(&default),
            "{command} --help lacks {default}: {help}"
        );
    }
}
