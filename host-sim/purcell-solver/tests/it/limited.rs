//! The global search under a joint limit (`purcell_solver::solver::search`): what it must file
//! whatever the seed, and which of its minima the refinement skips.

use purcell_solver::problem::{Problem, Spec};
use purcell_solver::solver::continuation::{Warm, continue_to};
use purcell_solver::solver::recentre::recentred;
use purcell_solver::solver::refinement::walked;
use purcell_solver::solver::settings::{LIMITED_MIN_STARTS, NEAR_TARGET, UNRESOLVED};
use purcell_solver::solver::{
    Extremal, Solution, SolveOptions, Stop, refine, search_coarse, solve,
};

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

/// At `α_max = 1.5` (the public problem `joint-limit-1.5`) eight coarse minima of the
/// barrier problem (thirteen while the free minima were carried in along both coarse paths)
/// end 6–7 % of the displacement asked for off the target once prolonged to
/// the next grid: minima of the coarse grid's error, whose barrier path there stalls (about
/// 1 s of Newton each, most of the solve). All dearer on the coarse grid than the resolved
/// minimum that settles the cheapest gait, they are skipped and reported as unrefined; the
/// gait is the public problem's, and the cheapest skipped minimum, refined all the same,
/// reaches a dearer gait (1.2311147, through the 256-step grid; through grids 16 times finer
/// it stalled).
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
    assert!(skipped.len() >= 5, "{}", skipped.len());
    let cheapest = skipped
        .iter()
        .map(|u| u.minimum.cost)
        .fold(f64::INFINITY, f64::min);
    let found = search_coarse(&problem, &options, &|| {}).unwrap();
    let c = (found.candidates.iter())
        .find(|c| c.cost == cheapest)
        .unwrap();
    // Refined all the same, it stalls or reaches a gait no cheaper: skipping it lost nothing.
    match refine(&problem, &c.u, &c.nu, f64::INFINITY, &|| ()) {
        Err(Stop::Defect(_) | Stop::Stationarity { .. }) => {}
        Ok((grid, run)) => {
            let refined = grid.cost(&run.point.u, &run.point.states);
            assert!(refined >= cost, "{refined} below {cost}");
        }
        Err(stop) => panic!("{stop:?}"),
    }
}

/// Under a joint limit every seed runs the loops in one order (module docs of
/// [`search`](purcell_solver::solver::search)): two seeds' searches file the same minima, bit
/// for bit, so the stopping rule ends them at the same start. On `--alpha-max 1.2 --target 0,0,-0.5`, seed 7 of main 5289f99 gave
/// up after 96 starts without a candidate (the hopeless rule) and the cheapest gait,
/// 2.8620559, comes from start 357 of seed 0; here 128 starts run for both seeds (issue 33).
/// About 5 CPU-s.
#[test]
fn every_seed_runs_one_order() {
    use purcell_solver::solver::{coarse_grid, search::search};
    let problem = Problem::new(&Spec {
        target: [0.0, 0.0, -0.5],
        alpha_max: Some(1.2),
        ..Spec::default()
    })
    .unwrap();
    let grid = coarse_grid(&problem, &SolveOptions::default()).unwrap();
    let run = |seed| {
        let admits = |a| problem.admits(a);
        search(
            &grid,
            128..=128,
            seed,
            problem.alpha_max,
            &admits,
            &[],
            &|| {},
        )
    };
    let (a, b) = rayon::join(|| run(0), || run(7));
    assert_eq!((a.starts, b.starts), (128, 128));
    assert!(!a.candidates.is_empty());
    assert_eq!(a.candidates.len(), b.candidates.len());
    for (x, y) in a.candidates.iter().zip(&b.candidates) {
        assert_eq!(x.u, y.u, "{} vs {}", x.cost, y.cost);
        assert_eq!((x.cost, x.hits, x.start), (y.cost, y.hits, y.start));
    }
}

