//! Joint-limit arcs (MODEL.md §9): the arc table's checks, the law on an arc against the free
//! law with the limit's costate jump, the replay of real constrained solves (the committed
//! gaits `examples/paper-limit.gait` and `tests/data/tiny-limit.gait`, written by
//! `purcell-sim solve --alpha-max … && purcell-sim export`) against the solver's own states
//! at the arcs' exits, and no panic on any arc table.

use crate::common;

use common::*;
use nalgebra::{Vector2, Vector3};
use proptest::prelude::*;
use purcell_core::arc;
use purcell_core::gait::{self, CheckpointRecord, Gait};
use purcell_core::{Arc, Checkpoint, Error, Kinematics, OnArcs, Passes, Real, Replay, Se2, State};

static PAPER_LIMIT: &[u8] = include_bytes!("../../examples/paper-limit.gait");
static TINY_LIMIT: &[u8] = include_bytes!("../data/tiny-limit.gait");

fn arc(joint: u8, sign: i8, first: u32, last: u32) -> Arc {
    Arc {
        joint,
        sign,
        first,
        last,
    }
}

#[test]
fn arc_tables_are_checked() {
    let n = 100;
    assert_eq!(arc::check([], n), Ok(()));
    // Arcs of different joints may overlap; a touch point is an arc of one state.
    let ok = [
        arc(2, 1, 5, 20),
        arc(1, -1, 10, 30),
        arc(2, -1, 21, 21),
        arc(1, 1, 31, 99),
    ];
    assert_eq!(arc::check(ok, n), Ok(()));
    for bad in [
        arc(0, 1, 5, 6),
        arc(3, 1, 5, 6),
        arc(1, 0, 5, 6),
        arc(1, 2, 5, 6),
        arc(1, 1, 0, 6),
        arc(1, 1, 7, 6),
        arc(1, 1, 5, 100),
    ] {
        assert_eq!(arc::check([bad], n), Err(Error::ArcInvalid), "{bad:?}");
    }
    for bad in [
        [arc(1, 1, 10, 12), arc(2, 1, 9, 12)],   // not sorted by first
        [arc(2, 1, 10, 12), arc(1, 1, 10, 12)],  // not sorted by joint
        [arc(1, 1, 10, 12), arc(1, 1, 10, 12)],  // twice
        [arc(1, 1, 10, 12), arc(1, -1, 12, 14)], // one joint, a shared state
    ] {
        assert_eq!(arc::check(bad, n), Err(Error::ArcOrder), "{bad:?}");
    }
}

/// The committed tiny constrained gait, as numbers.
fn tiny() -> (gait::GaitParams, Vec<CheckpointRecord>, Vec<Arc>) {
    let g = Gait::from_bytes(TINY_LIMIT).unwrap();
    (*g.params(), g.checkpoints().collect(), g.arcs().collect())
}

