//! Property tests of the `purcell-sim` command line on random inputs: every run ends within
//! its time limit, exits with a documented code (0, 2, 3; never a panic or an abort), says
//! why on stderr when it fails, creates nothing when it refuses its input, and never changes
//! a file it did not write.

use crate::common;

use common::fixtures::COSTATE_V3;
use common::*;
use proptest::prelude::*;
use std::time::Duration;

/// Time limit of one random run: generous, but far below "hung".
const RANDOM_LIMIT: Duration = Duration::from_secs(60);

/// A number as a user might type it wrong: huge, tiny, special, garbage, or any `f64`.
fn wild() -> impl Strategy<Value = String> {
    prop_oneof![
        1 => any::<f64>().prop_map(|x| format!("{x:e}")),
        1 => (-4.0..4.0f64).prop_map(|x| format!("{x}")),
        1 => prop::sample::select(vec![
            "0", "-0", "1e39", "-1e39", "1e-39", "1e300", "1e-300", "NaN", "inf", "-inf",
            "3.14159265358979", "-3.1415926536", "1e-50", "", "x", "1,", "--5", "0x10",
        ])
        .prop_map(str::to_string),
    ]
}

/// A plausible number in `[lo, hi)` 24 times out of 25, else a [`wild`] one (so that
/// about half of the runs have every number plausible).
fn value(lo: f64, hi: f64) -> impl Strategy<Value = String> {
    prop_oneof![24 => (lo..hi).prop_map(|x| format!("{x}")), 1 => wild()]
}

/// `n` comma-separated [`value`]s, one too few or too many one time in 25.
fn values(n: usize, lo: f64, hi: f64) -> impl Strategy<Value = String> {
    prop_oneof![
        24 => Just(n),
        1 => prop::sample::select(vec![n - 1, n + 1]),
    ]
    .prop_flat_map(move |n| prop::collection::vec(value(lo, hi), n))
    .prop_map(|v| v.join(","))
}