/// Under a joint limit the stopping rule ends the search ([`search`]'s module docs): on the
/// public `joint-limit-2.0` it is met after 64 starts ([`LIMITED_MIN_STARTS`]), well before
/// the budget of 160, at the same start for two seeds (both run seed 0's order). About 4 CPU-s.
///
/// [`search`]: purcell_solver::solver::search
#[test]
fn the_stopping_rule_ends_a_limited_search_at_the_same_start_for_every_seed() {
    let problem = Problem::new(&Spec {
        alpha_max: Some(2.0),
        ..Spec::default()
    })
    .unwrap();
    let run = |seed| {
        let options = SolveOptions {
            seed,
            ..SolveOptions::default()
        };
        search_coarse(&problem, &options, &|| {}).unwrap()
    };
    let (a, b) = rayon::join(|| run(0), || run(5));
    assert!(a.satisfied && b.satisfied);
    assert_eq!(
        (a.starts, b.starts),
        (LIMITED_MIN_STARTS, LIMITED_MIN_STARTS)
    );
    assert!(a.starts < SolveOptions::default().budget(&problem));
}

/// On (0, 0.1, 0) within 1.3 rad, seed 0 of main 5289f99 returned 1.5494037 (its one resolved
/// coarse minimum settled 1.5707995, and the cheapest of its unresolved ones, refined since
/// cheaper on the coarse grid, 1.5494037) and seeds 1–7 1.5258579, from a coarse minimum seed
/// 0's early stop did not file (issue 33). Under a joint limit every seed now runs the same
/// starts (here the whole budget: the stopping rule is not met), and the resolved minima
/// settle 1.5258579 (nothing is skipped). About 20 s.
#[test]
fn the_cheapest_gait_within_1_3_rad_is_every_seeds() {
    let problem = Problem::new(&Spec {
        target: [0.0, 0.1, 0.0],
        alpha_max: Some(1.3),
        ..Spec::default()
    })
    .unwrap();
    let s = solve(&problem, &SolveOptions::default(), &|| {}).unwrap();
    let cost = s.extremals[s.best].cost;
    assert!((cost - 1.5258579).abs() <= 1e-7, "{cost}");
}

/// The paper's target within `|α_i| ≤ 0.95` (issue 33) from a coarse grid too coarse for it:
/// on 32 steps no start of the search converges, the best ending within [`NEAR_TARGET`] of the
/// displacement (of 128 starts, 3.0e-4 from the target), so `solve` searches again on 64 steps and returns
/// the gait the default 64-step search does (3.4649234 on 14 arcs, `purcell-sim solve
/// --alpha-max 0.95`), dearer than the 2.9734287 of `α_max = 1` (a looser limit is never
/// dearer). (With the search of main 5289f99 the 64-step grid's minima did not refine either
/// and the finer grids' search returned 3.5905650 from 256 steps; until the unresolved
/// candidates were refined as resolved ones where those settle none, the 64-step search
/// returned 3.5985213 on 16 arcs, then 3.5905650 until the coarse minima that miss the target
/// by more than 5 % were walked back up the central path.) The default budget of 512
/// starts: with 128 the 64-step search returns 3.8426862 (it did 3.5985213 while a path's
/// weights were all solved to the run's tolerances). About 20 CPU-s.
#[test]
fn a_tight_limit_whose_coarse_grid_is_too_coarse_is_searched_on_finer_grids() {
    let problem = Problem::new(&Spec {
        alpha_max: Some(0.95),
        ..Spec::default()
    })
    .unwrap();
    let options = SolveOptions {
        coarse_steps: 32,
        ..SolveOptions::default()
    };
    let found = search_coarse(&problem, &options, &|| {}).unwrap();
    assert!(found.candidates.is_empty(), "{}", found.candidates.len());
    assert!(found.best_residual <= NEAR_TARGET * problem.displacement());
    let s = solve(&problem, &options, &|| {}).unwrap();
    let best = &s.extremals[s.best];
    assert!((best.cost - 3.4649234).abs() <= 1e-6, "{}", best.cost);
    assert!(best.admissible && best.cost > 2.9734287);
    assert!(best.local_min && !best.arcs.is_empty());
}

