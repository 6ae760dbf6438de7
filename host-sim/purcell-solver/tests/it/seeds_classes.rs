//! Seeds 0–7 of the global search agree on new problems of each class of issue 33: other
//! swimmers (drag ratio, unequal links), far and turning targets and bent starts, a joint
//! limit. For each problem, every seed's cheapest admissible coarse minimum runs the same
//! shape path and costs within the coarse grid's error ([`COARSE_COST_ERROR`], with a limit
//! [`LIMITED_COARSE_COST_ERROR`]) of the cheapest gait on the problem's grid, which
//! `purcell-sim solve --seed S` returned for every seed 0–7 (the costs below, the command in
//! each problem's note; docs/MEASUREMENTS.md). The refinement that follows the search is
//! deterministic, so the same coarse minimum gives the same gait.

use purcell_solver::problem::{Problem, Spec};
use purcell_solver::solver::settings::{
    COARSE_COST_ERROR, FREE_STARTS, LIMITED_COARSE_COST_ERROR, LIMITED_STARTS,
};
use purcell_solver::solver::{SolveOptions, solve};
use purcell_solver::testkit::seeds_agree;

/// Seeds 0–7 agree on `spec` ([`seeds_agree`]), whose cost on its own grid is `cheapest`.
fn every_seed_agrees(name: &str, spec: Spec, cheapest: f64) {
    let error = match spec.alpha_max {
        None => COARSE_COST_ERROR,
        Some(_) => LIMITED_COARSE_COST_ERROR,
    };
    // Under a joint limit every seed runs the same starts (limited.rs): two suffice.
    let seeds = if spec.alpha_max.is_some() { 0..2 } else { 0..8 };
    seeds_agree(name, &Problem::new(&spec).unwrap(), seeds, cheapest, error);
}

/// Other swimmers: drag ratios 1.5 and 2.5, unequal links.
#[test]
fn other_swimmers() {
    // `solve --ratio 1.5`: 0.7491627 for seeds 0–7.
    let ratio = Spec {
        ratio: 1.5,
        ..Spec::default()
    };
    every_seed_agrees("ratio 1.5", ratio, 0.7491627);
    // `solve --links 1,0.8,1.2 --target 0.1,0.05,0.2`: 0.2534228 for seeds 0–7.
    let links = Spec {
        links: [1.0, 0.8, 1.2],
        target: [0.1, 0.05, 0.2],
        ..Spec::default()
    };
    every_seed_agrees("links 1, 0.8, 1.2", links, 0.2534228);
    // `solve --ratio 2.5 --target 0.05,0,0.5`: 0.1923286 for seeds 0–7.
    let turning = Spec {
        ratio: 2.5,
        target: [0.05, 0.0, 0.5],
        ..Spec::default()
    };
    every_seed_agrees("ratio 2.5, turning", turning, 0.1923286);
    // The random probe of 2026-11-30 (docs/MEASUREMENTS.md), `solve --links 1.0,1.05,0.87
    // --target -0.054,0.014,0.26`: 0.2335927 for seeds 0–7.
    let probe = Spec {
        links: [1.0, 1.05, 0.87],
        target: [-0.054, 0.014, 0.26],
        ..Spec::default()
    };
    every_seed_agrees("links 1, 1.05, 0.87, turning", probe, 0.2335927);
}

/// Far and turning targets, a bent start.
#[test]
fn far_and_turning_targets() {
    // `solve --target 0.4,0,0`: 0.8852669 for seeds 0–7.
    let far = Spec {
        target: [0.4, 0.0, 0.0],
        ..Spec::default()
    };
    every_seed_agrees("0.4 m ahead", far, 0.8852669);
    // `solve --target 0,0,1.0`: 0.3671974 for seeds 0–7.
    let turn = Spec {
        target: [0.0, 0.0, 1.0],
        ..Spec::default()
    };
    every_seed_agrees("a turn of 1 rad", turn, 0.3671974);
    // `solve --alpha0 0.4,-0.3 --target 0.2,0.1,0.3`: 0.4315017 for seeds 0–7.
    let bent = Spec {
        alpha0: [0.4, -0.3],
        target: [0.2, 0.1, 0.3],
        ..Spec::default()
    };
    every_seed_agrees("bent start, far", bent, 0.4315017);
    // The random probe of 2026-11-30, `solve --target -0.195,-0.034,0.46`: 0.3965402 for
    // seeds 0–7.
    let back = Spec {
        target: [-0.195, -0.034, 0.46],
        ..Spec::default()
    };
    every_seed_agrees("0.2 m back, turning", back, 0.3965402);
}

/// A joint limit with a bent start and a turning target.
#[test]
fn a_joint_limit_and_a_bent_start() {
    // `solve --alpha-max 1.8 --alpha0 0.3,-0.3 --target 0.05,0.05,0.2`: 0.3168819 for seeds
    // 0–7.
    let limited = Spec {
        alpha_max: Some(1.8),
        alpha0: [0.3, -0.3],
        target: [0.05, 0.05, 0.2],
        ..Spec::default()
    };
    every_seed_agrees("limit 1.8, bent start", limited, 0.3168819);
}