/// `gait::check` with arcs: a checkpoint at each arc's exit, on the limit, none elsewhere but
/// at the multiples of `checkpoint_every`; an `α_max` that every checkpoint respects.
#[test]
fn gait_check_covers_the_arcs() {
    let (params, records, arcs) = tiny();
    let check = |p: &gait::GaitParams, r: &[CheckpointRecord], a: &[Arc]| {
        gait::check(p, r.iter().copied(), a.iter().copied())
    };
    assert_eq!(check(&params, &records, &arcs), Ok(()));
    assert_eq!(
        records.iter().map(|c| c.k).collect::<Vec<_>>(),
        [100, 137, 185, 200]
    );

    // The exit checkpoint of the first arc missing, or the arc's exit moved off it.
    let without: Vec<_> = records.iter().copied().filter(|c| c.k != 137).collect();
    assert_eq!(check(&params, &without, &arcs), Err(Error::ArcCheckpoint));
    let mut moved = arcs.clone();
    moved[0].last = 140;
    assert_eq!(
        check(&params, &records, &moved),
        Err(Error::CheckpointSpacing)
    );
    // A checkpoint neither periodic nor at an exit; a periodic one missing.
    let mut extra = records.clone();
    extra.insert(
        1,
        CheckpointRecord {
            k: 120,
            ..records[0]
        },
    );
    assert_eq!(check(&params, &extra, &arcs), Err(Error::CheckpointSpacing));
    let no_200: Vec<_> = records.iter().copied().filter(|c| c.k != 200).collect();
    assert_eq!(
        check(&params, &no_200, &arcs),
        Err(Error::CheckpointSpacing)
    );
    // The exit's joint off the limit, or the other sign.
    let mut off = records.clone();
    off[1].alpha[1] = 0.8 - 1e-6;
    assert_eq!(check(&params, &off, &arcs), Err(Error::ArcOffLimit));
    let mut flipped = arcs.clone();
    flipped[0].sign = -1;
    assert_eq!(check(&params, &records, &flipped), Err(Error::ArcOffLimit));
    // Arcs need a limit; checkpoints may not lie past it; the limit must be in ]|ᾱ|, π[.
    let unlimited = gait::GaitParams {
        alpha_max: None,
        ..params
    };
    assert_eq!(check(&unlimited, &records, &arcs), Err(Error::JointLimit));
    let periodic = [records[0], records[3]];
    assert_eq!(check(&unlimited, &periodic, &[]), Ok(()));
    let tighter = gait::GaitParams {
        alpha_max: Some(0.7),
        ..params
    };
    assert_eq!(check(&tighter, &records, &arcs), Err(Error::JointLimit));
    for bad in [0.0, -0.5, core::f64::consts::PI, f64::INFINITY] {
        let p = gait::GaitParams {
            alpha_max: Some(bad),
            ..params
        };
        assert_eq!(check(&p, &records, &arcs), Err(Error::JointLimit), "{bad}");
    }
    // An invalid table is refused before the checkpoints are looked at.
    let mut unsorted = arcs.clone();
    unsorted.swap(0, 1);
    assert_eq!(check(&params, &records, &unsorted), Err(Error::ArcOrder));
    // `encode` refuses what `check` refuses, and writes nothing.
    let mut out = vec![7u8; gait::encoded_len(records.len(), 2)];
    assert_eq!(
        gait::encode(&params, &without, &arcs, &mut out),
        Err(Error::ArcCheckpoint)
    );
    assert!(out.iter().all(|&b| b == 7));
}

/// A damaged arc record is refused: its padding (layout), its values (as `check`).
#[test]
fn damaged_arc_records_are_refused() {
    let reseal = |b: &mut Vec<u8>| {
        let n = b.len() - 4;
        let crc = gait::crc32(&b[..n]);
        b[n..].copy_from_slice(&crc.to_le_bytes());
    };
    let edit = |at: usize, v: u8| {
        let mut b = TINY_LIMIT.to_vec();
        b[at] = v;
        reseal(&mut b);
        Gait::from_bytes(&b).err()
    };
    // ARCS at 224: joint, sign, pad, pad, first, last.
    assert_eq!(edit(224, 3), Some(Error::ArcInvalid));
    assert_eq!(edit(225, 0), Some(Error::ArcInvalid));
    assert_eq!(edit(226, 1), Some(Error::GaitLayout));
    assert_eq!(edit(224, 1), Some(Error::ArcOffLimit));
    assert_eq!(edit(228, 200), Some(Error::ArcInvalid));
    // The second arc's last moved to 186: its checkpoint at 185 is then neither.
    assert_eq!(edit(244, 186), Some(Error::CheckpointSpacing));
}

