//! Bad input reaches every variant of `purcell_core::Error` through the public API, and no
//! function panics on any input: garbage (NaN, ±∞, huge, subnormal, at the limits) gives
//! `Ok` or `Err`, and every `Ok` is finite and admissible.

use crate::common;

use common::*;
use core::f64::consts::PI;
use nalgebra::{Vector2, Vector3};
use proptest::prelude::*;
use purcell_core::{
    Checkpoint, Checkpoints, Costate, Error, Kinematics, OnArcs, Passes, Real, Replay, Se2, State,
    Swimmer, se2,
};

fn kin() -> Kinematics<f64> {
    paper_kinematics::<f64>()
}

#[test]
fn non_finite_input_is_refused_everywhere() {
    let sw = Swimmer::<f64>::purcell();
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let alpha = Vector2::new(0.1, bad);
        assert_eq!(sw.connection(&alpha), Err(Error::NonFinite));
        assert_eq!(
            sw.connection_with_derivatives(&alpha),
            Err(Error::NonFinite)
        );
        let ok = State::at_origin(Vector2::new(0.1, 0.2));
        let nan_g = State {
            alpha: ok.alpha,
            g: Se2::new(bad, 0.0, 0.0),
        };
        assert_eq!(nan_g.check(), Err(Error::NonFinite));
        assert_eq!(kin().step(&nan_g, &Vector2::zeros()), Err(Error::NonFinite));
        assert_eq!(
            kin().step(&ok, &Vector2::new(bad, 0.0)),
            Err(Error::NonFinite)
        );
        let (xi, mu) = (Vector2::zeros(), Vector3::new(1.0, 2.0, 3.0));
        assert_eq!(
            kin().law_step(&nan_g, &xi, &mu, OnArcs::NONE, f64::PASSES),
            Err(Error::NonFinite)
        );
        assert_eq!(
            kin().law_step(&ok, &Vector2::new(0.0, bad), &mu, OnArcs::NONE, f64::PASSES),
            Err(Error::NonFinite)
        );
        assert_eq!(
            kin().law_step(
                &ok,
                &xi,
                &Vector3::new(0.0, 0.0, bad),
                OnArcs::NONE,
                f64::PASSES
            ),
            Err(Error::NonFinite)
        );
        let costate = Costate {
            mu: Vector3::new(bad, 0.0, 0.0),
            xi,
        };
        assert_eq!(
            Replay::new(kin(), ok, costate, 10, &[]).err(),
            Some(Error::NonFinite)
        );
        let costate = Costate { mu, xi };
        let cp = [Checkpoint {
            k: 3,
            state: ok,
            xi: Vector2::new(bad, 0.0),
        }];
        assert_eq!(
            Replay::new(kin(), ok, costate, 10, &cp).err(),
            Some(Error::NonFinite)
        );
        let mut table = Checkpoints::<f64, 4>::new();
        assert_eq!(table.push(cp[0]), Err(Error::NonFinite));
        assert!(table.as_slice().is_empty());
    }
}

#[test]
fn shapes_at_or_past_the_overlap_limit_are_refused() {
    let sw = Swimmer::<f64>::purcell();
    for alpha in [
        Vector2::new(PI, 0.0),
        Vector2::new(0.0, -PI),
        Vector2::new(4.0, 0.0),
        Vector2::new(-1e300, 1e300),
    ] {
        assert_eq!(sw.connection(&alpha), Err(Error::ShapeLimit));
        let s = State::at_origin(alpha);
        assert_eq!(s.check(), Err(Error::ShapeLimit));
        let mu = Vector3::new(1.0, 0.0, 0.0);
        assert_eq!(
            kin().law_step(&s, &Vector2::zeros(), &mu, OnArcs::NONE, f64::PASSES),
            Err(Error::ShapeLimit)
        );
        let c = Costate {
            mu,
            xi: Vector2::zeros(),
        };
        assert_eq!(
            Replay::new(kin(), s, c, 5, &[]).err(),
            Some(Error::ShapeLimit)
        );
    }
    // f32: π rounds to a value above π, so the largest f32 below π is the last admissible.
    let sw32 = Swimmer::<f32>::purcell();
    assert_eq!(
        sw32.connection(&Vector2::new(core::f32::consts::PI, 0.0)),
        Err(Error::ShapeLimit)
    );
    assert!(sw32.connection(&Vector2::new(3.1415925f32, 0.0)).is_ok());
    // A step that would end past the limit is refused too (α_{k+1} = 3.1 + 0.01·10 > π).
    let s = State::at_origin(Vector2::new(3.1, 0.0));
    assert_eq!(
        kin().step(&s, &Vector2::new(10.0, 0.0)),
        Err(Error::ShapeLimit)
    );
    let xi = Vector2::new(1e3, 0.0); // u ≈ ξ ≈ 1e3 rad/s: the law also ends past π.
    assert_eq!(
        kin().law_step(&s, &xi, &Vector3::zeros(), OnArcs::NONE, f64::PASSES),
        Err(Error::ShapeLimit)
    );
}