/// More swimmers: unequal links (a long front and short rear link, and the reverse) and
/// drag ratios 2.2 and 3.
#[test]
fn more_swimmers() {
    // `solve --links 1,0.7,1.3 --target 0.1,0.1,0`: 0.3584623 for seeds 0–7.
    let short_front = Spec {
        links: [1.0, 0.7, 1.3],
        target: [0.1, 0.1, 0.0],
        ..Spec::default()
    };
    every_seed_agrees("links 1, 0.7, 1.3", short_front, 0.3584623);
    // `solve --links 1,1.5,0.6 --target 0,-0.1,0`: 0.3422444 for seeds 0–7.
    let long_front = Spec {
        links: [1.0, 1.5, 0.6],
        target: [0.0, -0.1, 0.0],
        ..Spec::default()
    };
    every_seed_agrees("links 1, 1.5, 0.6, sideways", long_front, 0.3422444);
    // `solve --ratio 3.0 --target 0.1,0,0`: 0.0790207 for seeds 0–7.
    let ratio_3 = Spec {
        ratio: 3.0,
        target: [0.1, 0.0, 0.0],
        ..Spec::default()
    };
    every_seed_agrees("ratio 3", ratio_3, 0.0790207);
    // `solve --ratio 2.2 --target 0.1,-0.05,0.3`: 0.2554360 for seeds 0–7.
    let ratio_2_2 = Spec {
        ratio: 2.2,
        target: [0.1, -0.05, 0.3],
        ..Spec::default()
    };
    every_seed_agrees("ratio 2.2", ratio_2_2, 0.2554360);
}

/// A start bent to 0.8 rad, a turn of −1 rad with a step ahead.
#[test]
fn more_bent_starts_and_turns() {
    // `solve --alpha0 0.8,-0.8 --target 0.1,0,0`: 0.1258270 for seeds 0–7.
    let bent = Spec {
        alpha0: [0.8, -0.8],
        target: [0.1, 0.0, 0.0],
        ..Spec::default()
    };
    every_seed_agrees("bent 0.8, -0.8", bent, 0.1258270);
    // `solve --target 0.2,0,-1.0`: 0.4134747 for seeds 0–7.
    let turn = Spec {
        target: [0.2, 0.0, -1.0],
        ..Spec::default()
    };
    every_seed_agrees("0.2 m and -1 rad", turn, 0.4134747);
}

/// A cheapest admissible minimum must be clear of the overlap to stop the search: at drag
/// ratio 1.5, target (0.3, 0, 0.5), seed 7 stopped on one at 3.135 (coarse), which crosses
/// it on the problem's grid, before it met the one seeds 0–6 return.
#[test]
fn a_cheapest_minimum_clear_of_the_overlap() {
    // `solve --ratio 1.5 --target 0.3,0,0.5`: 1.6620245 for seeds 0–7 (seed 7 1.8085956
    // before).
    let spec = Spec {
        ratio: 1.5,
        target: [0.3, 0.0, 0.5],
        ..Spec::default()
    };
    // Seed 7 and its neighbour (the rule met at 480 and 224 starts; all eight take a minute).
    let problem = Problem::new(&spec).unwrap();
    seeds_agree(
        "ratio 1.5, turning",
        &problem,
        6..8,
        1.6620245,
        COARSE_COST_ERROR,
    );
}

/// A joint limit on another swimmer.
#[test]
fn a_joint_limit_on_another_swimmer() {
    // `solve --ratio 2.2 --alpha-max 3.0 --target 0,0,0.8`: 0.2685634 for seeds 0 and 5.
    let spec = Spec {
        ratio: 2.2,
        alpha_max: Some(3.0),
        target: [0.0, 0.0, 0.8],
        ..Spec::default()
    };
    every_seed_agrees("ratio 2.2, limit 3.0", spec, 0.2685634);
}

/// The default budget: 1024 starts without a joint limit, 160 with one (where the whole
/// budget runs: the 96 rim loops and 64 of the family), a given one for both.
#[test]
fn the_default_budget_follows_the_joint_limit() {
    let options = SolveOptions::default();
    let free = Problem::new(&Spec::default()).unwrap();
    let limited = Problem::new(&Spec {
        alpha_max: Some(1.5),
        ..Spec::default()
    })
    .unwrap();
    assert_eq!(options.budget(&free), FREE_STARTS);
    assert_eq!(options.budget(&limited), LIMITED_STARTS);
    assert_eq!((FREE_STARTS, LIMITED_STARTS), (1024, 160));
    let given = SolveOptions {
        starts: Some(64),
        ..options
    };
    assert_eq!((given.budget(&free), given.budget(&limited)), (64, 64));
}

/// Issue 33: at drag ratio 2.5, target (0, −0.15, 0.2), no seed met the stopping rule within
/// 512 starts and seed 6 returned 0.8175969 where seeds 0–5 and 7 returned 0.8043649; the
/// default budget of 1024 starts without a joint limit gives seed 6 the same gait.
#[test]
fn a_budget_of_1024_starts_gives_every_seed_the_same_gait() {
    // `solve --ratio 2.5 --target 0,-0.15,0.2 --seed S`: 0.8043649 for seeds 0–7.
    let problem = Problem::new(&Spec {
        ratio: 2.5,
        target: [0.0, -0.15, 0.2],
        ..Spec::default()
    })
    .unwrap();
    for seed in [0, 6] {
        let options = SolveOptions {
            seed,
            ..SolveOptions::default()
        };
        let s = solve(&problem, &options, &|| {}).expect("the problem solves");
        let cost = s.extremals[s.best].cost;
        assert!(
            (cost / 0.8043649 - 1.0).abs() < 1e-6,
            "seed {seed}: J = {cost}"
        );
    }
}
