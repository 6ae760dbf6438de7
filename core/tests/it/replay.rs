//! The fixed-horizon replay: it is the law stepped `N` times, checkpoints reset `(α, g, ξ)`
//! exactly at their steps, it stops for good at the first error, and `finish` is the last state.

use crate::common;

use common::*;
use nalgebra::{Vector2, Vector3};
use purcell_core::{
    Checkpoint, Checkpoints, Costate, Error, OnArcs, Real, Replay, Sample, Se2, State,
};

fn start() -> State<f64> {
    State::at_origin(Vector2::zeros())
}

fn run(costate: Costate<f64>, steps: u32, cps: &[Checkpoint<f64>]) -> Vec<Sample<f64>> {
    Replay::new(paper_kinematics(), start(), costate, steps, cps)
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap()
}

#[test]
fn replay_is_the_law_stepped_in_order() {
    let kin = paper_kinematics::<f64>();
    let c = costate_mu13();
    let samples = run(c, 200, &[]);
    assert_eq!(samples.len(), 200);
    let (mut state, mut xi) = (start(), c.xi);
    for (k, s) in samples.iter().enumerate() {
        let step = kin
            .law_step(&state, &xi, &c.mu, OnArcs::NONE, f64::PASSES)
            .unwrap();
        assert_eq!(s.k as usize, k);
        assert_eq!((s.state, s.u, s.xi), (state, step.u, step.xi));
        (state, xi) = (step.next, step.xi);
    }
}

#[test]
fn checkpoints_reset_state_and_xi_at_their_steps() {
    let kin = paper_kinematics::<f64>();
    let c = costate_mu13();
    let mut table = Checkpoints::<f64, 4>::new();
    let at = |a1, a2, x, th| State {
        alpha: Vector2::new(a1, a2),
        g: Se2::new(x, 0.02, th),
    };
    let reset = [
        Checkpoint {
            k: 0,
            state: at(0.1, -0.1, 0.0, 0.1),
            xi: Vector2::new(2.0, -2.0),
        },
        Checkpoint {
            k: 7,
            state: at(0.3, 0.2, 0.01, -0.2),
            xi: Vector2::new(2.5, -1.5),
        },
        Checkpoint {
            k: 19,
            state: at(-0.4, 0.5, 0.03, 0.4),
            xi: Vector2::new(1.0, -1.0),
        },
    ];
    for cp in reset {
        table.push(cp).unwrap();
    }
    let with = run(c, 30, table.as_slice());
    let without = run(c, 30, &[]);
    // Step k starts from the checkpoint's (α_k, g_k, ξ^{k−1}) where there is one, else from
    // the previous step's outputs.
    let (mut state, mut xi) = (start(), c.xi);
    for s in &with {
        if let Some(cp) = reset.iter().find(|cp| cp.k == s.k) {
            (state, xi) = (cp.state, cp.xi);
        }
        assert_eq!(s.state, state, "step {}", s.k);
        let step = kin
            .law_step(&state, &xi, &c.mu, OnArcs::NONE, f64::PASSES)
            .unwrap();
        assert_eq!((s.u, s.xi), (step.u, step.xi), "step {}", s.k);
        (state, xi) = (step.next, step.xi);
    }
    // The checkpoint at k = 0 overrides the start and ξ^{−1}.
    assert_ne!(with[0].u, without[0].u);
    // A checkpoint holding exactly what the replay would have carries no change.
    let same = [Checkpoint {
        k: 11,
        state: without[11].state,
        xi: without[10].xi,
    }];
    assert_eq!(run(c, 30, &same), without);
}

#[test]
fn in_place_steps_match_the_iterator() {
    let c = costate_mu13();
    let mut replay = Replay::new(paper_kinematics::<f64>(), start(), c, 25, &[]).unwrap();
    let mut lent = Vec::new();
    while let Some(s) = replay.step().unwrap() {
        lent.push(*s);
    }
    assert_eq!(replay.step(), Ok(None));
    assert_eq!(lent, run(c, 25, &[]));
}

