//! Issue 24, the command-line conventions: `solve` and `sweep` print a summary (`--json`
//! their report, `-q` nothing), `-o` for `--out`, `-j N` threads, the exit codes in every
//! `--help`, shell completions, the manual page, `--version` with the commit.

use crate::common;

use common::*;
use std::path::Path;

/// `report.json` of `dir` without its timing.
fn untimed(dir: &Path) -> serde_json::Value {
    let mut r = report(dir);
    r.as_object_mut().unwrap().remove("solve_seconds");
    r
}

/// The quick problem with three batches of starts, so that `-j` has threads to use.
fn searched() -> Solve {
    Solve::quick().starts(70).no_plots()
}

#[test]
fn solve_prints_a_summary_with_the_cost_and_the_output_directory() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = Solve::quick().out(&out).run();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = stdout(&o);
    let cost = report(&out)["cost"].as_f64().unwrap();
    assert!(text.contains(&format!("J = {cost:.7}")), "{text}");
    assert!(text.contains(&format!("{}/", out.display())), "{text}");
    for (line, name) in text
        .lines()
        .zip(["cost", "arcs", "residuals", "search", "time", "wrote"])
    {
        assert!(line.starts_with(name), "{name} not in {text}");
    }
    assert!(text.lines().count() <= 8, "{text}");
}

/// `--json` prints the report exactly as written (what stdout held before the summary).
#[test]
fn json_prints_the_report_as_written() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = Solve::quick().no_plots().out(&out).with(&["--json"]).run();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(o.stdout, std::fs::read(out.join("report.json")).unwrap());
    let mut printed: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    printed.as_object_mut().unwrap().remove("solve_seconds");
    assert_eq!(printed, untimed(&out));
}

/// Issue 36: on a stderr that is no terminal (a CI log), `solve` says each phase as it begins,
/// with the seconds since the command began, and when it is done; the summary's time line is
/// the command's, the solver's part beside it.
#[test]
fn a_solve_tells_its_phases_on_a_log() {
    let tmp = tempfile::tempdir().unwrap();
    let o = Solve::quick().no_plots().out(&tmp.path().join("out")).run();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let phases: Vec<String> = stderr(&o)
        .lines()
        .filter_map(|l| {
            let (seconds, what) = l.trim_start().split_once(" s  ")?;
            seconds.parse::<f64>().ok()?;
            Some(what.split(',').next().unwrap_or(what).to_string())
        })
        .collect();
    assert_eq!(
        phases,
        ["search", "refinement", "output", "done"],
        "{}",
        stderr(&o)
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    let time = stdout.lines().find(|l| l.starts_with("time ")).unwrap();
    assert!(time.ends_with(" s solving)"), "{time}");
}

/// `-q`: nothing on stdout or stderr (not even the warning of a search that spent its budget
/// of one start), the files written all the same; errors are still said.
#[test]
fn quiet_prints_nothing_but_errors() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let loud = Solve::quick().no_plots().out(&out).run();
    assert!(stderr(&loud).contains("warning: the search used its budget"));
    let o = Solve::quick()
        .no_plots()
        .force()
        .out(&out)
        .with(&["-q"])
        .run();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(o.stdout.is_empty() && o.stderr.is_empty(), "{}", stderr(&o));
    assert!(out.join("report.json").exists());
    let o = sim(&["-q", "solve", "--starts", "0", "-o", arg(&out)]);
    assert_exit(&o, 2, "--starts must be 1 to");
    assert!(o.stdout.is_empty());
}

