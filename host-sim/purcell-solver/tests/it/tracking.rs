//! The gait under model error (docs/ROBUSTNESS.md): the tracking law against open loop on the
//! stored gaits of `core/examples` (the paper's, and the paper's under `|α_i| ≤ 1.5`).

use purcell_core::Gait;
use purcell_core::gait::{encode_with_tracking, encoded_len_with_tracking};
use purcell_solver::problem::Problem;
use purcell_solver::solver::continuation::{Warm, continue_to};
use purcell_solver::tracking::{
    Control, Design, Feedforward, Mismatch, Noise, Outcome, PlanError, Table, fly, joint_bound,
    nominal, table_of,
};

const PAPER: &[u8] = include_bytes!("../../../../core/examples/paper.gait");
const LIMIT: &[u8] = include_bytes!("../../../../core/examples/paper-limit.gait");

/// The gait's tracking table with the default design, and its nominal cost.
fn setup(gait: &Gait<'_>) -> (Table, f64) {
    let p = gait.params();
    let t = nominal(gait).unwrap();
    let design = Design {
        bound: joint_bound(p.alpha_max),
        ..Design::default()
    };
    let cost = t
        .controls
        .iter()
        .map(|u| 0.5 * p.h * u.norm_squared())
        .sum();
    (table_of(gait, &t, &design).unwrap().0, cost)
}

/// Open and closed loop through the plant of `mismatch` with `noise`.
fn both(gait: &Gait<'_>, table: &Table, mismatch: Mismatch, noise: Noise) -> [Outcome; 2] {
    let p = gait.params();
    let plant = mismatch.plant(&p.kinematics().unwrap()).unwrap();
    let limit = joint_bound(p.alpha_max);
    [Control::Open, Control::Closed { table, limit }].map(|control| {
        fly(
            gait.replay::<f64>().unwrap(),
            &plant,
            p.start(),
            control,
            &noise,
        )
        .unwrap()
    })
}

/// The larger component of the terminal error.
fn terminal(gait: &Gait<'_>, o: &Outcome) -> f64 {
    let e = gait.params().terminal_error(&o.end);
    e.alpha.max(e.g)
}

#[test]
fn closed_loop_lands_ten_times_closer_at_ten_percent_ratio_error() {
    for bytes in [PAPER, LIMIT] {
        let gait = Gait::from_bytes(bytes).unwrap();
        let (table, nominal_cost) = setup(&gait);
        let ratio = Mismatch {
            ratio: 0.1,
            ..Mismatch::default()
        };
        let [open, closed] = both(&gait, &table, ratio, Noise::default());
        let (o, c) = (terminal(&gait, &open), terminal(&gait, &closed));
        assert!(c * 10.0 <= o, "closed {c:e} against open {o:e}");
        // The law and the tracking law in f32 (the M4F's precision, the table rounded) land
        // where the f64 ones do, to a few percent.
        let p = gait.params();
        let plant = ratio.plant(&p.kinematics().unwrap()).unwrap();
        let limit = joint_bound(p.alpha_max);
        let control = Control::Closed {
            table: &table,
            limit,
        };
        let replay = gait.replay::<f32>().unwrap();
        let single = fly(replay, &plant, p.start(), control, &Noise::default()).unwrap();
        let s = terminal(&gait, &single);
        assert!((s / c - 1.0).abs() < 0.05, "f32 {s:e} against f64 {c:e}");
        // A larger drag ratio swims further per stroke: less effort than the nominal.
        assert!(
            closed.cost <= nominal_cost,
            "{} > {nominal_cost}",
            closed.cost
        );
        let bound = joint_bound(gait.params().alpha_max);
        assert!(closed.max_abs_alpha <= bound + 1e-12);
    }
}

#[test]
fn limits_hold_and_the_estimate_is_the_ratio_error() {
    let gait = Gait::from_bytes(LIMIT).unwrap();
    let (table, _) = setup(&gait);
    for ratio in [-0.2, -0.1, 0.1] {
        let m = Mismatch {
            ratio,
            ..Mismatch::default()
        };
        let [open, closed] = both(&gait, &table, m, Noise::default());
        assert!(
            closed.max_abs_alpha <= 1.5 + 1e-12,
            "{}",
            closed.max_abs_alpha
        );
        assert!(terminal(&gait, &closed) < terminal(&gait, &open));
    }
    // In the linear regime the running least-squares estimate recovers ε.
    let small = Mismatch {
        ratio: 1e-3,
        ..Mismatch::default()
    };
    let [_, closed] = both(&gait, &table, small, Noise::default());
    assert!(
        (closed.estimate / 1e-3 - 1.0).abs() < 0.05,
        "{}",
        closed.estimate
    );
}

