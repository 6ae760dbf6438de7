//! Left-equivariance of whole replays: the law run from `q·g₀` with `μ' = Ad_q^{−T} μ`
//! (`= Ad_{q⁻¹}ᵀ μ`) gives the same controls and `q·g_k` at every step, because the body
//! momentum `Ad_{q g_k}ᵀ μ'` equals `Ad_{g_k}ᵀ μ`. Over long horizons rounding differences
//! are amplified by the extremal's instability (see `precision.rs`), so the tolerance is
//! checked over 1 000 steps in f64 and the growth is bounded.

use nalgebra::Vector2;
use purcell_core::testkit::*;
use purcell_core::{Costate, Se2, State};
use purcell_tests::*;

#[test]
fn long_replays_are_left_equivariant() {
    let moves = [
        Se2::new(0.3, -1.2, 0.7),
        Se2::new(-2.0, 0.5, -2.9),
        Se2::new(1e-8, -1e-8, 1e-8),
        Se2::new(5.0, 5.0, core::f64::consts::PI),
    ];
    for c in [costate_mu13(), costate_mu6()] {
        let start = State::at_origin(Vector2::new(0.0, 0.0));
        let (base, _) = replay_all(paper_kinematics(), start, c, 1000, &[]).unwrap();
        for q in moves {
            let moved = State {
                alpha: start.alpha,
                g: q * start.g,
            };
            let cq = Costate {
                mu: q.inverse().adjoint_transpose_mul(&c.mu),
                xi: c.xi,
            };
            let (other, _) = replay_all(paper_kinematics(), moved, cq, 1000, &[]).unwrap();
            let (mut du, mut dg) = (0.0f64, 0.0f64);
            for (a, b) in base.iter().zip(&other) {
                du = du.max((a.u - b.u).abs().max());
                dg = dg.max(se2_distance(&(q * a.state.g), &b.state.g));
                assert_eq!(a.k, b.k);
            }
            // Rounding of Ad_q (|q| ≤ 7) is ≈ 1e-15 per step, amplified ≲ 100× over 1 000
            // steps (precision.rs: ×10 per 250 steps at most, here from 1e-15).
            assert!(du <= 1e-11 && dg <= 1e-11, "q = {q:?}: du {du:e} dg {dg:e}");
        }
    }
}

/// Over the whole horizon (10 000 steps) the moved replay still reaches `q·g_N` closely.
#[test]
fn full_horizon_replay_is_left_equivariant_at_the_end() {
    let c = costate_mu6();
    let q = Se2::new(0.3, -1.2, 0.7);
    let start = State::at_origin(Vector2::new(0.0, 0.0));
    let (_, end) = replay_all(paper_kinematics(), start, c, STEPS, &[]).unwrap();
    let moved = State {
        alpha: start.alpha,
        g: q,
    };
    let cq = Costate {
        mu: q.inverse().adjoint_transpose_mul(&c.mu),
        xi: c.xi,
    };
    let (_, end_q) = replay_all(paper_kinematics(), moved, cq, STEPS, &[]).unwrap();
    let d = se2_distance(&(q * end.g), &end_q.g);
    println!("end distance after {STEPS} steps: {d:e}");
    assert!(d <= 1e-6, "{d:e}");
}
