//! `report.json`'s typed structs (`purcell_sim::report`) keep the key order the files have
//! always had: alphabetical, as when they were written from JSON maps.

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

#[test]
fn reports_keep_the_files_key_order() {
    let arc = ArcReport {
        first: 1,
        joint: 2,
        last: 3,
        sign: -1,
    };
    let extremal = ExtremalReport {
        admissible: true,
        arcs: vec![arc.clone()],
        cost: 1.0,
        costs: [("effort", 1.0), ("power", 0.5)].into(),
        hits: 2,
        kkt_residual: Some(1e-12),
        law_residual: None,
        local_min: true,
        max_abs_alpha: 1.5,
        min_eta: Some(0.1),
        mu: [1.0, 2.0, 3.0],
        newton_iterations: 4,
        residual: 1e-14,
        start: 5,
        stationarity: 1e-13,
        terminal_residual: Some(1e-14),
        twin_of: Some(0),
        xi0: [0.1, 0.2],
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
        admissible: true,
        arcs: vec![arc],
        cost: 1.0,
        costs: [("power", 0.5), ("effort", 1.0)].into(),
        extremals: vec![extremal],
        format: REPORT_FORMAT,
        kkt_residual: None,
        law_residual: Some(1e-13),
        local_min: true,
        max_abs_alpha: 1.5,
        min_eta: None,
        mu: [1.0, 2.0, 3.0],
        problem: ProblemReport {
            common: SweepProblemReport {
                alpha0: [0.0; 2],
                alpha_end: [0.5, -0.5],
                alpha_max: Some(1.5),
                drag: 1.0,
                horizon: 100.0,
                links: [1.0; 3],
                ratio: 2.0,
                step: 0.01,
            },
            steps: 10_000,
            target: [0.1, 0.1, 0.0],
        },
        replays: vec![replay],
        residual: 1e-14,
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
        terminal_residual: Some(1e-14),
        version: REPORT_VERSION,
        xi0: [0.1, 0.2],
    };
    in_file_order(&report);
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