#[test]
fn invalid_parameters_are_refused() {
    for bad in [0.0, -0.0, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(
            Swimmer::new([bad, 1.0, 1.0], 1.0, 2.0),
            Err(Error::InvalidParameters)
        );
        assert_eq!(
            Swimmer::new([1.0, bad, 1.0], 1.0, 2.0),
            Err(Error::InvalidParameters)
        );
        assert_eq!(
            Swimmer::new([1.0, 1.0, bad], 1.0, 2.0),
            Err(Error::InvalidParameters)
        );
        assert_eq!(
            Swimmer::new([1.0, 1.0, 1.0], bad, 2.0),
            Err(Error::InvalidParameters)
        );
        assert_eq!(
            Swimmer::new([1.0, 1.0, 1.0], 1.0, bad),
            Err(Error::InvalidParameters)
        );
    }
    assert_eq!(
        Swimmer::new([1.0f32, 1.0, 1.0], 1.0, f32::NAN),
        Err(Error::InvalidParameters)
    );
    let sw = Swimmer::new([0.5, 1.5, 2.0], 3.0, 1.5).unwrap();
    assert_eq!(
        (sw.lengths(), sw.drag(), sw.ratio()),
        ([0.5, 1.5, 2.0], 3.0, 1.5)
    );
}

#[test]
fn invalid_time_steps_are_refused() {
    for h in [0.0, -0.0, -0.01, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(
            Kinematics::new(Swimmer::purcell(), h),
            Err(Error::InvalidStep)
        );
    }
    assert_eq!(
        Kinematics::new(Swimmer::<f32>::purcell(), -1.0),
        Err(Error::InvalidStep)
    );
    assert_eq!(
        Kinematics::new(Swimmer::<f64>::purcell(), 1e-300).map(|k| k.h()),
        Ok(1e-300)
    );
}

/// The first iterate's matrix `M = I − hB(m) − (h/2)κ·[[0, 1], [−1, 0]]` (see `law.rs`) is
/// singular when `|μ|` is large enough. At `α = 0`, `g = e`, `μ = (s, 0, 0)`: `hB = t·[[−4, 2],
/// [−2, 4]]` with `t = sh/27` (MODEL §7's `∂A/∂α`) and `(h/2)κ = −(7/6)t` (`A` of MODEL §7), so
/// `det M = (1 + 4t)(1 − 4t) + (5t/6)² = 1 − (551/36)t²` vanishes at `s = 162/(h√551)`.
#[test]
fn singular_control_law_matrix_is_refused() {
    let h = 0.01;
    let s = 162.0 / (h * 551f64.sqrt());
    let state = State::at_origin(Vector2::zeros());
    let mu = Vector3::new(s, 0.0, 0.0);
    assert_eq!(
        kin().law_step(&state, &Vector2::zeros(), &mu, OnArcs::NONE, f64::PASSES),
        Err(Error::Singular)
    );
    assert_eq!(
        kin().law_step(
            &state,
            &Vector2::zeros(),
            &mu,
            OnArcs::NONE,
            Passes::plain(0)
        ),
        Err(Error::Singular)
    );
    // 10% away from the root the step goes through.
    let mu = Vector3::new(0.9 * s, 0.0, 0.0);
    assert!(
        kin()
            .law_step(
                &state,
                &Vector2::zeros(),
                &mu,
                OnArcs::NONE,
                Passes::plain(0)
            )
            .is_ok()
    );
    // f32 as well (the root rounded to f32 leaves |det| ≈ 1e-7 < the 1e-6 threshold).
    let k32 = paper_kinematics::<f32>();
    let s32 = State::at_origin(Vector2::<f32>::zeros());
    let mu32 = Vector3::new(s as f32, 0.0, 0.0);
    assert_eq!(
        k32.law_step(&s32, &Vector2::zeros(), &mu32, OnArcs::NONE, f32::PASSES),
        Err(Error::Singular)
    );
}

