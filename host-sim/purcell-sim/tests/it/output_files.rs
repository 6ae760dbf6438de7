//! Issue 24, outputs and inputs: angles in degrees on input (`30deg`), lengths that refuse
//! them; `trajectory.csv`, `sweep.csv` and `replay --trace` with units in their headers,
//! exact times and grid values, the costate path and the arc flags; `report.json` tagged
//! with its format and version. (The JSON Schemas are checked against fresh outputs by
//! `python/tests/test_outputs.py`.)

use crate::common;

use common::fixtures::data;
use common::*;
use std::path::Path;

/// `report.json` of `dir` without its timing.
fn untimed(dir: &Path) -> serde_json::Value {
    let mut r = report(dir);
    r.as_object_mut().unwrap().remove("solve_seconds");
    r
}

/// The rows of a CSV file as fields, the header first.
fn rows(path: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

/// The quick problem solved into `dir/out`; that directory.
fn quick_solve(dir: &Path) -> std::path::PathBuf {
    let out = dir.join("out");
    let o = Solve::quick().no_plots().out(&out).run();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    out
}

/// The header of trajectory.csv and of a trace.
const PATH_HEADER: &str = "k,t_s,alpha1_rad,alpha2_rad,u1_rad_per_s,u2_rad_per_s,x_m,y_m,\
                           theta_rad,xi1_rad_per_s,xi2_rad_per_s,arc1,arc2";

#[test]
fn angle_flags_take_degrees() {
    let tmp = tempfile::tempdir().unwrap();
    let (deg, rad) = (tmp.path().join("deg"), tmp.path().join("rad"));
    let r = |d: f64| f64::to_radians(d).to_string();
    let runs = [
        (
            &deg,
            "0.01,0.01,1deg".to_string(),
            "2deg,-1deg",
            "85deg".to_string(),
        ),
        (
            &rad,
            format!("0.01,0.01,{}", r(1.0)),
            &*format!("{},{}", r(2.0), r(-1.0)),
            r(85.0),
        ),
    ];
    for (out, target, alpha0, alpha_max) in &runs {
        let o = Solve::quick()
            .starts(8)
            .no_plots()
            .target(target)
            .alpha0(alpha0)
            .alpha_max(alpha_max)
            .out(out)
            .run();
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    }
    assert_eq!(untimed(&deg), untimed(&rad));
    let problem = &report(&deg)["problem"];
    assert_eq!(problem["alpha_max"].as_f64(), Some(85f64.to_radians()));
    let connection = |alpha: &str| sim(&["connection", "--alpha", alpha]).stdout;
    assert_eq!(
        connection("30deg,-20deg"),
        connection(&format!("{},{}rad", r(30.0), r(-20.0)))
    );
}

#[test]
fn lengths_refuse_an_angle_unit_and_lists_their_length() {
    for (args, needle) in [
        (
            &["connection", "--alpha", "0,0", "--links", "1,1deg,1"][..],
            "metres",
        ),
        (
            &["solve", "--target", "0.1deg,0,0", "--out", "x"],
            "--target",
        ),
        (&["sweep", "--x", "0:0.1deg:2", "--out", "x"], "--x"),
        (
            &["connection", "--alpha", "0.1"],
            "takes 2 comma-separated numbers (got 1)",
        ),
        (&["connection", "--alpha", "1,tendeg"], "30deg"),
    ] {
        assert_exit(&sim(args), 2, needle);
    }
}

#[test]
fn help_states_the_units_and_defaults_paste_back() {
    let help = stdout(&sim(&["sweep", "--help"]));
    assert!(
        help.contains("[default: 0,0]") && !help.contains("[default: 0 0]"),
        "{help}"
    );
    let help = stdout(&sim(&["solve", "--help"]));
    for needle in [
        "0.1,0.1,30deg",
        "10deg,-5deg",
        "85deg",
        "in metres (no unit suffix)",
    ] {
        assert!(help.contains(needle), "{needle} not in {help}");
    }
}

/// trajectory.csv: the header, `t_s = k·h` as the decimal (`0.3`, not `0.30000000000000004`),
/// the costate path from `ξ^{−1}`, no arc without a limit; report.json tagged; a search of
/// budget 1 counts one start (the zero loop is not one).
#[test]
fn trajectory_csv_has_units_exact_times_and_the_costate() {
    let tmp = tempfile::tempdir().unwrap();
    let out = quick_solve(tmp.path());
    let rows = rows(&out.join("trajectory.csv"));
    assert_eq!(rows[0].join(","), PATH_HEADER);
    assert_eq!(rows.len(), 102);
    assert_eq!(rows[4][1], "0.3");
    for (k, row) in rows[1..].iter().enumerate() {
        assert_eq!(row[0], k.to_string());
        assert_eq!(row[1].parse::<f64>().unwrap(), k as f64 / 10.0, "{row:?}");
        assert_eq!(row[11..], ["0", "0"]);
    }
    let r = report(&out);
    let xi0: Vec<String> = r["xi0"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap().to_string())
        .collect();
    assert_eq!(rows[1][9..11], xi0[..]);
    assert_eq!(r["format"], "purcell-solve-report");
    assert_eq!(r["version"], 1);
    assert_eq!(r["search"]["budget"], 1);
    assert_eq!(r["search"]["starts"], 1);
}

/// sweep.csv: the header, grid values as typed (`0.1`, not `0.09999999999999999`), and in
/// report.json the same values; degrees on theta.
#[test]
fn sweep_csv_keys_are_the_decimals_typed() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let flags = "--x 0:0.3:4 --y 0.05 --theta 0deg:2deg:2 --horizon 10 --step 0.1 --starts 1";
    let mut args: Vec<&str> = ["sweep", "--no-plots", "--out", arg(&out)].into();
    args.extend(flags.split(' '));
    let o = sim(&args);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let rows = rows(&out.join("sweep.csv"));
    assert_eq!(
        rows[0].join(","),
        "x_m,y_m,theta_rad,cost_rad2_per_s,residual,max_abs_alpha_rad,admissible,local_min,\
         kkt_residual_rad_per_s,status"
    );
    let xs: Vec<&str> = rows[1..].iter().step_by(2).map(|r| r[0].as_str()).collect();
    assert_eq!(xs, ["0", "0.1", "0.2", "0.3"]);
    assert_eq!(rows[2][2], 2f64.to_radians().to_string());
    let r = report(&out);
    assert_eq!(r["format"], "purcell-sweep-report");
    assert_eq!(r["version"], 1);
    assert_eq!(r["axes"]["x"], serde_json::json!([0.0, 0.1, 0.2, 0.3]));
}