/// A gait on many arcs of a tight limit carried to a finer time step (`solve --from`): links
/// 1, 0.93, 0.93 to (0.144, 0.023, −0.44) within 1 rad, from its gait of `--step 0.1` (16
/// arcs) to `--step 0.05`. The medium grid's route stalls there (and the global search of
/// `--step 0.05` returns 14.7280354); the refinement straight from the gait reaches
/// 8.6260113, its active-set rounds settling from the stretches within `LOOSE_NEAR` of the
/// limit (from those within `NEAR` Newton does not converge). About 5 s.
#[test]
fn a_tight_limits_gait_carries_to_a_finer_time_step() {
    let spec = |step| Spec {
        target: [0.144, 0.023, -0.44],
        links: [1.0, 0.93, 0.93],
        alpha_max: Some(1.0),
        step,
        ..Spec::default()
    };
    let coarse = Problem::new(&spec(0.1)).unwrap();
    let s = solve(&coarse, &SolveOptions::default(), &|| {}).unwrap();
    let x = &s.extremals[s.best];
    assert!((x.cost - 7.8450051).abs() <= 1e-6, "{}", x.cost);
    let warm = Warm::from_trajectory(&x.trajectory, &x.mu, coarse.horizon()).unwrap();
    let fine = Problem::new(&spec(0.05)).unwrap();
    let y = continue_to(&fine, &warm).unwrap();
    assert!(y.admissible && y.local_min, "{y:?}");
    assert_eq!(y.arcs.len(), 16);
    assert!((y.cost - 8.6260113).abs() <= 1e-6, "{}", y.cost);
}

/// A lateral target within a limit that asks for six strokes (`--alpha-max 1.9 --ratio 1.7
/// --target -0.001,-0.242,-0.01`): none of the search's 160 start loops reaches a minimum
/// within the limit, its one gait is a free minimum carried in (7.8813055, on no arc), and
/// IPOPT from a circle finds 7.8124168 on the limit (`peers/ipopt-results/probe2.jsonl`); the
/// gait flown twice is tried too and is the cheaper, 7.7969821 on two arcs. About 10 s.
#[test]
fn where_no_start_loop_reaches_the_limit_the_flown_gaits_are_tried_too() {
    let problem = Problem::new(&Spec {
        target: [-0.001, -0.242, -0.01],
        ratio: 1.7,
        alpha_max: Some(1.9),
        ..Spec::default()
    })
    .unwrap();
    let s = solve(&problem, &SolveOptions::default(), &|| {}).unwrap();
    assert_eq!(s.flown, Some(2));
    let x = &s.extremals[s.best];
    assert!((x.cost - 7.7969821).abs() <= 1e-6, "{}", x.cost);
    assert!(x.cost < 7.8124168 && x.admissible && x.local_min);
    assert_eq!(x.arcs.len(), 2);
    let found = search_coarse(&problem, &SolveOptions::default(), &|| {}).unwrap();
    assert!(found.from_starts == 0 && !found.candidates.is_empty());
}

/// A random probe's turn within 1.5 rad (`--alpha-max 1.5 --target -0.053,-0.226,0.53`,
/// `peers/probe3.json` p17-5): no coarse minimum of the search is resolved by its grid; of
/// the unresolved ones the first to settle reaches 4.1967975 on 10 arcs (one start of 160,
/// rule not met), a later one 4.1912378 on 8, the answer of the refinement. IPOPT from
/// 4.1967975 (its first barrier weight lifting it off its arcs) converges to 4.1770333 on 7
/// arcs (`peers/ipopt-results/probe3.jsonl`). Walked back up the central path and down,
/// 4.1912378 stays in its basin and 4.1967975 reaches IPOPT's gait, which was returned so,
/// certified as every gait ([`recentre`](purcell_solver::solver::recentre)): so each admissible
/// gait is walked, not only the answer. The refinement now reaches it first: its coarse
/// minima that miss the target by more than 5 % on the next grid and cost less there than
/// the settled gait are walked back up the central path too, and twenty of them reach it;
/// the recentring then finds nothing cheaper. About 30 s.
#[test]
fn a_limited_gait_walked_back_up_the_central_path_reaches_ipopts_cheaper_gait() {
    let problem = Problem::new(&Spec {
        target: [-0.053, -0.226, 0.53],
        alpha_max: Some(1.5),
        ..Spec::default()
    })
    .unwrap();
    let s = solve(&problem, &SolveOptions::default(), &|| {}).unwrap();
    assert!(!s.recentred && s.flown.is_none());
    let x = &s.extremals[s.best];
    assert!((x.cost - 4.1770333).abs() <= 1e-6, "{}", x.cost);
    assert!(x.admissible && x.local_min && x.hits >= 10, "{}", x.hits);
    assert_eq!(x.arcs.len(), 7);
    let refined: Vec<Extremal> = (s.extremals.iter())
        .filter(|y| !std::ptr::eq(*y, x))
        .cloned()
        .collect();
    let costs: Vec<f64> = refined.iter().map(|y| y.cost).collect();
    assert_eq!(costs.len(), 2, "{costs:?}");
    assert!((costs[0] - 4.1912378).abs() <= 1e-6, "{costs:?}");
    assert!((costs[1] - 4.1967975).abs() <= 1e-6, "{costs:?}");
    // The refinement's answer alone walks back into its own basin.
    let walked = |extremals: Vec<Extremal>| {
        let solution = Solution {
            best: 0,
            extremals,
            search: None,
            flown: None,
            recentred: false,
        };
        recentred(&problem, solution, &|| {})
    };
    let alone = walked(refined[..1].to_vec());
    assert!(!alone.recentred && alone.extremals.len() == 1);
    let both = walked(refined);
    let reached = both.extremals[both.best].cost;
    assert!(
        both.recentred && (reached - x.cost).abs() <= 1e-12 * x.cost,
        "{reached}"
    );
}