/// A drag matrix that overflows (a link so long that `L³` is infinite) is refused as
/// singular rather than producing ∞ or NaN.
#[test]
fn degenerate_drag_matrix_is_refused() {
    let sw = Swimmer::new([1e200, 1.0, 1.0], 1.0, 2.0).unwrap();
    assert_eq!(sw.connection(&Vector2::new(0.1, 0.2)), Err(Error::Singular));
    let sw = Swimmer::new([1.0f32, 1e13, 1.0], 1.0, 2.0).unwrap();
    assert_eq!(
        sw.connection_with_derivatives(&Vector2::new(0.1, 0.2)),
        Err(Error::Singular)
    );
    let kin = Kinematics::new(sw, 0.01).unwrap();
    let s = State::at_origin(Vector2::new(0.1f32, 0.2));
    assert_eq!(kin.step(&s, &Vector2::new(1.0, 1.0)), Err(Error::Singular));
}

/// Issue 9: a state whose rotation is not one (`(cos, sin) = (3, 0)`) is refused where
/// states enter the core (it came back as `Ok` samples with `cos = −9`); the tolerance is
/// far above rounding (every `f64` rotation rounded to `f32` passes).
#[test]
fn a_non_unit_rotation_is_refused_where_states_enter_the_core() {
    let bad = State {
        alpha: Vector2::new(0.1, 0.2),
        g: Se2::from_rotation(0.0, 0.0, 3.0, 0.0),
    };
    let ok = State::at_origin(bad.alpha);
    let (xi, mu) = (Vector2::new(0.1, 0.2), Vector3::new(1.0, 2.0, 0.5));
    let costate = Costate { mu, xi };
    let cp = [Checkpoint {
        k: 3,
        state: bad,
        xi,
    }];
    let refused = Some(Error::NotRotation);
    assert_eq!(bad.check().err(), refused);
    assert_eq!(kin().step(&bad, &xi).err(), refused);
    assert_eq!(
        kin()
            .law_step(&bad, &xi, &mu, OnArcs::NONE, f64::PASSES)
            .err(),
        refused
    );
    assert_eq!(Replay::new(kin(), bad, costate, 10, &[]).err(), refused);
    assert_eq!(Replay::new(kin(), ok, costate, 10, &cp).err(), refused);
    let mut table = Checkpoints::<f64, 4>::new();
    assert_eq!(table.push(cp[0]).err(), refused);
    assert!(table.as_slice().is_empty());

    let tol = purcell_core::kinematics::UNIT_ROTATION_TOLERANCE;
    let off_by = |e: f64| State {
        alpha: ok.alpha,
        g: Se2::from_rotation(0.0, 0.0, (1.0 + e).sqrt(), 0.0),
    };
    for e in [0.9 * tol, -0.9 * tol] {
        assert_eq!(off_by(e).check(), Ok(()), "{e}");
    }
    for e in [1.1 * tol, -1.1 * tol] {
        assert_eq!(off_by(e).check().err(), refused, "{e}");
    }
    for i in 0..=100_000 {
        let g = Se2::<f64>::new(0.0, 0.0, -PI + 2.0 * PI * f64::from(i) / 1e5);
        let g32 = Se2::from_rotation(0.0f32, 0.0, g.cos() as f32, g.sin() as f32);
        let s = State {
            alpha: Vector2::new(0.1f32, 0.2),
            g: g32,
        };
        assert_eq!(s.check(), Ok(()), "{g:?}");
    }
}

