//! `report.json`'s typed structs (`purcell_sim::report`) keep the key order the files have
//! always had: alphabetical, as when they were written from JSON maps — a solve's report
//! through [`SolveReport::to_json`], which sorts the keys of its flattened parts.

use purcell_sim::replay::ReplayReport;
use purcell_sim::report::*;
use serde::Serialize;

/// Serialised as itself and through a JSON map (whose keys are sorted): the same text
/// when every struct declares its fields in alphabetical order, as the files always had.
fn in_file_order<T: Serialize>(value: &T) {
    let typed = serde_json::to_string_pretty(value).unwrap();
    let mapped = serde_json::to_string_pretty(&serde_json::to_value(value).unwrap()).unwrap();
    assert_eq!(typed, mapped);
}

/// Every object's keys in `text` (pretty JSON, two spaces an indent) are in ascending order.
fn keys_sorted(text: &str) {
    let mut last: Vec<Option<&str>> = Vec::new();
    for line in text.lines() {
        let depth = (line.len() - line.trim_start().len()) / 2;
        last.truncate(depth + 1);
        last.resize(depth + 1, None);
        let body = line.trim_start();
        if let Some(key) = body.strip_prefix('"').and_then(|b| b.split_once("\": ")) {
            let key = key.0;
            if let Some(before) = last[depth] {
                assert!(before < key, "{before:?} before {key:?} in\n{text}");
            }
            last[depth] = Some(key);
        }
        if body.starts_with('}') || body.starts_with('{') {
            last[depth] = None;
        }
    }
}

#[test]
fn reports_keep_the_files_key_order() {
    let arc = ArcReport {
        first: 1,
        joint: 2,
        last: 3,
        sign: -1,
    };
    let certified = CertifiedReport {
        admissible: true,
        arcs: vec![arc],
        cost: 1.0,
        costs: [("effort", 1.0), ("power", 0.5)].into(),
        kkt_residual: Some(1e-12),
        law_residual: None,
        local_min: true,
        max_abs_alpha: 1.5,
        min_eta: Some(0.1),
        mu: [1.0, 2.0, 3.0],
        residual: 1e-14,
        terminal_residual: Some(1e-14),
        xi0: [0.1, 0.2],
    };
    let extremal = ExtremalReport {
        certified: certified.clone(),
        hits: 2,
        newton_iterations: 4,
        start: 5,
        stationarity: 1e-13,
        twin_of: Some(0),
    };
    let minimum = MinimumReport {
        cost: 1.0,
        hits: 3,
        max_abs_alpha: 1.2,
    };
    let unrefined = UnrefinedReport {
        cheaper: true,
        cost: 0.9,
        defect: None,
        hits: 1,
        max_abs_alpha: 2.0,
    };
    let replay = ReplayReport {
        alpha_error: Some(1e-7),
        checkpoints: true,
        digest: Some("0x1".into()),
        failed_at_step: None,
        failure: None,
        final_state_bits: Some(vec!["0x2".into()]),
        g_error: Some(1e-8),
        precision: "f32",
    };
    let report = SolveReport {
        best: certified,
        extremals: vec![extremal],
        flown: None,
        format: REPORT_FORMAT,
        problem: ProblemReport {
            common: SweepProblemReport {
                alpha0: [0.0; 2],
                alpha_end: [0.5, -0.5],
                alpha_max: Some(1.5),
                cost: "power",
                drag: 1.0,
                horizon: 100.0,
                links: [1.0; 3],
                ratio: 2.0,
                step: 0.01,
            },
            steps: 10_000,
            target: [0.1, 0.1, 0.0],
        },
        recentred: false,
        replays: vec![replay],
        returned: 0,
        search: Some(EvidenceReport {
            budget: 512,
            distinct_minima: 1,
            expected_minima: Some(1.0),
            minima: vec![minimum],
            rule_met: true,
            starts: 128,
            unrefined: vec![unrefined],
            unseen_estimate: 0.0,
        }),
        solve_seconds: 1.0,
        version: REPORT_VERSION,
    };
    let text = report.to_json().unwrap();
    keys_sorted(&text);
    let typed = serde_json::to_string_pretty(&report).unwrap();
    assert_ne!(
        text.trim_end(),
        typed,
        "the flattened parts come first when not sorted"
    );
    assert!(std::panic::catch_unwind(|| keys_sorted(&typed)).is_err());
    in_file_order(&SweepReport {
        axes: AxesReport {
            theta: vec![0.0],
            x: vec![0.1],
            y: vec![0.2],
        },
        format: SWEEP_REPORT_FORMAT,
        problem: SweepProblemReport {
            alpha0: [0.0; 2],
            alpha_end: [0.0; 2],
            alpha_max: None,
            cost: "effort",
            drag: 1.0,
            horizon: 10.0,
            links: [1.0; 3],
            ratio: 2.0,
            step: 0.05,
        },
        solved: 1,
        sweep_seconds: 1.0,
        targets: 1,
        version: SWEEP_REPORT_VERSION,
    });
}