/// A random probe's far sideways move within 1.2 rad (`--alpha-max 1.2 --ratio 2.2 --target
/// 0.087,0.28,0.14`, `peers/probe4.json` p18-3): on the 128-step grid (the 64-step one's
/// minima do not refine) the coarse minimum of J 9.7390 stalls on both of the refinement's
/// routes, while walked back up the central path from `τ = 0.1` on 256 steps and down it
/// reaches 9.3519385 on 18 arcs, certified, where the refinement settled 9.9472948 before
/// and IPOPT from a circle found 9.9436241 (`--max-cpu 900`). About 20 s.
#[test]
fn a_stalled_coarse_minimum_walked_back_up_the_central_path_reaches_a_cheaper_gait() {
    let problem = Problem::new(&Spec {
        target: [0.087, 0.28, 0.14],
        ratio: 2.2,
        alpha_max: Some(1.2),
        ..Spec::default()
    })
    .unwrap();
    let options = SolveOptions {
        coarse_steps: 128,
        ..SolveOptions::default()
    };
    let found = search_coarse(&problem, &options, &|| {}).unwrap();
    let c = (found.candidates.iter())
        .find(|c| (c.cost - 9.7390).abs() <= 1e-4)
        .expect("the coarse minimum");
    let stalled = refine(&problem, &c.u, &c.nu, f64::INFINITY, &|| {}).err();
    assert!(
        matches!(stalled, Some(Stop::Defect(_) | Stop::Stationarity { .. })),
        "{stalled:?}"
    );
    let x = walked(&problem, &c.u, (0.0, 9.9472948), 1.2, &|| {}).expect("a cheaper gait");
    assert!((x.cost - 9.3519385).abs() <= 1e-6, "{}", x.cost);
    assert!(x.admissible && x.local_min && x.arcs.len() == 18);
    assert!(x.kkt_residual.is_some_and(|r| r <= 1e-8));
}

/// An extremal's hits are every start whose coarse minimum the refinement carried to it, on
/// the problem's grid or meeting its path on a finer grid (repeats), twins apart: on the turn
/// (0, 0, 0.3) within 1.1 rad the coarse grid splits the cheapest gait's basin into many
/// minima, each reached from one or two starts, and the gait is reached from more starts than
/// any one of them; no start is counted twice. About 6 s.
#[test]
fn an_extremals_hits_count_every_start_that_reached_it() {
    let problem = Problem::new(&Spec {
        target: [0.0, 0.0, 0.3],
        alpha_max: Some(1.1),
        ..Spec::default()
    })
    .unwrap();
    let s = solve(&problem, &SolveOptions::default(), &|| {}).unwrap();
    let e = s.search.as_ref().unwrap();
    let most = e.minima.iter().map(|m| m.hits).max().unwrap();
    let x = &s.extremals[s.best];
    assert!(x.hits > most, "{} hits, a minimum {most}", x.hits);
    let counted: usize = s.extremals.iter().map(|y| y.hits).sum();
    let reached: usize = e.minima.iter().map(|m| m.hits).sum();
    assert!(counted <= reached, "{counted} > {reached}");
}
