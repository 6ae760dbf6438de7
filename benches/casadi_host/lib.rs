//! C entry points to the core's `f64` control-law step, so that `harness.c` can time it and a
//! CasADi-generated step the same way: one out-of-line call per step, the outputs fed back as
//! the next inputs (see `README.md`). Built as a static library by `run.sh`.

use nalgebra::{Vector2, Vector3};
use purcell_core::{Kinematics, Se2, State, Swimmer};

/// The swimmer and time step: `params = [L0, L1, L2, k, r, h]`. Null if the core refuses them.
///
/// # Safety
/// `params` must point to six readable `f64`. The result is freed by [`purcell_free_f64`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn purcell_new_f64(params: *const [f64; 6]) -> *mut Kinematics<f64> {
    // SAFETY: the caller passes six readable numbers.
    let [l0, l1, l2, k, r, h] = unsafe { *params };
    match Swimmer::new([l0, l1, l2], k, r).and_then(|sw| Kinematics::new(sw, h)) {
        Ok(kin) => Box::into_raw(Box::new(kin)),
        Err(_) => core::ptr::null_mut(),
    }
}

/// Frees what [`purcell_new_f64`] returned.
///
/// # Safety
/// `kin` is null or a pointer from [`purcell_new_f64`], not used afterwards.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn purcell_free_f64(kin: *mut Kinematics<f64>) {
    if !kin.is_null() {
        // SAFETY: from Box::into_raw in purcell_new_f64, freed once.
        drop(unsafe { Box::from_raw(kin) });
    }
}

/// One step of the law, `Kinematics::law_step`: `state = [α1, α2, x, y, cos θ, sin θ, ξ1, ξ2]`
/// (`ξ^{k−1}`) is replaced by the next one (`ξ^k`), `u` receives `u_k`. Returns 0, or 1 if the
/// core returned an error (the state is then unchanged).
///
/// # Safety
/// `kin` from [`purcell_new_f64`]; `mu` three, `state` eight and `u` two valid `f64`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn purcell_law_step_f64(
    kin: *const Kinematics<f64>,
    mu: *const [f64; 3],
    state: *mut [f64; 8],
    u: *mut [f64; 2],
) -> i32 {
    // SAFETY: the caller passes valid pointers (see above).
    let (kin, mu, s, u) = unsafe { (&*kin, &*mu, &mut *state, &mut *u) };
    let [a1, a2, x, y, c, sn, x1, x2] = *s;
    let st = State {
        alpha: Vector2::new(a1, a2),
        g: Se2::from_rotation(x, y, c, sn),
    };
    match kin.law_step(
        &st,
        &Vector2::new(x1, x2),
        &Vector3::new(mu[0], mu[1], mu[2]),
    ) {
        Ok(step) => {
            let (n, g) = (&step.next, &step.next.g);
            *s = [
                n.alpha.x,
                n.alpha.y,
                g.x(),
                g.y(),
                g.cos(),
                g.sin(),
                step.xi.x,
                step.xi.y,
            ];
            *u = [step.u.x, step.u.y];
            0
        }
        Err(_) => 1,
    }
}