/// The replay of a constrained gait in f64: on every arc step the joint rests (`u_i = 0`
/// exactly, `α_i` unchanged bit for bit), and at every arc's exit the replayed state, before
/// the exit's checkpoint replaces it, is the solver's state there (the checkpoint), with the
/// other joint's costate too. Returns the largest deviation in `α`, `g` and that `ξ_j`.
fn exits_follow_the_solution(bytes: &[u8]) -> [f64; 3] {
    let gait = Gait::from_bytes(bytes).unwrap();
    let arcs: Vec<Arc> = gait.arcs().collect();
    let exits: Vec<CheckpointRecord> = gait
        .checkpoints()
        .filter(|c| arcs.iter().any(|a| a.last == c.k))
        .collect();
    assert_eq!(exits.len(), arcs.len());
    let mut replay = gait.replay::<f64>().unwrap();
    let mut worst = [0.0f64; 3];
    let mut arc_steps = 0;
    loop {
        let k = replay.steps_done();
        if let Some(c) = exits.iter().find(|c| c.k == k) {
            let (s, xi) = (replay.state(), replay.xi());
            let da = (s.alpha - Vector2::from(c.alpha)).amax();
            let dg = se2_distance(&s.g, &Se2::from_rotation(c.g[0], c.g[1], c.g[2], c.g[3]));
            // ξ_j of a joint off its limit at k carries no jump.
            let free = |j: usize| {
                !arcs
                    .iter()
                    .any(|a| a.index_of() == j && a.first <= k && k <= a.last)
            };
            let dxi = (0..2)
                .filter(|&j| free(j))
                .map(|j| (xi[j] - c.xi[j]).abs() / c.xi[j].abs().max(1.0))
                .fold(0.0, f64::max);
            for (w, d) in worst.iter_mut().zip([da, dg, dxi]) {
                *w = w.max(d);
            }
        }
        let Some(sample) = replay.step().unwrap() else {
            break;
        };
        let (u, sample_alpha) = (sample.u, sample.state.alpha);
        for a in arcs.iter().filter(|a| a.first <= k && k < a.last) {
            let i = a.index_of();
            assert_eq!(u[i], 0.0, "k {k} {a:?}");
            assert_eq!(replay.state().alpha[i], sample_alpha[i], "k {k} {a:?}");
            arc_steps += 1;
        }
    }
    assert!(arc_steps > 0);
    worst
}

trait Index {
    fn index_of(&self) -> usize;
}
impl Index for Arc {
    fn index_of(&self) -> usize {
        usize::from(self.joint) - 1
    }
}

#[test]
fn arc_steps_follow_the_solver_to_its_exits() {
    // Measured: paper 8.6e-14, 3.1e-14, 5.5e-15; tiny 6.3e-10, 1.7e-10, 9.5e-11 (its
    // solution is that far from the law: the solver's law residual there is 1.6e-10).
    let paper = exits_follow_the_solution(PAPER_LIMIT);
    assert!(paper.iter().all(|&d| d < 1e-12), "{paper:?}");
    let tiny = exits_follow_the_solution(TINY_LIMIT);
    assert!(tiny.iter().all(|&d| d < 1e-8), "{tiny:?}");
}

/// The committed constrained gaits land on `(ᾱ, ḡ)`: in f64 to `1e-12`, in f32 with their
/// checkpoints to `1e-6`; without the periodic ones (only the arcs' exits) f64 still does.
#[test]
fn the_paper_limit_gait_lands_on_target() {
    let gait = Gait::from_bytes(PAPER_LIMIT).unwrap();
    assert_eq!((gait.params().alpha_max, gait.arc_count()), (Some(1.5), 5));
    let p = gait.params();
    let f64_end = gait.replay::<f64>().unwrap().finish().unwrap();
    let f32_end = gait.replay::<f32>().unwrap().finish().unwrap();
    let exits_only = gait
        .replay_without_checkpoints::<f64>()
        .unwrap()
        .finish()
        .unwrap();
    for (name, e, bound) in [
        ("f64", p.terminal_error(&f64_end), 1e-12),
        ("f32", p.terminal_error(&f32_end), 1e-6),
        ("f64, exits only", p.terminal_error(&exits_only), 1e-11),
    ] {
        assert!(e.alpha < bound && e.g < bound, "{name}: {e:?}");
    }
}

/// Without its periodic checkpoints a constrained gait restores exactly those at the arcs'
/// exits; stored tables replay like the same tables in memory.
#[test]
fn replays_from_stored_tables_and_from_memory_agree() {
    let gait = Gait::from_bytes(PAPER_LIMIT).unwrap();
    let arcs: Vec<Arc> = gait.arcs().collect();
    let p = gait.params();
    let all: Vec<Checkpoint<f32>> = gait.checkpoints().map(|c| c.to_checkpoint()).collect();
    let exits: Vec<Checkpoint<f32>> = all
        .iter()
        .copied()
        .filter(|c| arcs.iter().any(|a| a.last == c.k))
        .collect();
    let memory = |cps: &[Checkpoint<f32>], arcs: &[Arc]| fly(Ok(replay_in_memory(p, cps, arcs)));
    let stored = fly(gait.replay::<f32>()).unwrap();
    let exits_only = fly(gait.replay_without_checkpoints::<f32>()).unwrap();
    assert_eq!(Ok(stored), memory(&all, &arcs));
    assert_eq!(Ok(exits_only), memory(&exits, &arcs));
    assert_ne!(stored, exits_only);
    // Without the arc table the same costate is the free law: another flight.
    assert_ne!(memory(&all, &[]), Ok(stored));
}