/// Checks the exit-code contract of one run; `created` says whether an output appeared.
fn contract(o: &std::process::Output, created: bool) -> Result<(), TestCaseError> {
    let e = stderr(o);
    let code = o.status.code();
    prop_assert!(matches!(code, Some(0 | 2 | 3)), "exit {code:?}, stderr {e}");
    prop_assert!(
        !e.contains("panicked") && !e.contains("RUST_BACKTRACE"),
        "{e}"
    );
    if code != Some(0) {
        // After the phase lines of work begun (issue 36), the error says why.
        prop_assert!(
            e.lines().any(|l| l.starts_with("error")),
            "no message: {e:?}"
        );
    }
    if code == Some(2) {
        prop_assert!(!created, "refused, yet the output exists: {e}");
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 48,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// `connection` on any shape and model.
    #[test]
    fn connection_on_random_input(alpha in values(2, -3.2, 3.2), links in values(3, 0.01, 10.0),
                                  ratio in value(0.1, 10.0), equals in any::<bool>()) {
        let (a, l, r) = if equals {
            (format!("--alpha={alpha}"), format!("--links={links}"), format!("--ratio={ratio}"))
        } else {
            (alpha, links, ratio)
        };
        let o = if equals {
            sim_in(None, &["connection", &a, &l, &r], RANDOM_LIMIT)
        } else {
            sim_in(None, &["connection", "--alpha", &a, "--links", &l, "--ratio", &r],
                   RANDOM_LIMIT)
        };
        contract(&o, false)?;
        if o.status.success() {
            let v: serde_json::Value = serde_json::from_slice(&o.stdout)
                .map_err(|e| TestCaseError::fail(e.to_string()))?;
            prop_assert!(v["A"][2][1].as_f64().is_some_and(f64::is_finite));
        }
    }

    /// `solve` on random problems (small horizons so that valid ones solve quickly; seed 0
    /// and at most 8 starts: the built-in starts), into a missing directory or one that
    /// holds a file of somebody else's, with or without `--force` (which replaces it, and only
    /// on success).
    #[test]
    fn solve_on_random_input(
        target in values(3, -0.02, 0.02), alpha0 in values(2, -1.0, 1.0),
        links in values(3, 0.5, 2.0),
        horizon in prop_oneof![12 => Just("5".to_string()), 12 => Just("10".to_string()), 1 => wild()],
        step in prop_oneof![12 => Just("0.1".to_string()), 12 => Just("0.05".to_string()), 1 => wild()],
        alpha_max in value(1.5, 3.2),
        starts in prop_oneof![12 => 1usize..=2, 1 => Just(0)],
        occupied in prop::bool::weighted(0.25),
        force in any::<bool>(),
    ) {
        let tmp = tempfile::tempdir().unwrap();
        let out = tmp.path().join("out");
        if occupied {
            std::fs::create_dir(&out).unwrap();
            std::fs::write(out.join("mine.txt"), "precious").unwrap();
        }
        let solve = Solve::paper().out(&out).no_plots()
            .target(&target).alpha0(&alpha0).flag("links", &links)
            .horizon(&horizon).step(&step).alpha_max(&alpha_max)
            .starts(starts);
        let o = if force { solve.force() } else { solve }.run_within(RANDOM_LIMIT);
        let replaced = o.status.code() == Some(0) && occupied && force;
        contract(&o, !occupied && out.exists())?;
        if occupied && !replaced {
            // Refused (without --force) or failed: somebody else's file is untouched.
            prop_assert_eq!(std::fs::read(out.join("mine.txt")).unwrap(), b"precious");
            prop_assert_eq!(std::fs::read_dir(&out).unwrap().count(), 1);
        }
        if occupied && !force {
            prop_assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        }
        if o.status.code() == Some(0) {
            // With --force the result replaced the directory, somebody else's file included.
            prop_assert!(out.join("purcell-sim-manifest.json").exists());
            prop_assert_eq!(out.join("mine.txt").exists(), false);
            let c = out.join("costate.json");
            let r = sim_in(None, &["replay", "--costate", arg(&c)], RANDOM_LIMIT);
            contract(&r, false)?;
            // A solved problem is valid in f32 (solve checks it), so its replay is not
            // refused: it lands (0) or a replay misses (3, say which).
            prop_assert!(matches!(r.status.code(), Some(0 | 3)), "{}", stderr(&r));
        } else {
            // Only the directory it was given (or nothing) is left.
            prop_assert_eq!(std::fs::read_dir(tmp.path()).unwrap().count(), usize::from(occupied));
        }
    }

    /// `replay` on a valid costate file with one number replaced by a random one.
    #[test]
    fn replay_on_random_costate_files(field in 0usize..23, value in wild()) {
        let numbers = [
            ("[1,1,1]", "links"), ("\"drag\":1", "drag"), ("\"ratio\":2", "ratio"),
            ("\"h\":0.01", "h"), ("\"steps\":200", "steps"), ("[0,0]", "alpha0"),
            ("[0.1,0.1,0]", "target"), ("[0.1,0.2,0.0]", "mu"), ("\"xi0\":[0.01,-0.02]", "xi0"),
            ("\"checkpoint_every\":100", "every"), ("\"k\":100", "k"),
            ("\"alpha\":[0.5,-0.02]", "cp alpha"), ("[0.001,0.0,1,0]", "cp g"),
            ("\"xi\":[0.01,-0.02]", "cp xi"), ("\"version\":3", "version"),
            ("0.001,0.0,1,0]", "cp x"), ("\"ratio\":2}", "ratio end"), ("-0.02]}]}", "cp xi end"),
            ("\"alpha_max\":0.5", "alpha_max"), ("\"joint\":1", "joint"), ("\"sign\":1", "sign"),
            ("\"first\":90", "first"), ("\"last\":100", "last"),
        ];
        let (pattern, _) = numbers[field];
        // Replace the first number inside the pattern.
        let start = pattern.find(|c: char| c == '-' || c.is_ascii_digit()).unwrap();
        let end = pattern[start..]
            .find(|c: char| !(c == '-' || c == '.' || c == 'e' || c.is_ascii_digit()))
            .map_or(pattern.len(), |e| start + e);
        let mutated = format!("{}{}{}", &pattern[..start], value, &pattern[end..]);
        let text = COSTATE_V3.replacen(pattern, &mutated, 1);
        let tmp = tempfile::tempdir().unwrap();
        let c = tmp.path().join("c.json");
        std::fs::write(&c, &text).unwrap();
        let report = tmp.path().join("r.json");
        let o = sim_in(None, &["replay", "--costate", arg(&c), "--out", arg(&report)],
                       RANDOM_LIMIT);
        contract(&o, report.exists())?;
        prop_assert_eq!(std::fs::read_to_string(&c).unwrap(), text);
        if o.status.code() == Some(3) {
            prop_assert!(stderr(&o).contains("replay"), "{}", stderr(&o));
        }
    }
}