/// A valid checkpoint at step `k`: `α = 0` at the identity, `ξ = (0.1, 0.2)`.
fn checkpoint_at_rest<T: Real>(k: u32) -> Checkpoint<T> {
    Checkpoint {
        k,
        state: State::at_origin(Vector2::zeros()),
        xi: Vector2::new(T::from_f64(0.1), T::from_f64(0.2)),
    }
}

#[test]
fn checkpoints_out_of_order_or_beyond_the_horizon_are_refused() {
    let cp = checkpoint_at_rest::<f64>;
    let mut table = Checkpoints::<f64, 8>::new();
    table.push(cp(5)).unwrap();
    assert_eq!(table.push(cp(5)), Err(Error::CheckpointOrder));
    assert_eq!(table.push(cp(3)), Err(Error::CheckpointOrder));
    assert_eq!(table.as_slice(), &[cp(5)]);
    table.push(cp(9)).unwrap();
    let (s, c) = (
        State::at_origin(Vector2::zeros()),
        Costate {
            mu: Vector3::new(1.0, 2.0, 0.5),
            xi: Vector2::zeros(),
        },
    );
    assert!(Replay::new(kin(), s, c, 10, table.as_slice()).is_ok());
    // k must be below the number of steps.
    assert_eq!(
        Replay::new(kin(), s, c, 9, table.as_slice()).err(),
        Some(Error::CheckpointOrder)
    );
    // A hand-made slice must be strictly increasing too.
    for bad in [[cp(4), cp(2)], [cp(4), cp(4)]] {
        assert_eq!(
            Replay::new(kin(), s, c, 10, &bad).err(),
            Some(Error::CheckpointOrder)
        );
    }
}

#[test]
fn full_checkpoint_table_is_refused_and_unchanged() {
    let cp = checkpoint_at_rest::<f32>;
    let mut table = Checkpoints::<f32, 2>::new();
    table.push(cp(1)).unwrap();
    table.push(cp(2)).unwrap();
    assert_eq!(table.push(cp(3)), Err(Error::CapacityExceeded));
    assert_eq!(table.as_slice(), &[cp(1), cp(2)]);
    let mut empty = Checkpoints::<f64, 0>::new();
    let zero = Checkpoint {
        k: 0,
        state: State::at_origin(Vector2::zeros()),
        xi: Vector2::zeros(),
    };
    assert_eq!(empty.push(zero), Err(Error::CapacityExceeded));
}

#[test]
fn every_error_has_a_distinct_message() {
    let all = [
        Error::NonFinite,
        Error::ShapeLimit,
        Error::InvalidParameters,
        Error::InvalidStep,
        Error::Singular,
        Error::CheckpointOrder,
        Error::CapacityExceeded,
        Error::CheckpointSpacing,
        Error::NotRotation,
        Error::GaitMagic,
        Error::GaitVersion(7),
        Error::GaitLength,
        Error::GaitChecksum,
        Error::GaitLayout,
        Error::ArcInvalid,
        Error::ArcOrder,
        Error::ArcCheckpoint,
        Error::ArcOffLimit,
        Error::JointLimit,
    ];
    assert!(Error::GaitVersion(7).to_string().contains("version 7"));
    let msgs: Vec<String> = all.iter().map(|e| e.to_string()).collect();
    for (i, m) in msgs.iter().enumerate() {
        assert!(!m.is_empty());
        assert!(
            msgs.iter().skip(i + 1).all(|n| n != m),
            "duplicate message {m}"
        );
    }
    let _: &dyn core::error::Error = &Error::Singular;
}

/// Any f64: literally arbitrary bit patterns (NaN, ±∞, subnormals) half of the time, else
/// values at the edges of what the core accepts.
fn wild() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => any::<f64>(),
        1 => prop::sample::select(vec![
            f64::NAN, f64::INFINITY, f64::NEG_INFINITY, f64::MAX, f64::MIN, f64::MIN_POSITIVE,
            0.0, -0.0, 1e300, -1e300, 1e-300, PI, -PI, PI - 1e-15, 1e10, -1e10,
        ]),
        3 => -10.0..10.0f64,
        2 => -3.2..3.2f64,
    ]
}

