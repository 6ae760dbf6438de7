//! One step of the control law (MODEL.md §5, with `Real::FIXED_POINT_PASSES` passes) in f32
//! and f64 on a realistic state, and for context its parts: the connection `A(α)` with
//! `∂A/∂α`, and `exp` on SE(2).
//!
//! The state is step 2 500 of the f64 replay of a `|μ| ≈ 13` extremal of the paper's problem
//! (α ≈ (1.6, 0.9), g far from the identity), so every branch taken is the one taken in
//! flight. `replay` runs the whole 10 000-step horizon of the paper's returned extremal
//! (`J = 0.686`) through [`Replay::step`], with its f64 checkpoints every 100 steps (in f32;
//! none needed in f64), and reports the time per step as throughput.
//! Run: `cargo bench -p purcell-benches --bench step`.
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use nalgebra::{Vector2, Vector3};
use purcell_core::{Checkpoint, Costate, Kinematics, Real, Replay, Se2, State, Swimmer, se2};
use std::hint::black_box;

/// `(state, ξ^{k−1}, μ)` at step `k` of the f64 replay of the `|μ| ≈ 13` extremal.
fn realistic(k: u32) -> (State<f64>, Vector2<f64>, Vector3<f64>) {
    let costate = Costate {
        mu: Vector3::new(
            1.532_914_552_615_802_8,
            13.222_390_687_754_31,
            0.593_346_744_546_872_6,
        ),
        xi: Vector2::new(2.262_121_649_874_644, -1.952_433_722_666_657_5),
    };
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
    let passes = T::FIXED_POINT_PASSES;
    c.bench_function(&format!("law_step/{name} ({passes} passes)"), |b| {
        b.iter(|| kin.law_step(black_box(&state), black_box(&xi), black_box(&mu)))
    });
    c.bench_function(&format!("law_step/{name} (0 passes, no dexp)"), |b| {
        b.iter(|| kin.law_step_with_passes(black_box(&state), black_box(&xi), black_box(&mu), 0))
    });
    let sw = *kin.swimmer();
    c.bench_function(&format!("connection_with_derivatives/{name}"), |b| {
        b.iter(|| sw.connection_with_derivatives(black_box(&state.alpha)))
    });
    let step = kin.law_step(&state, &xi, &mu).expect("admissible step");
    let x = kin.twist(&sw.connection(&state.alpha).expect("admissible"), &step.u);
    c.bench_function(&format!("se2_exp/{name} (|w| ~ 1e-3)"), |b| {
        b.iter(|| se2::exp(black_box(&x)))
    });
}

/// The returned extremal of the paper's problem (`J = 0.686`, `|μ| ≈ 6.4`).
fn paper_costate() -> Costate<f64> {
    Costate {
        mu: Vector3::new(
            1.267_405_852_682_282_5,
            6.195_325_497_329_788,
            -1.054_518_565_868_840_5,
        ),
        xi: Vector2::new(0.645_028_386_460_496_6, -1.333_507_114_196_018_2),
    }
}

/// Full-horizon replay per step, as the firmware runs it.
fn bench_replay<T: Real>(c: &mut Criterion, name: &str, cast: fn(f64) -> T, every: u32) {
    const STEPS: u32 = 10_000;
    let c64 = paper_costate();
    let kin64 = Kinematics::new(Swimmer::purcell(), 0.01).expect("valid step");
    let start64 = State::at_origin(Vector2::zeros());
    let mut checkpoints = Vec::new();
    let (mut state, mut xi_prev) = (start64, c64.xi);
    for k in 0..STEPS {
        if every > 0 && k > 0 && k % every == 0 {
            let g = &state.g;
            checkpoints.push(Checkpoint {
                k,
                state: State {
                    alpha: state.alpha.map(cast),
                    g: Se2::from_rotation(cast(g.x()), cast(g.y()), cast(g.cos()), cast(g.sin())),
                },
                xi: xi_prev.map(cast),
            });
        }
        let s = kin64
            .law_step(&state, &xi_prev, &c64.mu)
            .expect("admissible");
        (state, xi_prev) = (s.next, s.xi);
    }
    let kin = Kinematics::new(Swimmer::<T>::purcell(), cast(0.01)).expect("valid step");
    let costate = Costate {
        mu: c64.mu.map(cast),
        xi: c64.xi.map(cast),
    };
    let start = State::at_origin(Vector2::<T>::zeros());
    let mut group = c.benchmark_group("replay");
    group.throughput(Throughput::Elements(u64::from(STEPS)));
    group.sample_size(20);
    group.bench_function(format!("{name} (10 000 steps, Replay::step)"), |b| {
        b.iter(|| {
            let mut replay =
                Replay::new(kin, start, costate, STEPS, black_box(&checkpoints)).expect("valid");
            while let Some(s) = replay.step().expect("admissible") {
                black_box(s);
            }
            *replay.state()
        })
    });
    group.finish();
}

fn bench(c: &mut Criterion) {
    bench_type::<f64>(c, "f64", |v| v);
    bench_type::<f32>(c, "f32", |v| v as f32);
    bench_replay::<f64>(c, "f64", |v| v, 0);
    bench_replay::<f32>(c, "f32", |v| v as f32, 100);
}

criterion_group!(benches, bench);
criterion_main!(benches);