#[test]
fn short_o_is_out() {
    let tmp = tempfile::tempdir().unwrap();
    let (long, short) = (tmp.path().join("long"), tmp.path().join("short"));
    let o = Solve::quick().no_plots().out(&long).run();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let o = Solve::quick().no_plots().with(&["-o", arg(&short)]).run();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(untimed(&short), untimed(&long));
    let gait = tmp.path().join("paper.gait");
    let costate = arg(&long.join("costate.json")).to_string();
    let o = sim(&["export", "--costate", &costate, "-o", arg(&gait)]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(gait.exists());
}

/// One worker thread or one per core: the same files, bit for bit (the report but its time).
#[test]
fn one_thread_gives_the_same_result() {
    let tmp = tempfile::tempdir().unwrap();
    let (all, one) = (tmp.path().join("all"), tmp.path().join("one"));
    let o = searched().out(&all).run();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let o = searched().out(&one).with(&["-j", "1"]).run();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(untimed(&one), untimed(&all));
    for name in ["trajectory.csv", "costate.json"] {
        assert!(std::fs::read(one.join(name)).unwrap() == std::fs::read(all.join(name)).unwrap());
    }
    for zero in [&["-j", "0"][..], &["--threads", "0"]] {
        let o = sim(&[zero, &["solve", "-o", arg(&one)]].concat());
        assert_exit(&o, 2, "0 is not in 1..=");
    }
}

#[test]
fn sweep_prints_a_summary_or_its_report() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("sweep");
    let sweep = |extra: &[&str]| {
        let base = [
            "sweep",
            "--x",
            "0.01",
            "--y",
            "0.01",
            "--horizon",
            "10",
            "--step",
            "0.1",
        ];
        let o = sim(&[
            &base[..],
            &["--starts", "1", "--no-plots", "--force", "-o", arg(&out)],
            extra,
        ]
        .concat());
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        o
    };
    let text = stdout(&sweep(&[]));
    assert!(
        text.contains("targets    1 (1 x, 1 y, 1 theta), 1 solved"),
        "{text}"
    );
    assert!(
        text.contains(&format!("{}/ (sweep.csv, report.json)", out.display())),
        "{text}"
    );
    assert_eq!(
        sweep(&["--json"]).stdout,
        std::fs::read(out.join("report.json")).unwrap()
    );
    assert!(sweep(&["-q"]).stdout.is_empty());
}

/// The exit codes, one list (`purcell_sim::cli::EXIT_CODES`), after every command's help,
/// and the same codes as the README's table.
#[test]
fn every_help_lists_the_exit_codes() {
    let codes = purcell_sim::cli::EXIT_CODES;
    let mut helps = vec![stdout(&sim(&["--help"]))];
    for c in [
        "solve",
        "replay",
        "export",
        "connection",
        "sweep",
        "field",
        "robustness",
        "completions",
        "man",
    ] {
        helps.push(stdout(&sim(&[c, "--help"])));
    }
    for help in helps {
        assert!(help.trim_end().ends_with(codes), "{help}");
    }
    let readme =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../README.md"))
            .unwrap();
    let section = readme
        .split("\n## ")
        .find(|s| s.starts_with("Exit codes"))
        .expect("README has a section on exit codes");
    let mut table: Vec<&str> = section
        .lines()
        .filter_map(|l| l.strip_prefix("| ")?.split(' ').next())
        .filter(|c| !c.is_empty() && c.chars().all(|c| c.is_ascii_digit()))
        .collect();
    let mut listed: Vec<&str> = codes
        .lines()
        .skip(1)
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    table.sort_unstable();
    listed.sort_unstable();
    assert_eq!(table, listed);
}

#[test]
fn completions_and_the_manual_page() {
    let o = sim(&["completions", "bash"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let script = stdout(&o);
    assert!(
        script.contains("purcell-sim") && script.contains("solve"),
        "{script}"
    );
    assert!(script.contains("--alpha-max"), "{script}");
    assert_exit(&sim(&["completions", "tcsh"]), 2, "invalid value");
    let page = stdout(&sim(&["man"]));
    assert!(page.contains(".TH purcell-sim 1"), "{page}");
    let page = stdout(&sim(&["man", "solve"]));
    assert!(
        page.contains(".TH purcell-sim-solve 1") && page.contains("alpha\\-max"),
        "{page}"
    );
    assert_exit(&sim(&["man", "nope"]), 2, "no command \"nope\"");
}

/// `--version`: the package's version, and the commit when built in a git checkout.
#[test]
fn version_names_the_package_version() {
    let o = sim(&["--version"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = stdout(&o);
    let expected = format!("purcell-sim {}", env!("CARGO_PKG_VERSION"));
    assert!(text.starts_with(&expected), "{text}");
    assert!(text.contains(purcell_sim::cli::VERSION), "{text}");
}
