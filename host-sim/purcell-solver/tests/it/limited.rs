//! The global search under a joint limit (`purcell_solver::solver::search`): what it must file
//! whatever the seed, and which of its minima the refinement skips.

use purcell_solver::problem::{Problem, Spec};
use purcell_solver::solver::settings::UNRESOLVED;
use purcell_solver::solver::{SolveOptions, Stop, refine, search_coarse, solve};

/// The zero target from a bent start within a limit: the zero control (every state at `ᾱ`,
/// inside the limit) is the exact global minimum, `J = 0`, which the barrier's gradient at a
/// bent `ᾱ` pushed every start off (exit 3, "no start reached the target").
#[test]
fn the_zero_target_from_a_bent_start_is_the_zero_gait() {
    let problem = Problem::new(&Spec {
        target: [0.0; 3],
        alpha0: [0.0, 0.9],
        alpha_max: Some(1.5),
        ..Spec::default()
    })
    .unwrap();
    for seed in 0..2 {
        let options = SolveOptions {
            seed,
            ..SolveOptions::default()
        };
        let s = solve(&problem, &options, &|| {}).unwrap();
        let best = &s.extremals[s.best];
        assert_eq!(best.cost, 0.0, "seed {seed}");
        assert!(best.arcs.is_empty() && best.admissible, "seed {seed}");
        assert!(best.trajectory.controls.iter().all(|u| u.norm() == 0.0));
    }
}

/// At `α_max = 1.5` (the public problem `joint-limit-1.5`) thirteen coarse minima of the
/// barrier problem end 6–7 % of the displacement asked for off the target once prolonged to
/// the next grid: minima of the coarse grid's error, whose barrier path there stalls (about
/// 1 s of Newton each, most of the solve). All dearer on the coarse grid than the resolved
/// minimum that settles the cheapest gait, they are skipped and reported as unrefined; the
/// gait is the public problem's, and the cheapest skipped minimum, refined all the same,
/// stalls.
#[test]
fn unresolved_coarse_minima_are_skipped_not_lost() {
    let problem = Problem::new(&Spec {
        alpha_max: Some(1.5),
        ..Spec::default()
    })
    .unwrap();
    let options = SolveOptions::default();
    let s = solve(&problem, &options, &|| {}).unwrap();
    let cost = s.extremals[s.best].cost;
    assert!((cost - 1.2108538249259375).abs() <= 1e-7, "{cost}");
    let evidence = s.search.as_ref().unwrap();
    let limit = UNRESOLVED * problem.displacement();
    let skipped: Vec<_> = (evidence.unrefined.iter())
        .filter(|u| u.defect > limit)
        .collect();
    assert!(skipped.len() >= 10, "{}", skipped.len());
    let cheapest = skipped
        .iter()
        .map(|u| u.minimum.cost)
        .fold(f64::INFINITY, f64::min);
    let found = search_coarse(&problem, &options, &|| {}).unwrap();
    let c = (found.candidates.iter())
        .find(|c| c.cost == cheapest)
        .unwrap();
    let refined = refine(&problem, &c.u, &c.nu, f64::INFINITY, &|| ());
    assert!(
        matches!(refined, Err(Stop::Defect(_) | Stop::Stationarity { .. })),
        "{refined:?}"
    );
}

/// Every start loop runs its own barrier path, whatever its place in a seed's order
/// ([`StartLoop::path`](purcell_solver::solver::starts::StartLoop::path)): run over the whole
/// family, two seeds' searches file the same minima. By its place (every other start), seed 3
/// of `--alpha-max 1.1 --target 0,0,0.3 --starts 936` returned 1.7266 and the others 1.5449.
/// About 20 s (two coarse searches of 936 starts under a tight limit).
#[test]
fn the_whole_family_files_the_same_minima_for_every_seed() {
    use purcell_solver::solver::grid::same_path;
    use purcell_solver::solver::{coarse_grid, search::search};
    let problem = Problem::new(&Spec {
        target: [0.0, 0.0, 0.3],
        alpha_max: Some(1.1),
        ..Spec::default()
    })
    .unwrap();
    let grid = coarse_grid(&problem, &SolveOptions::default()).unwrap();
    let run = |seed| {
        let all = 936..=936;
        search(
            &grid,
            all,
            seed,
            problem.alpha_max,
            &|a| problem.admits(a),
            &[],
            &|| {},
        )
    };
    let (a, b) = (run(0), run(3));
    assert_eq!(a.starts, 936);
    assert!(!a.candidates.is_empty());
    assert_eq!(a.candidates.len(), b.candidates.len());
    // Twins cost the same to rounding: matched by path, not by place in the list.
    for x in &a.candidates {
        let y = (b.candidates.iter())
            .find(|y| same_path(&x.u, &y.u, grid.h()))
            .unwrap_or_else(|| panic!("{} (seed 0) not filed by seed 3", x.cost));
        assert!(
            (x.cost / y.cost - 1.0).abs() <= 1e-9,
            "{} vs {}",
            x.cost,
            y.cost
        );
        assert_eq!(x.hits, y.hits, "{}", x.cost);
    }
}

/// On (0, 0.1, 0) within 1.3 rad, seed 0's one resolved coarse minimum (coarse 1.5841)
/// settles 1.5707995; its unresolved ones (coarse 1.5077–1.5203, each missing the target by
/// 1.2–1.3 % on the next grid) are cheaper on the coarse grid, so the cheapest is refined all
/// the same and settles 1.5494037 (skipped, the solve returned 1.5707995). Seeds 1–7 reach
/// 1.5258579 from a coarse minimum seed 0 does not file (issue 33): the test asks for no
/// dearer than 1.5494037, so a search that finds it too still passes. About 10 s.
#[test]
fn unresolved_minima_cheaper_than_the_resolved_ones_are_refined() {
    let problem = Problem::new(&Spec {
        target: [0.0, 0.1, 0.0],
        alpha_max: Some(1.3),
        ..Spec::default()
    })
    .unwrap();
    let s = solve(&problem, &SolveOptions::default(), &|| {}).unwrap();
    let cost = s.extremals[s.best].cost;
    assert!(cost <= 1.5494037 + 1e-7, "{cost}");
    let limit = UNRESOLVED * problem.displacement();
    let unrefined = &s.search.as_ref().unwrap().unrefined;
    assert!(unrefined.iter().any(|u| u.defect > limit), "{unrefined:?}");
}

/// The paper's target within `|α_i| ≤ 0.95` (issue 33): the four minima of the 64-step coarse
/// grid miss the target by 1.4–1.6 % of the displacement once prolonged to the next grid and
/// none refines (main 5289f99 exited 3 there), nor do the five of 128 steps; `solve` searches
/// again on finer grids and on 256 steps returns 3.5905650, dearer than the 3.1658241 of
/// `α_max = 1` (a looser limit is never dearer). About 100 CPU-s: three searches of a tight
/// limit.
#[test]
fn a_tight_limit_whose_coarse_minima_do_not_refine_is_searched_on_finer_grids() {
    let problem = Problem::new(&Spec {
        alpha_max: Some(0.95),
        ..Spec::default()
    })
    .unwrap();
    let options = SolveOptions::default();
    let s = solve(&problem, &options, &|| {}).unwrap();
    let best = &s.extremals[s.best];
    assert!((best.cost - 3.5905650).abs() <= 1e-6, "{}", best.cost);
    assert!(best.admissible && best.cost > 3.1658241);
    assert!(best.local_min && !best.arcs.is_empty());
}