fn wild2() -> impl Strategy<Value = Vector2<f64>> {
    (wild(), wild()).prop_map(|(a, b)| Vector2::new(a, b))
}

fn wild3() -> impl Strategy<Value = Vector3<f64>> {
    (wild(), wild(), wild()).prop_map(|(a, b, c)| Vector3::new(a, b, c))
}

/// An `Ok` from the core is finite and admissible, its rotation one.
fn sane<T: Real>(s: &State<T>) -> bool {
    s.check().is_ok()
}

/// Calls every fallible entry point on the given numbers in the scalar `T`.
#[allow(clippy::too_many_arguments)]
fn exercise<T: Real>(
    params: [T; 5],
    h: T,
    alpha: Vector2<T>,
    g: [T; 3],
    x: Vector3<T>,
    xi: Vector2<T>,
    mu: Vector3<T>,
    passes: usize,
    steps: u32,
    cps: &[(u32, Vector2<T>)],
) -> Result<(), TestCaseError> {
    let sw = Swimmer::new([params[0], params[1], params[2]], params[3], params[4])
        .unwrap_or_else(|_| Swimmer::purcell());
    // Must not panic; that an `Ok` is finite is `connection_ok_is_finite_for_any_parameters`.
    let _ = (
        sw.connection(&alpha),
        sw.connection_with_derivatives(&alpha),
    );
    // Total functions: must not panic (their values may be NaN for NaN input).
    let e = se2::exp(&x);
    let _ = (se2::dexp(&x), se2::ad(&x), e.log(), e.theta(), e.adjoint());
    let gg = Se2::new(g[0], g[1], g[2]);
    let _ = (
        gg * e,
        gg.inverse(),
        gg.between(&e),
        gg.log(),
        gg.adjoint_transpose_mul(&mu),
    );
    let _ = gg.act(&xi);

    let kin = Kinematics::new(sw, h).or_else(|_| Kinematics::new(sw, T::from_f64(0.01)));
    let kin = kin.map_err(|e| TestCaseError::fail(e.to_string()))?;
    let state = State { alpha, g: gg };
    if let Ok(next) = kin.step(&state, &xi) {
        prop_assert!(sane(&next));
    }
    for p in [Passes::plain(passes), Passes::newton(passes), T::PASSES] {
        if let Ok(s) = kin.law_step(&state, &xi, &mu, OnArcs::NONE, p) {
            prop_assert!(sane(&s.next));
            prop_assert!(s.u.iter().chain(s.xi.iter()).all(|v| v.is_finite()));
        }
    }
    let checkpoints: Vec<Checkpoint<T>> = cps
        .iter()
        .map(|&(k, xi)| Checkpoint { k, state, xi })
        .collect();
    let costate = Costate { mu, xi };
    if let Ok(mut replay) = Replay::new(kin, state, costate, steps, &checkpoints) {
        let mut n = 0;
        let mut failed = false;
        for item in replay.by_ref() {
            n += 1;
            match item {
                Ok(s) => prop_assert!(!failed && sane(&s.state)),
                Err(_) => failed = true,
            }
        }
        prop_assert!(n <= steps);
        prop_assert!(replay.next().is_none());
        prop_assert!(sane(replay.state()));
    }
    Ok(())
}