#[test]
fn replay_fuses_after_an_error() {
    // μ = 0 makes B = 0 and u = ξ = (120, 0) rad/s: α₁ grows by 1.2 per step (h = 0.01).
    let costate = Costate {
        mu: Vector3::zeros(),
        xi: Vector2::new(120.0, 0.0),
    };
    let mut replay = Replay::new(paper_kinematics(), start(), costate, 100, &[]).unwrap();
    let mut oks = 0;
    let err = loop {
        match replay.next() {
            Some(Ok(_)) => oks += 1,
            Some(Err(e)) => break e,
            None => panic!("ended without the expected error"),
        }
    };
    assert_eq!(err, Error::ShapeLimit);
    assert_eq!(
        replay.step(),
        Err(Error::ShapeLimit),
        "in-place stepping repeats the error"
    );
    assert_eq!(oks, 2); // α₁ = 0, 1.2, 2.4, then 3.6 > π
    let (state, done) = (*replay.state(), replay.steps_done());
    for _ in 0..5 {
        assert!(replay.next().is_none());
    }
    assert_eq!(replay.size_hint(), (0, Some(0)));
    // The failed step changed nothing: the state is the last good one.
    assert_eq!((*replay.state(), replay.steps_done()), (state, done));
    assert!(state.alpha.x < core::f64::consts::PI);
    // finish() reports the error.
    let replay = Replay::new(paper_kinematics(), start(), costate, 100, &[]).unwrap();
    assert_eq!(replay.finish(), Err(Error::ShapeLimit));
}

#[test]
fn finish_equals_the_last_state() {
    let kin = paper_kinematics::<f64>();
    let c = costate_mu4();
    let n = 500;
    let mut replay = Replay::new(kin, start(), c, n, &[]).unwrap();
    assert_eq!(replay.size_hint(), (0, Some(n as usize)));
    let samples: Vec<_> = replay.by_ref().collect::<Result<_, _>>().unwrap();
    assert_eq!(replay.steps_done(), n);
    let end = *replay.state();
    // (α_N, g_N) is the law applied to the last sample, from ξ^{N−2}.
    let [.., prev, last] = samples.as_slice() else {
        panic!("too few samples")
    };
    assert_eq!(
        kin.law_step(&last.state, &prev.xi, &c.mu, OnArcs::NONE, f64::PASSES)
            .unwrap()
            .next,
        end
    );
    // finish() on a fresh replay, and on a half-consumed one, reaches the same state.
    assert_eq!(
        Replay::new(kin, start(), c, n, &[]).unwrap().finish(),
        Ok(end)
    );
    let mut half = Replay::new(kin, start(), c, n, &[]).unwrap();
    half.by_ref().take(250).for_each(drop);
    assert_eq!(half.finish(), Ok(end));
    // Zero steps: finish() is the start state, and the iterator is empty.
    let empty = Replay::new(kin, start(), c, 0, &[]).unwrap();
    assert_eq!(empty.clone().count(), 0);
    assert_eq!(empty.finish(), Ok(start()));
}

/// A replay in f32 is bit-identical to the law stepped by hand from the same start, and to a
/// second replay built from scratch (not a clone, which would share its state).
#[test]
fn replay_in_f32_is_deterministic() {
    let c = costate_mu13();
    let c32 = costate_f32(&c);
    let kin = paper_kinematics::<f32>();
    let s32 = State::at_origin(Vector2::<f32>::zeros());
    let replayed = Replay::new(kin, s32, c32, 1000, &[])
        .unwrap()
        .finish()
        .unwrap();
    let again = Replay::new(paper_kinematics::<f32>(), s32, c32, 1000, &[])
        .unwrap()
        .finish()
        .unwrap();
    let (mut state, mut xi) = (s32, c32.xi);
    for _ in 0..1000 {
        let step = kin
            .law_step(&state, &xi, &c32.mu, OnArcs::NONE, f32::PASSES)
            .unwrap();
        (state, xi) = (step.next, step.xi);
    }
    assert_eq!(replayed, state);
    assert_eq!(again, state);
}