#[test]
fn replay_refuses_bad_arc_tables() {
    let kin = paper_kinematics::<f64>();
    let start = State::at_origin(Vector2::zeros());
    let c = costate_mu13();
    let cp = |k| Checkpoint {
        k,
        state: start,
        xi: Vector2::zeros(),
    };
    let run = |cps: &[Checkpoint<f64>], arcs: &[Arc]| {
        Replay::with_arcs(kin, start, c, 50, cps, arcs).err()
    };
    assert_eq!(run(&[cp(20)], &[arc(1, 1, 10, 20)]), None);
    assert_eq!(
        run(&[cp(21)], &[arc(1, 1, 10, 20)]),
        Some(Error::ArcCheckpoint)
    );
    assert_eq!(run(&[], &[arc(1, 1, 10, 20)]), Some(Error::ArcCheckpoint));
    assert_eq!(
        run(&[cp(20)], &[arc(1, 1, 10, 50)]),
        Some(Error::ArcInvalid)
    );
    assert_eq!(
        run(&[cp(20), cp(30)], &[arc(1, 1, 25, 30), arc(1, 1, 10, 20)]),
        Some(Error::ArcOrder)
    );
}

/// Newton passes enough to reach the law's root to rounding for any input of the tests.
const TO_ROUNDING: Passes = Passes::newton(4);

/// The free law's input `ξ̃^{k−1}` with its joint-`i` component solved (secant, to rounding)
/// so that the free law's `u_i` is 0: the costate with the limit's jump (MODEL.md §9).
/// `None` if the free law refuses an iterate (a step past the overlap limit).
fn jumped_costate(
    kin: &Kinematics<f64>,
    s: &State<f64>,
    xi: &Vector2<f64>,
    mu: &Vector3<f64>,
    i: usize,
) -> Option<Vector2<f64>> {
    let with = |x: f64| {
        let mut v = *xi;
        v[i] = x;
        v
    };
    let ui = |x: f64| {
        Some(
            kin.law_step(s, &with(x), mu, OnArcs::NONE, TO_ROUNDING)
                .ok()?
                .u[i],
        )
    };
    // u_i is about ξ̃_i − (Aᵀζ)_i: start with that slope, then secant steps, keeping the
    // iterate with the least |u_i| (near the root a secant through two rounding-level values
    // may jump far off it).
    let a = xi[i];
    let fa = ui(a)?;
    let (mut a, mut fa, mut b) = (a, fa, a - fa);
    let mut fb = ui(b)?;
    let mut best = if fb.abs() < fa.abs() {
        (b, fb)
    } else {
        (a, fa)
    };
    for _ in 0..8 {
        if fb == fa {
            break;
        }
        let c = b - fb * (b - a) / (fb - fa);
        (a, fa, b) = (b, fb, c);
        fb = ui(b)?;
        if fb.abs() < best.1.abs() {
            best = (b, fb);
        }
    }
    Some(with(best.0))
}

