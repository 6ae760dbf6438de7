//! The offline solver on the paper's problem (N = 10 000):
//! - `newton_from_good_start`: multiple-shooting Newton from the direct method's loop and
//!   its fitted costate (the start the solver actually uses), to a residual ≤ 1e-12;
//! - `shooting_jacobian`: one exact 5×5 single-shooting Jacobian (dual numbers);
//! - `default_solve`: the whole default multi-start `solve` (8 starts, rayon).
use criterion::{Criterion, criterion_group, criterion_main};
use host_sim::direct::Basis;
use host_sim::problem::Problem;
use host_sim::seed::Ellipse;
use host_sim::shooting;
use host_sim::solve::{SolveOptions, shooting_start, solve};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let p = Problem::paper();
    let basis = Basis::new(&p);
    let e = Ellipse {
        a: 0.5,
        b: -0.5,
        psi: 0.0,
        phase: 0.5 * core::f64::consts::PI,
        turns: 2,
    };
    let (ms, y0) = shooting_start(&p, &basis, &e, &SolveOptions::default()).unwrap();
    // The fitted (μ, ξ^{−1}) lead the multiple-shooting unknowns.
    let z = shooting::Unknowns::from_fn(|i, _| y0[i]);
    let mut g = c.benchmark_group("solve");
    g.sample_size(10);
    g.bench_function("newton_from_good_start", |b| {
        b.iter(|| {
            let (_, r, _) = ms.solve(&p, black_box(&y0), 1e-12, 25);
            assert!(r <= 1e-12);
        })
    });
    g.bench_function("shooting_jacobian", |b| {
        b.iter(|| shooting::residual_and_jacobian(&p, black_box(&z)).is_ok())
    });
    g.bench_function("default_solve", |b| {
        b.iter(|| solve(&p, &SolveOptions::default(), &|| {}).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
