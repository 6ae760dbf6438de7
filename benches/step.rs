//! One step of the control law (MODEL.md §5, with `Real::PASSES`) in f32
//! and f64 on a realistic state, and for context its parts: the connection `A(α)` with
//! `∂A/∂α`, and `exp` on SE(2).
//!
//! The state is step 2 500 of the f64 replay of a `|μ| ≈ 13` extremal of the paper's problem
//! (α ≈ (1.6, 0.9), g far from the identity), so every branch taken is the one taken in
//! flight (the extremals are the fixtures of `purcell_core::testkit`). `replay` runs the whole
//! 10 000-step horizon of a paper's-problem extremal (`J = 0.686`, the testkit fixture) through
//! [`Replay::step`], with the f64 replay's checkpoints every 100 steps in f32 (none needed in
//! f64), and reports the time per step as throughput.
//! Run: `cargo bench -p purcell-benches --bench step`.
use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, Throughput, criterion_group, criterion_main};
use nalgebra::{Vector2, Vector3};
use purcell_core::testkit::{STEPS, costate_f32, costate_mu6, costate_mu13, paper_kinematics};
use purcell_core::{
    Checkpoint, Costate, Kinematics, OnArcs, Passes, Real, Replay, Se2, State, Swimmer, se2,
};
use std::hint::black_box;

/// `(state, ξ^{k−1}, μ)` at step `k` of the f64 replay of the `|μ| ≈ 13` extremal.
fn realistic(k: u32) -> (State<f64>, Vector2<f64>, Vector3<f64>) {
    let costate = costate_mu13();
    let kin = Kinematics::new(Swimmer::purcell(), 0.01).expect("valid step");
    let start = State::at_origin(Vector2::zeros());
    let mut replay = Replay::new(kin, start, costate, k, &[]).expect("valid replay");
    let mut xi = costate.xi;
    for s in replay.by_ref() {
        xi = s.expect("admissible loop").xi;
    }
    (*replay.state(), xi, costate.mu)
}

fn bench_type<T: Real>(c: &mut Criterion, name: &str, cast: fn(f64) -> T) {
    let (s, xi, mu) = realistic(2500);
    let state = State {
        alpha: s.alpha.map(cast),
        g: Se2::new(cast(s.g.x()), cast(s.g.y()), cast(s.g.theta())),
    };
    let (xi, mu) = (xi.map(cast), mu.map(cast));
    let kin = Kinematics::new(Swimmer::<T>::purcell(), cast(0.01)).expect("valid step");
    let Passes { kind, count } = T::PASSES;
    c.bench_function(&format!("law_step/{name} ({count} {kind:?} passes)"), |b| {
        b.iter(|| {
            kin.law_step(
                black_box(&state),
                black_box(&xi),
                black_box(&mu),
                OnArcs::NONE,
                T::PASSES,
            )
        })
    });
    c.bench_function(&format!("law_step/{name} (first iterate only)"), |b| {
        b.iter(|| {
            let first = Passes::plain(0);
            kin.law_step(
                black_box(&state),
                black_box(&xi),
                black_box(&mu),
                OnArcs::NONE,
                first,
            )
        })
    });
    let sw = *kin.swimmer();
    c.bench_function(&format!("connection_with_derivatives/{name}"), |b| {
        b.iter(|| sw.connection_with_derivatives(black_box(&state.alpha)))
    });
    let step = kin
        .law_step(&state, &xi, &mu, OnArcs::NONE, T::PASSES)
        .expect("admissible step");
    let x = kin.twist(&sw.connection(&state.alpha).expect("admissible"), &step.u);
    c.bench_function(&format!("se2_exp/{name} (|w| ~ 1e-3)"), |b| {
        b.iter(|| se2::exp(black_box(&x)))
    });
}

/// Full-horizon replay of the returned extremal, per step, as the firmware runs it: f64 from
/// `(μ, ξ^{−1})` alone, f32 with the f64 replay's checkpoints every 100 steps.
fn bench_replay(c: &mut Criterion) {
    let c64 = costate_mu6();
    let start = State::at_origin(Vector2::zeros());
    let (samples, _) = purcell_tests::replay_all(paper_kinematics(), start, c64, STEPS, &[])
        .expect("admissible extremal");
    let checkpoints = purcell_tests::checkpoints_f32(&samples, 100);
    let mut group = c.benchmark_group("replay");
    group.throughput(Throughput::Elements(u64::from(STEPS)));
    group.sample_size(20);
    time_replay(&mut group, "f64", c64, &[]);
    time_replay(&mut group, "f32", costate_f32(&c64), &checkpoints);
    group.finish();
}

fn time_replay<T: Real>(
    group: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    costate: Costate<T>,
    checkpoints: &[Checkpoint<T>],
) {
    let start = State::at_origin(Vector2::<T>::zeros());
    group.bench_function(format!("{name} (10 000 steps, Replay::step)"), |b| {
        b.iter(|| {
            let mut replay = Replay::new(
                paper_kinematics(),
                start,
                costate,
                STEPS,
                black_box(checkpoints),
            )
            .expect("valid");
            while let Some(s) = replay.step().expect("admissible") {
                black_box(s);
            }
            *replay.state()
        })
    });
}

fn bench(c: &mut Criterion) {
    bench_type::<f64>(c, "f64", |v| v);
    bench_type::<f32>(c, "f32", |v| v as f32);
    bench_replay(c);
}

criterion_group!(benches, bench);
criterion_main!(benches);