/// `replay --trace`: the path of the replay selected, trajectory.csv's columns, numbers in
/// the replay's type, the arcs of the file flagged on their states.
#[test]
fn replay_trace_writes_the_path_as_replayed() {
    let tmp = tempfile::tempdir().unwrap();
    let costate = data("tiny-limit.costate.json");
    let file: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&costate).unwrap()).unwrap();
    let trace = tmp.path().join("trace.csv");
    let o = sim(&[
        "replay",
        "--costate",
        arg(&costate),
        "--precision",
        "f32",
        "--trace",
        arg(&trace),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let rows = rows(&trace);
    assert_eq!(rows[0].join(","), PATH_HEADER);
    assert_eq!(rows.len(), file["steps"].as_u64().unwrap() as usize + 2);
    for (k, row) in rows[1..].iter().enumerate() {
        assert_eq!(row[1].parse::<f64>().unwrap(), k as f64 / 100.0, "{row:?}");
        // f32 numbers in f32's shortest form.
        for v in &row[2..11] {
            assert_eq!(v.parse::<f32>().unwrap().to_string(), *v, "{row:?}");
        }
        let mut on = [0i64; 2];
        for a in file["arcs"].as_array().unwrap() {
            let (first, last) = (a["first"].as_u64().unwrap(), a["last"].as_u64().unwrap());
            if (first..=last).contains(&(k as u64)) {
                on[a["joint"].as_u64().unwrap() as usize - 1] = a["sign"].as_i64().unwrap();
            }
        }
        assert_eq!(row[11..], [on[0].to_string(), on[1].to_string()], "{row:?}");
    }
    assert!(rows.iter().any(|r| r[11] != "0") && rows.iter().any(|r| r[12] != "0"));
}

/// The f64 trace of a solve's costate file follows its trajectory.csv: the same keys and
/// arcs, the states within the law's rounding (MODEL.md §5: the core's law reproduces the
/// solver's controls to about 1e-6 on this coarse grid; a column off by a row is off by
/// 1e-3).
#[test]
fn an_f64_trace_follows_the_trajectory() {
    let tmp = tempfile::tempdir().unwrap();
    let out = quick_solve(tmp.path());
    let trace = tmp.path().join("trace.csv");
    let costate = out.join("costate.json");
    let o = sim(&["replay", "--costate", arg(&costate), "--trace", arg(&trace)]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let (solved, replayed) = (rows(&out.join("trajectory.csv")), rows(&trace));
    assert_eq!(solved.len(), replayed.len());
    for (s, r) in solved.iter().zip(&replayed).skip(1) {
        assert_eq!((&s[..2], &s[11..]), (&r[..2], &r[11..]));
        for (a, b) in s[2..11].iter().zip(&r[2..11]) {
            let (a, b) = (a.parse::<f64>().unwrap(), b.parse::<f64>().unwrap());
            assert!((a - b).abs() <= 1e-5, "{s:?} {r:?}");
        }
    }
}

/// The trace is written only where nothing would be lost: never over an existing file
/// without --force, never over an input or --out even with it.
#[test]
fn replay_trace_never_overwrites() {
    let tmp = tempfile::tempdir().unwrap();
    let costate = data("tiny.costate.json");
    let existing = write(tmp.path(), "mine.csv", "my data\n");
    let replay = |trace: &str, extra: &[&str]| {
        let mut args = vec!["replay", "--costate", arg(&costate), "--trace", trace];
        args.extend(extra);
        sim(&args)
    };
    assert_exit(&replay(&existing, &[]), 2, "--force");
    assert_eq!(std::fs::read_to_string(&existing).unwrap(), "my data\n");
    assert_exit(&replay(arg(&costate), &["--force"]), 2, "input");
    let report = tmp.path().join("report.json");
    let both = replay(arg(&report), &["--out", arg(&report), "--force"]);
    assert_exit(&both, 2, "the same file");
    assert!(!report.exists());
    let o = replay(&existing, &["--force"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        std::fs::read_to_string(&existing)
            .unwrap()
            .starts_with("k,t_s,")
    );
}