proptest! {
    #![proptest_config(proptest_config())]

    /// On an arc of joint `i` the step is the free law fed the costate with the limit's jump
    /// (which makes its `u_i` zero): the same `u_j`, next state and `ξ^k` (MODEL.md §9), both
    /// solved to rounding; with the type's passes, to what they leave of the root.
    #[test]
    fn an_arc_step_is_the_free_law_with_the_jump(
        a in alpha(), g in se2(), xi in (-20.0..20.0f64, -20.0..20.0f64),
        mu in (-15.0..15.0f64, -15.0..15.0f64, -3.0..3.0f64), i in 0usize..2,
    ) {
        let kin = paper_kinematics::<f64>();
        let s = State { alpha: a, g };
        let (xi, mu) = (Vector2::new(xi.0, xi.1), Vector3::new(mu.0, mu.1, mu.2));
        let mut on = [false; 2];
        on[i] = true;
        // (A step of the other joint past the overlap limit is refused, as by the free law.)
        let arc = kin.law_step(&s, &xi, &mu, OnArcs(on), TO_ROUNDING);
        prop_assume!(arc != Err(Error::ShapeLimit));
        let arc = arc.unwrap();
        prop_assert_eq!(arc.u[i], 0.0);
        prop_assert_eq!(arc.next.alpha[i], a[i]);
        let jumped = jumped_costate(&kin, &s, &xi, &mu, i);
        prop_assume!(jumped.is_some());
        let jumped = jumped.unwrap();
        let free = kin.law_step(&s, &jumped, &mu, OnArcs::NONE, TO_ROUNDING).unwrap();
        let scale = 1.0 + arc.u.amax();
        prop_assert!(free.u[i].abs() < 1e-12 * scale, "{:?}", free.u);
        prop_assert!((free.u - arc.u).amax() < 1e-12 * scale, "{:?} {:?}", free.u, arc.u);
        prop_assert!((free.next.alpha - arc.next.alpha).amax() < 1e-13 * scale);
        prop_assert!(se2_distance(&free.next.g, &arc.next.g) < 1e-13 * scale);
        let xi_scale = 1.0 + arc.xi.amax();
        prop_assert!((free.xi - arc.xi).amax() < 1e-12 * xi_scale, "{:?} {:?}", free.xi, arc.xi);
        // The type's single pass at a gait's speeds (|u| ≤ 5 rad/s; the paper's gaits stay
        // below 3): the same root to what it leaves (a wrong row or ζ would be off by about
        // h|B||u|, 1e-2 of u).
        if scale <= 6.0 {
            let one = kin.law_step(&s, &xi, &mu, OnArcs(on), f64::PASSES).unwrap();
            prop_assert!((one.u - arc.u).amax() < 1e-9 * scale, "{:?} {:?}", one.u, arc.u);
        }
    }

    /// Both joints on arcs: the swimmer rests (`u = 0`, the state unchanged), and the costate
    /// is `Aᵀm`, both rows made to hold.
    #[test]
    fn both_joints_on_arcs_rest(a in alpha(), g in se2(), xi in (-20.0..20.0f64, -20.0..20.0f64)) {
        let kin = paper_kinematics::<f64>();
        let s = State { alpha: a, g };
        let mu = Vector3::new(1.5, 13.2, 0.6);
        let xi = Vector2::new(xi.0, xi.1);
        let step = kin.law_step(&s, &xi, &mu, OnArcs([true; 2]), f64::PASSES).unwrap();
        prop_assert_eq!(step.u, Vector2::zeros());
        prop_assert_eq!(step.next.alpha, a);
        prop_assert!(se2_distance(&step.next.g, &g) < 1e-15);
        let conn = kin.swimmer().connection(&a).unwrap();
        let atm = conn.transpose() * g.adjoint_transpose_mul(&mu);
        prop_assert!((step.xi - atm).amax() < 1e-12 * (1.0 + atm.amax()));
    }

    /// Any arc table and checkpoint list: a replay is refused with a typed error or runs to
    /// its end or to a step's error, and never panics; when it runs, no joint on an arc moves.
    #[test]
    fn arbitrary_arc_tables_never_panic(
        raw in proptest::collection::vec((0u8..4, -2i8..3, 0u32..40, 0u32..40), 0..6),
        ks in proptest::collection::vec(0u32..40, 0..6),
        steps in 0u32..40,
    ) {
        let arcs: Vec<Arc> = raw.iter().map(|&(j, s, f, l)| arc(j, s, f, l)).collect();
        let start = State::at_origin(Vector2::new(0.3f32, -0.2));
        let cps: Vec<Checkpoint<f32>> = ks
            .iter()
            .map(|&k| Checkpoint { k, state: start, xi: Vector2::new(0.1, -0.1) })
            .collect();
        let costate = purcell_core::Costate { mu: Vector3::new(0.5f32, 1.0, 0.2), xi: Vector2::new(0.3, -0.1) };
        if let Ok(mut replay) = Replay::with_arcs(paper_kinematics::<f32>(), start, costate, steps, &cps, &arcs) {
            prop_assert!(arc::check(arcs.iter().copied(), steps).is_ok());
            while let Ok(Some(s)) = replay.step() {
                for a in arcs.iter().filter(|a| a.first <= s.k && s.k < a.last) {
                    prop_assert_eq!(s.u[a.index_of()], 0.0);
                }
            }
        }
    }

    /// Valid arc tables by construction (per joint, disjoint arcs in order; both joints
    /// merged by `(first, joint)`; a checkpoint at every exit, plus random ones): the replay
    /// accepts every one and runs to its end; on an arc its joint rests, and at each
    /// checkpoint the replay stands on the checkpoint's state.
    #[test]
    fn valid_arc_tables_replay_with_their_joints_at_rest(
        steps in 2u32..40,
        runs in [
            proptest::collection::vec((0u32..6, 0u32..6, any::<bool>()), 0..4),
            proptest::collection::vec((0u32..6, 0u32..6, any::<bool>()), 0..4),
        ],
        extra in proptest::collection::vec(0u32..40, 0..4),
    ) {
        let mut arcs = Vec::new();
        for (joint, runs) in (1u8..=2).zip(&runs) {
            // Each arc starts `gap + 1` states after the previous one's last state (or after
            // state 0), and lasts `len` steps; arcs that would reach `steps` are dropped.
            let mut end = 0;
            for &(gap, len, upper) in runs {
                let first = end + gap + 1;
                let last = first + len;
                if last >= steps {
                    break;
                }
                arcs.push(arc(joint, if upper { 1 } else { -1 }, first, last));
                end = last;
            }
        }
        arcs.sort_by_key(|a| (a.first, a.joint));
        prop_assert_eq!(arc::check(arcs.iter().copied(), steps), Ok(()));
        let mut ks: Vec<u32> = arcs.iter().map(|a| a.last).chain(extra).filter(|&k| k < steps).collect();
        ks.sort_unstable();
        ks.dedup();
        let at = |k: u32| State::at_origin(Vector2::new(0.3f32 - 0.01 * k as f32, -0.2));
        let cps: Vec<Checkpoint<f32>> = ks
            .iter()
            .map(|&k| Checkpoint { k, state: at(k), xi: Vector2::new(0.1, -0.1) })
            .collect();
        let costate = purcell_core::Costate { mu: Vector3::new(0.5f32, 1.0, 0.2), xi: Vector2::new(0.3, -0.1) };
        let mut replay = Replay::with_arcs(paper_kinematics::<f32>(), at(0), costate, steps, &cps, &arcs)
            .expect("a valid table is accepted");
        let mut previous: Option<purcell_core::Sample<f32>> = None;
        let mut count = 0;
        while let Some(s) = replay.step().expect("no step fails") {
            let restored = cps.iter().find(|c| c.k == s.k);
            if let Some(c) = restored {
                prop_assert_eq!(s.state, c.state);
            }
            for a in arcs.iter().filter(|a| a.first <= s.k && s.k < a.last) {
                let i = a.index_of();
                prop_assert_eq!(s.u[i], 0.0);
                if let Some(p) = previous.filter(|_| s.k > a.first && restored.is_none()) {
                    prop_assert_eq!(s.state.alpha[i], p.state.alpha[i]);
                }
            }
            previous = Some(*s);
            count += 1;
        }
        prop_assert_eq!(count, steps);
    }

    /// Any bytes in the arc table of a valid file (resealed): refused with a typed error or
    /// read and replayed, never a panic.
    #[test]
    fn arbitrary_arc_records_never_panic(at in 224usize..248, byte in any::<u8>()) {
        let mut b = TINY_LIMIT.to_vec();
        b[at] = byte;
        let n = b.len() - 4;
        let crc = gait::crc32(&b[..n]);
        b[n..].copy_from_slice(&crc.to_le_bytes());
        if let Ok(g) = Gait::from_bytes(&b) {
            let _ = g.replay::<f32>().and_then(|r| r.finish());
            let _ = g.replay_without_checkpoints::<f64>().and_then(|r| r.finish());
        }
    }
}
