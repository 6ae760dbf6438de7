//! The "no solution" paths: `solve` exits 3 and writes nothing when no start reaches the
//! target or none of the coarse search's extremals can be carried to the problem's grid
//! (`NotRefined`); when every extremal found is inadmissible (`NoneAdmissible`) it solves
//! within a margin of the links' overlap instead; `sweep` reports each target it cannot
//! solve in its CSV and still exits 0.

use crate::common;

use common::*;

/// Runs `solve` into a missing `new/parents/out`: exit 3 with an error message after the
/// phase lines of the work done, nothing on stdout, nothing written (no output, no staging
/// directory, not even the parents it created); the error it said on stderr.
fn no_solution(solve: Solve) -> String {
    let tmp = tempfile::tempdir().unwrap();
    let o = solve.out(&tmp.path().join("new/parents/out")).run();
    let all = stderr(&o);
    assert_eq!(o.status.code(), Some(3), "{all}");
    let e = match all.find("error: ") {
        Some(i) if i == 0 || all[..i].ends_with('\n') => all[i..].to_string(),
        _ => panic!("no error line: {all}"),
    };
    assert!(o.stdout.is_empty());
    assert_eq!(std::fs::read_dir(tmp.path()).unwrap().count(), 0);
    e
}

/// A target 40 m away in 10 s: no start reaches it; the message names the best residual.
#[test]
fn unreachable_target_exits_3_with_best_residual_and_no_output() {
    let e = no_solution(Solve::paper().target("40,0,0").horizon("10").starts(2));
    assert!(e.contains("best residual"), "{e}");
    // Issue 24: and what to try.
    assert!(
        e.contains("\ntry more starts (--starts 8; 2 now), another --seed (0 now)"),
        "{e}"
    );
    assert!(
        e.contains("or a warm start") && e.contains("(--from DIR/costate.json)"),
        "{e}"
    );
}

/// Exit 3's advice never asks for more starts than the family holds (1 128 loops without a
/// joint limit): up to it from 600, none from it.
#[test]
fn exit_3_advises_no_more_starts_than_the_family_holds() {
    let e = no_solution(Solve::paper().target("40,0,0").horizon("10").starts(600));
    assert!(e.contains("more starts (--starts 1128; 600 now)"), "{e}");
    let e = no_solution(Solve::paper().target("40,0,0").horizon("10").starts(1128));
    assert!(!e.contains("more starts"), "{e}");
}

/// `ḡ = (0.15, 0.25, −0.6)` on the paper's grid: every extremal the search finds swings a
/// joint past the links' overlap (`|α_i| ≥ π`), so none is admissible (it exited 3); `solve`
/// then returns the cheapest gait within 0.1 rad of the overlap (the problem with
/// `--alpha-max π − 0.1`, as its report says) and says so. About 10 CPU-s.
#[test]
fn solve_falls_back_to_a_margin_of_the_overlap_when_no_extremal_is_admissible() {
    let tmp = tempfile::tempdir().unwrap();
    let o = Solve::paper()
        .target("0.15,0.25,-0.6")
        .no_plots()
        .out(tmp.path())
        .run();
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(0), "{e}");
    assert!(e.contains("none admissible"), "{e}");
    assert!(
        e.contains("no gait found inside the links' overlap; solving for the cheapest within 0.1 rad of it (--alpha-max 3.0416)"),
        "{e}"
    );
    let r = report(tmp.path());
    let bound = std::f64::consts::PI - 0.1;
    assert_eq!(r["problem"]["alpha_max"].as_f64(), Some(bound));
    let reach = r["max_abs_alpha"].as_f64().unwrap();
    assert!(reach <= bound * (1.0 + 1e-12), "{reach}");
}

/// A tiny target, `ḡ = (1e-5, 0, 0)` within `|α_i| ≤ 1` in 20 s (16 starts): the coarse
/// search files extremals (points of one flat valley, the small loop's orientation about
/// `ᾱ`), but on the finer grids stationarity stalls at 1e-6–1e-5 and none is carried to the
/// problem's grid (issue 33); the message says so. The case before, `(0.02, 0.02, 0)` within 0.62, solves since a
/// start's barrier path is its own (with 24 starts or more). Should the refinement carry this
/// one too, the test needs another case: it guards the exit path, not the failure.
#[test]
fn solve_exits_3_when_no_extremal_is_carried_to_the_problems_grid() {
    let e = no_solution(
        Solve::paper()
            .target("1e-5,0,0")
            .horizon("20")
            .step("0.02")
            .alpha_max("1")
            .starts(16)
            .no_plots(),
    );
    assert!(
        e.contains("extremal(s) of the coarse search, none carried to the problem's grid"),
        "{e}"
    );
    assert!(e.contains("smallest terminal defect"), "{e}");
    // The cause: the defect was met, stationarity stalled (the defect alone said 4e-18).
    assert!(
        e.contains("Newton met the terminal defect there but its stationarity stalled at"),
        "{e}"
    );
    // Without the limit it is not solved either (issue 33): no looser limit is advised, and
    // the message says why none is certified.
    assert!(!e.contains("--alpha-max"), "{e}");
    assert!(
        e.contains(
            "\nwithout the joint limit no gait is found either: a looser one would not help"
        ),
        "{e}"
    );
    assert!(
        e.contains("\nthe extremals found meet the target but none is certified stationary: seen on tiny targets"),
        "{e}"
    );
}

/// `ḡ = (0.02, 0.02, 0)` in 10 s within `|α_i| ≤ 0.3` (32 starts): no start reaches it; the
/// same problem without the limit solves (J = 0.8319134, largest `|α_i|` 1.2961), so exit 3
/// names the limit that admits that gait, and that limit solves, to the same gait (issue 33).
#[test]
fn exit_3_under_a_limit_names_one_that_admits_the_gait_without_it() {
    let problem = || {
        Solve::paper()
            .target("0.02,0.02,0")
            .horizon("10")
            .step("0.1")
            .starts(32)
            .no_plots()
    };
    let e = no_solution(problem().alpha_max("0.3"));
    assert!(e.contains("no start reached the target"), "{e}");
    assert!(
        e.contains("or a looser joint limit (--alpha-max 1.31, which admits the gait found without one; 0.3 now; tighter ones may solve too)"),
        "{e}"
    );
    let tmp = tempfile::tempdir().unwrap();
    let o = problem().alpha_max("1.31").out(tmp.path()).run();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let cost = report(tmp.path())["cost"].as_f64().unwrap();
    assert!((cost - 0.8319134).abs() <= 1e-6, "{cost}");
}

/// Isotropic drag (`--ratio 1`): the swimmer cannot move, so no target of the lattice is
/// reached; `sweep` still writes its CSV (one row per target, no numbers, the reason in
/// `status`) and a report with `"solved": 0`, and exits 0.
#[test]
fn sweep_reports_unreachable_targets_and_exits_0() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = sim(&[
        "sweep",
        "--ratio",
        "1",
        "--x",
        "0.05:0.1:2",
        "--y",
        "0",
        "--horizon",
        "10",
        "--step",
        "0.1",
        "--starts",
        "4",
        "--no-plots",
        "--out",
        arg(&out),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len(), 2, "{csv}");
    for (row, x) in rows.iter().zip(["0.05", "0.1"]) {
        assert!(
            row.starts_with(&format!("{x},0,0,,,,,,,\"no start reached the target")),
            "{row}"
        );
    }
    let report = report(&out);
    assert_eq!(report["solved"], 0);
    assert_eq!(report["targets"], 2);
}
