//! C entry points to the core's `f64` replay, so that `harness.c` can time its steps and a
//! CasADi-generated step the same way, one out-of-line call per step, as `firmware` and
//! `peers/casadi_m4f` do on the Cortex-M4F (see `README.md`). Built as a static library by
//! `run.sh`.

use nalgebra::{Vector2, Vector3};
use purcell_core::{Costate, Kinematics, Replay, State, Swimmer};

/// A replay of `steps` steps from `α0` at the origin with costate `(μ, ξ^{−1})`:
/// `p = [L0, L1, L2, k, r, h, α0₁, α0₂, μ₁, μ₂, μ₃, ξ₁, ξ₂]`. Null if the core refuses it.
///
/// # Safety
/// `p` must point to 13 readable `f64`. The result is freed by [`purcell_replay_free_f64`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn purcell_replay_new_f64(
    p: *const [f64; 13],
    steps: u32,
) -> *mut Replay<'static, f64> {
    // SAFETY: the caller passes 13 readable numbers.
    let [l0, l1, l2, k, r, h, a1, a2, m1, m2, m3, x1, x2] = unsafe { *p };
    let costate = Costate {
        mu: Vector3::new(m1, m2, m3),
        xi: Vector2::new(x1, x2),
    };
    let start = State::at_origin(Vector2::new(a1, a2));
    match Swimmer::new([l0, l1, l2], k, r)
        .and_then(|sw| Kinematics::new(sw, h))
        .and_then(|kin| Replay::new(kin, start, costate, steps, &[]))
    {
        Ok(replay) => Box::into_raw(Box::new(replay)),
        Err(_) => core::ptr::null_mut(),
    }
}

/// Frees what [`purcell_replay_new_f64`] returned.
///
/// # Safety
/// `replay` is null or a pointer from [`purcell_replay_new_f64`], not used afterwards.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn purcell_replay_free_f64(replay: *mut Replay<'static, f64>) {
    if !replay.is_null() {
        // SAFETY: from Box::into_raw in purcell_replay_new_f64, freed once.
        drop(unsafe { Box::from_raw(replay) });
    }
}

/// One step, `Replay::step`: writes `u_k` to `u` and the state after the step,
/// `[α1, α2, x, y, cos θ, sin θ, ξ1, ξ2]` (`ξ^k`), to `state`. Returns 0, 1 if the core
/// returned an error, 2 once the horizon is done.
///
/// # Safety
/// `replay` from [`purcell_replay_new_f64`]; `state` eight and `u` two writable `f64`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn purcell_replay_step_f64(
    replay: *mut Replay<'static, f64>,
    state: *mut [f64; 8],
    u: *mut [f64; 2],
) -> i32 {
    // SAFETY: the caller passes valid pointers (see above).
    let (replay, state, u) = unsafe { (&mut *replay, &mut *state, &mut *u) };
    match replay.step() {
        Ok(Some(sample)) => {
            *u = [sample.u.x, sample.u.y];
            let xi = sample.xi;
            let (a, g) = (replay.state().alpha, replay.state().g);
            *state = [a.x, a.y, g.x(), g.y(), g.cos(), g.sin(), xi.x, xi.y];
            0
        }
        Ok(None) => 2,
        Err(_) => 1,
    }
}
