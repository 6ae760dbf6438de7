//! The offline solver on the paper's problem (N = 10 000):
//! - `default_solve`: the whole default `solve` (global search on the coarse grid, refinement
//!   of the candidates, certificates);
//! - `refine_cheapest_admissible`: carrying the coarse grid's cheapest admissible extremal to
//!   the fine grid (Newton on a 1 024-step grid, then on the problem's own);
//! - `coarse_search`: the global search alone;
//! - `joint_limit_1.5`, `joint_limit_2.5`: the default `solve` with `--alpha-max 1.5` and
//!   `2.5` (interior-point search, active-set refinement; issue target ≤ 2 s each on one
//!   core, `RAYON_NUM_THREADS=1`);
//! - `far_target`: the default `solve` toward `ḡ = (0.25, 0.2, 0)` (the public problem
//!   `far-diag-a`; target ≤ 10 s on one core).
use criterion::{Criterion, criterion_group, criterion_main};
use purcell_solver::problem::{Problem, Spec};
use purcell_solver::solver::{SolveOptions, coarse_grid, refine, search, solve};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let p = Problem::paper();
    let options = SolveOptions::default();
    let coarse = coarse_grid(&p, &options).unwrap();
    let admissible = |a: f64| p.admits(a);
    let run_search = || {
        search::search(
            &coarse,
            options.starts(&p),
            options.seed,
            None,
            &admissible,
            &[],
            &|| {},
        )
    };
    let found = run_search();
    let best = found
        .candidates
        .iter()
        .find(|c| admissible(c.max_abs_alpha))
        .unwrap()
        .clone();
    let mut g = c.benchmark_group("solve");
    g.sample_size(10);
    g.bench_function("default_solve", |b| {
        b.iter(|| solve(&p, &options, &|| {}).unwrap())
    });
    g.bench_function("refine_cheapest_admissible", |b| {
        b.iter(|| refine(&p, black_box(&best.u), &best.nu, f64::INFINITY, &|| ()).unwrap())
    });
    g.bench_function("coarse_search", |b| b.iter(run_search));
    for a in [1.5, 2.5] {
        let limited = Problem::new(&Spec {
            alpha_max: Some(a),
            ..Spec::default()
        })
        .unwrap();
        g.bench_function(format!("joint_limit_{a}"), |b| {
            b.iter(|| solve(&limited, &options, &|| {}).unwrap())
        });
    }
    let far = Problem::new(&Spec {
        target: [0.25, 0.2, 0.0],
        ..Spec::default()
    })
    .unwrap();
    g.bench_function("far_target", |b| {
        b.iter(|| solve(&far, &options, &|| {}).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