/// `--plan`: the gain on `ε` from the plant's neighbouring extremal. At +5 % in `r` the paper's
/// gait then lands ten times closer than open loop for at most 1 % more than the plant's own
/// extremal costs (reached here by Newton from the gait on the plant's problem: the solver's
/// route, not the table's), where the LQR's own gain spends more; a gait with a joint limit
/// keeps the LQR's gain.
#[test]
fn the_neighbouring_extremal_gain_costs_what_the_plant_needs() {
    let gait = Gait::from_bytes(PAPER).unwrap();
    let p = gait.params();
    let design = Design {
        bound: joint_bound(p.alpha_max),
        plan: true,
        ..Design::default()
    };
    let (planned, source) = table_of(&gait, &nominal(&gait).unwrap(), &design).unwrap();
    assert_eq!(source, Feedforward::Extremal);
    let (lqr, nominal_cost) = setup(&gait);
    let m = Mismatch {
        ratio: 0.05,
        ..Mismatch::default()
    };
    let plant = m.plant(&p.kinematics().unwrap()).unwrap();
    let problem = Problem {
        swimmer: *plant.swimmer(),
        ..Problem::of_gait(p).unwrap()
    };
    let t = nominal(&gait).unwrap();
    let warm = Warm::from_trajectory(&t, &p.costate::<f64>().mu, problem.horizon()).unwrap();
    let own = continue_to(&problem, &warm).unwrap();
    assert!(own.admissible && own.cost < nominal_cost);
    let [open, closed] = both(&gait, &planned, m, Noise::default());
    let [_, by_lqr] = both(&gait, &lqr, m, Noise::default());
    assert!(terminal(&gait, &closed) * 10.0 <= terminal(&gait, &open));
    assert!(
        closed.cost <= own.cost * 1.01,
        "{} vs {}",
        closed.cost,
        own.cost
    );
    assert!(by_lqr.cost > closed.cost);
    let limited = Gait::from_bytes(LIMIT).unwrap();
    let (_, source) = table_of(
        &limited,
        &nominal(&limited).unwrap(),
        &Design {
            bound: 1.5,
            ..design
        },
    )
    .unwrap();
    assert_eq!(source, Feedforward::Lqr(PlanError::JointLimit));
}

#[test]
fn without_error_both_fly_the_nominal_and_drag_cancels() {
    let gait = Gait::from_bytes(PAPER).unwrap();
    let (table, nominal_cost) = setup(&gait);
    let [open, closed] = both(&gait, &table, Mismatch::default(), Noise::default());
    let (o, c) = (terminal(&gait, &open), terminal(&gait, &closed));
    assert!(o < 1e-8 && c < 1e-8, "open {o:e}, closed {c:e}");
    assert!((closed.cost / nominal_cost - 1.0).abs() < 1e-9);
    // k scales all forces alike: the same motion, to the bit.
    let drag = Mismatch {
        drag: 0.2,
        ..Mismatch::default()
    };
    let [open_k, _] = both(&gait, &table, drag, Noise::default());
    assert_eq!(open_k.end, open.end);
    // Noise moves the closed loop (a seeded draw: the same twice), not the open one.
    let noise = Noise {
        pose: 1e-4,
        shape: 1e-3,
        seed: 7,
    };
    let [open_n, noisy] = both(&gait, &table, Mismatch::default(), noise);
    let [_, again] = both(&gait, &table, Mismatch::default(), noise);
    assert_eq!(open_n.end, open.end);
    assert_eq!(noisy.end, again.end);
    // The joints end within a few standard deviations of their noise.
    assert!(noisy.end != closed.end && terminal(&gait, &noisy) < 5e-3);
}

/// The table stored in a gait file (`f32`, with each record's first step) flies the `f32`
/// closed loop exactly as the table computed in `f64`: the same digest, bit for bit.
#[test]
fn the_stored_table_flies_like_the_computed_one_in_f32() {
    let gait = Gait::from_bytes(LIMIT).unwrap();
    let (computed, _) = setup(&gait);
    let records = computed.to_f32();
    let (checkpoints, arcs): (Vec<_>, Vec<_>) =
        (gait.checkpoints().collect(), gait.arcs().collect());
    let mut bytes =
        vec![0; encoded_len_with_tracking(checkpoints.len(), arcs.len(), records.len())];
    encode_with_tracking(gait.params(), &checkpoints, &arcs, &records, &mut bytes).unwrap();
    let with_table = Gait::from_bytes(&bytes).unwrap();
    let stored = Table::stored(&with_table.tracking().unwrap());
    assert_eq!(stored.starts, computed.starts);
    let p = gait.params();
    let mismatch = Mismatch {
        ratio: 0.1,
        ..Mismatch::default()
    };
    let plant = mismatch.plant(&p.kinematics().unwrap()).unwrap();
    let [a, b] = [&computed, &stored].map(|table| {
        let control = Control::Closed {
            table,
            limit: joint_bound(p.alpha_max),
        };
        let replay = with_table.replay::<f32>().unwrap();
        fly(replay, &plant, p.start(), control, &Noise::default()).unwrap()
    });
    assert_eq!(a.digest, b.digest);
    assert_eq!(a, b);
    // The table's record steps: one every `D` from 0, then one per step over the tail.
    assert_eq!(&computed.starts[..2], &[0, Design::default().every]);
    assert_eq!(computed.starts.last(), Some(&(p.steps - 1)));
}