proptest! {
    #![proptest_config(proptest_config())]

    /// No function of the core panics on any f64 input.
    #[test]
    fn no_function_panics_on_garbage_f64(
        params in (wild(), wild(), wild(), wild(), wild()),
        h in prop_oneof![wild(), Just(0.01)],
        alpha in wild2(), g in wild3(), x in wild3(), xi in wild2(), mu in wild3(),
        passes in 0usize..40, steps in 0u32..20,
        cps in prop::collection::vec((0u32..25, wild2()), 0..4),
    ) {
        exercise(
            [params.0, params.1, params.2, params.3, params.4],
            h, alpha, [g.x, g.y, g.z], x, xi, mu, passes, steps, &cps,
        )?;
    }

    /// No function of the core panics on any f32 input (f64 garbage rounded: huge values
    /// become ±∞, tiny ones subnormal or 0).
    #[test]
    fn no_function_panics_on_garbage_f32(
        params in (wild(), wild(), wild(), wild(), wild()),
        h in prop_oneof![wild(), Just(0.01)],
        alpha in wild2(), g in wild3(), x in wild3(), xi in wild2(), mu in wild3(),
        passes in 0usize..40, steps in 0u32..20,
        cps in prop::collection::vec((0u32..25, wild2()), 0..4),
        raw in any::<f32>(),
    ) {
        let f = |v: f64| v as f32;
        exercise(
            [f(params.0), f(params.1), f(params.2), f(params.3), f(params.4)],
            f(h), alpha.map(f), [f(g.x), raw, f(g.z)], x.map(f), xi.map(f), mu.map(f),
            passes, steps, &cps.iter().map(|(k, v)| (*k, v.map(f))).collect::<Vec<_>>(),
        )?;
    }
}

proptest! {
    #![proptest_config(proptest_config())]

    /// Any `(cos, sin)` entering the core is accepted exactly when finite and of unit length
    /// within the tolerance, and every state a replay from it returns has a unit rotation.
    #[test]
    fn only_unit_rotations_enter_the_core(c in wild(), s in wild(), steps in 0u32..20) {
        let state = State {
            alpha: Vector2::new(0.1, -0.2),
            g: Se2::from_rotation(0.01, 0.02, c, s),
        };
        let tol = purcell_core::kinematics::UNIT_ROTATION_TOLERANCE;
        let unit = c.is_finite() && s.is_finite() && (c * c + s * s - 1.0).abs() <= tol;
        prop_assert_eq!(state.check().is_ok(), unit);
        let costate = Costate {
            mu: Vector3::new(0.3, -0.2, 0.1),
            xi: Vector2::new(0.01, 0.02),
        };
        match Replay::new(kin(), state, costate, steps, &[]) {
            Ok(replay) => {
                prop_assert!(unit);
                for sample in replay {
                    prop_assert!(sane(&sample.map_err(|e| TestCaseError::fail(e.to_string()))?.state));
                }
            }
            Err(_) => prop_assert!(!unit),
        }
    }
}

/// Regression (found by `no_function_panics_on_garbage_f64`): with a vanishing middle link and
/// a subnormal drag ratio, `det W_ξ` passes the singularity check because
/// `1e-12·W_xx·W_yy·W_zz` underflows to 0, then `1/det` overflows and `A` came back `Ok`
/// with NaN and ∞ entries. Expected: `Err(Singular)` (or any `Err`).
#[test]
fn connection_ok_is_finite_for_extreme_parameters() {
    let sw = Swimmer::new(
        [
            1.3007426673947733e-274,
            1.6257540440664602,
            0.14693117667522249,
        ],
        2.3134888921980106e290,
        1.878319409435316e-309,
    )
    .unwrap();
    let alpha = Vector2::new(0.0, 1.9215692420621497);
    if let Ok(a) = sw.connection(&alpha) {
        assert!(a.iter().all(|v| v.is_finite()), "Ok with non-finite A: {a}");
    }
}

proptest! {
    #![proptest_config(proptest_config())]

    /// Every `Ok` of the connection is finite, for any valid parameters and shape.
    #[test]
    fn connection_ok_is_finite_for_any_parameters(
        params in (wild(), wild(), wild(), wild(), wild()),
        alpha in wild2(),
    ) {
        if let Ok(sw) = Swimmer::new([params.0, params.1, params.2], params.3, params.4)
            && let Ok(c) = sw.connection_with_derivatives(&alpha)
        {
            let all = c.a.iter().chain(c.da.iter().flat_map(|d| d.iter()));
            prop_assert!(all.copied().all(f64::is_finite), "{c:?}");
        }
    }
}
