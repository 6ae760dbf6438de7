//! Joint-limited solves beside the unlimited paper solve, in one run (issue 33's target: a
//! limited solve within 3× the paper's on one thread; run with `RAYON_NUM_THREADS=1`):
//! criterion times `paper` (`Problem::paper()`, default flags) and each limited problem,
//! then [`PAIRS`] pairs run alternately (limited, paper) give the ratio: the median of the
//! per-pair ratios, which the machine's drift over the run does not move.
//! - `joint_limit_1.5`, `joint_limit_2.0`: the public problems (`--alpha-max 1.5`, `2.0`);
//! - `limit_1.1_turn`: `--alpha-max 1.1 --target 0,0,0.3` (ten arcs).
use criterion::{Criterion, criterion_group, criterion_main};
use purcell_solver::problem::{Problem, Spec};
use purcell_solver::solver::{SolveOptions, solve};
use std::time::Instant;

/// Alternating pairs for the ratio.
const PAIRS: usize = 5;

fn limited() -> [(&'static str, Problem); 3] {
    let of = |alpha_max: f64, target: [f64; 3]| {
        Problem::new(&Spec {
            alpha_max: Some(alpha_max),
            target,
            ..Spec::default()
        })
        .unwrap()
    };
    [
        ("joint_limit_1.5", of(1.5, [0.1, 0.1, 0.0])),
        ("joint_limit_2.0", of(2.0, [0.1, 0.1, 0.0])),
        ("limit_1.1_turn", of(1.1, [0.0, 0.0, 0.3])),
    ]
}

/// Seconds of one default solve of `p`.
fn seconds(p: &Problem) -> f64 {
    let t = Instant::now();
    solve(p, &SolveOptions::default(), &|| {}).unwrap();
    t.elapsed().as_secs_f64()
}

fn bench(c: &mut Criterion) {
    let paper = Problem::paper();
    let options = SolveOptions::default();
    let mut g = c.benchmark_group("limits");
    g.sample_size(10);
    g.bench_function("paper", |b| {
        b.iter(|| solve(&paper, &options, &|| {}).unwrap())
    });
    for (name, p) in limited() {
        g.bench_function(name, |b| b.iter(|| solve(&p, &options, &|| {}).unwrap()));
    }
    g.finish();
    for (name, p) in limited() {
        let mut ratios: Vec<f64> = (0..PAIRS).map(|_| seconds(&p) / seconds(&paper)).collect();
        ratios.sort_by(f64::total_cmp);
        println!(
            "{name} / paper: {:.2} (median of {PAIRS} alternating pairs; {:.2}–{:.2})",
            ratios[PAIRS / 2],
            ratios[0],
            ratios[PAIRS - 1]
        );
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
