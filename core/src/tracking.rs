//! Closed-loop tracking of a gait (MODEL.md §10): the law's nominal step corrected by a gain on
//! the measured error and on a running estimate of the drag-ratio error.
//!
//! ```text
//! e_k = (α̂_k − α_k,  R(θ_k)ᵀ(p̂_k − p_k),  sin(θ̂_k − θ_k))      (nominal α_k, g_k = (p_k, θ_k))
//! at a record step k = jD:   a ← a + ψ_jᵀe_k,   ε̂ = a·β_j,   w = κ_j ε̂
//! u_k = u_k^nom + K_j e_k + w,   then each u_{k,i} clamped to [(−α_max − α_i)/h, (α_max − α_i)/h]
//! ```
//!
//! `(α̂, ĝ)` is the measured state; `e` is `(α̂ − α, log(g⁻¹ĝ))` to first order, computed without
//! trigonometry from the stored `(cos θ, sin θ)` of both poses: `sin(θ̂ − θ) = ŝc − ĉs`.
//! Record `j` ([`Record`], computed offline by purcell-solver's `tracking` module) holds the
//! feedback gain `K_j` (2×5, row-major, columns in the order of `e`), the gain `κ_j` on the
//! relative error `ε` of the drag ratio, the error `ψ_j` per unit `ε` that the closed loop
//! makes at step `jD` of the linearised model, and `β_j = 1/Σ_{i≤j}|ψ_i|²` (0 before the
//! estimate is used): `ε̂` is then the least-squares fit of `e_{iD} = ψ_i ε` over the records
//! so far, exact in the linearised, noise-free model. A record holds for `D` steps.
//!
//! The clamp keeps the joint angle `α_i` — the integral of the commanded `u`, which the joint
//! follows exactly (`α_{k+1} = α_k + h·u_k` in plant and model alike) — within a gait's joint
//! limit, as the law's arcs do: on an arc the nominal `u_i` is 0 and a correction that would
//! push the joint past the limit is cut to land on it. Fixed work per step: 8 multiplications
//! for `e`, 10 multiply-adds and 2 additions for `u`, two clamps; 8 more at a record step.

use crate::kinematics::State;
use crate::{Error, Kinematics, Real, Se2, Swimmer};
use nalgebra::Vector2;

/// How far inside the links' overlap `|α_i| = π` the tracking law holds a gait without a joint
/// limit, radians.
pub const OVERLAP_MARGIN: f64 = 0.02;

/// The bound the tracking law holds the joints within: the gait's joint limit `α_max`, or
/// [`OVERLAP_MARGIN`] inside the overlap.
pub fn joint_bound(alpha_max: Option<f64>) -> f64 {
    alpha_max.unwrap_or(core::f64::consts::PI - OVERLAP_MARGIN)
}

/// Relative errors of a plant's parameters against the model's (`0.1`: 10 % larger).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Mismatch {
    /// Of the drag ratio `r`.
    pub ratio: f64,
    /// Of the drag coefficient `k` (which cancels from `A`: no effect on the motion).
    pub drag: f64,
    /// Of the link lengths, as `(L0·(1 + E), L1·(1 − E), L2·(1 + E))`: middle and rear link
    /// longer, front link shorter (a common scale of all three only scales the displacement).
    pub length: f64,
}

impl Mismatch {
    /// The plant: `model`'s swimmer with these errors, same `h`.
    ///
    /// Errors: [`Error::InvalidParameters`] if a parameter is no longer positive.
    pub fn plant(&self, model: &Kinematics<f64>) -> Result<Kinematics<f64>, Error> {
        let sw = model.swimmer();
        let [l0, l1, l2] = sw.lengths();
        let e = self.length;
        let swimmer = Swimmer::new(
            [l0 * (1.0 + e), l1 * (1.0 - e), l2 * (1.0 + e)],
            sw.drag() * (1.0 + self.drag),
            sw.ratio() * (1.0 + self.ratio),
        )?;
        Kinematics::new(swimmer, model.h())
    }
}

/// `state` in `T`, as a sensor in `T` reads the plant's `f64` state: each number rounded to
/// nearest, the rotation as stored.
pub fn rounded<T: Real>(state: &State<f64>) -> State<T> {
    let (a, g) = (&state.alpha, &state.g);
    let c = T::from_f64;
    State {
        alpha: Vector2::new(c(a.x), c(a.y)),
        g: Se2::from_rotation(c(g.x()), c(g.y()), c(g.cos()), c(g.sin())),
    }
}

/// Values of one [`Record`]: `K` (10), `κ` (2), `ψ` (5), `β` (1).
pub const RECORD_VALUES: usize = 18;

/// One record of the tracking table: `[K (2×5 row-major), κ (2), ψ (5), β]`.
pub type Record<T> = [T; RECORD_VALUES];

/// The first-order error `(α̂ − α, R(θ)ᵀ(p̂ − p), sin(θ̂ − θ))` of `measured` against `nominal`
/// (see the [module docs](self)).
#[inline]
pub fn tracking_error<T: Real>(nominal: &State<T>, measured: &State<T>) -> [T; 5] {
    let (g, m) = (&nominal.g, &measured.g);
    let (c, s) = (g.cos(), g.sin());
    let (dx, dy) = (m.x() - g.x(), m.y() - g.y());
    [
        measured.alpha.x - nominal.alpha.x,
        measured.alpha.y - nominal.alpha.y,
        c * dx + s * dy,
        c * dy - s * dx,
        m.sin() * c - m.cos() * s,
    ]
}

/// `Σ xᵢyᵢ`, left to right.
#[inline(always)]
fn dot<T: Real>(x: &[T], y: &[T]) -> T {
    x.iter().zip(y).fold(T::zero(), |acc, (a, b)| acc + *a * *b)
}

/// The tracking law's state: the running sum `a` of the estimate, the estimate `ε̂` and the
/// record's feed-forward `w = κε̂`, computed once a record.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Tracker<T> {
    sum: T,
    estimate: T,
    feed: [T; 2],
}

impl<T: Real> Tracker<T> {
    /// No data yet: `a = ε̂ = 0`.
    pub fn new() -> Self {
        Tracker {
            sum: T::zero(),
            estimate: T::zero(),
            feed: [T::zero(); 2],
        }
    }

    /// The current estimate `ε̂` of the drag ratio's relative error.
    pub fn estimate(&self) -> T {
        self.estimate
    }

    /// At the first step of a record: `a ← a + ψᵀe`, `ε̂ = a·β`, `w = κε̂`.
    #[inline]
    pub fn update(&mut self, record: &Record<T>, error: &[T; 5]) {
        let (psi, beta) = (&record[12..17], record[17]);
        self.sum += dot(psi, error);
        self.estimate = self.sum * beta;
        self.feed = [record[10] * self.estimate, record[11] * self.estimate];
    }

    /// The control `u_nom + K·e + w` (`w` of the record's [`Tracker::update`]), clamped so that the joints at `joints` stay within
    /// `limit` (`None`: no clamp) after a step of `h`.
    ///
    /// Errors: [`Error::NonFinite`] if the result is not finite.
    #[inline]
    pub fn control(
        &self,
        record: &Record<T>,
        u_nom: &Vector2<T>,
        error: &[T; 5],
        joints: &Vector2<T>,
        limit: Option<T>,
        h: T,
    ) -> Result<Vector2<T>, Error> {
        let mut u = Vector2::new(
            u_nom.x + dot(&record[0..5], error) + self.feed[0],
            u_nom.y + dot(&record[5..10], error) + self.feed[1],
        );
        if let Some(l) = limit {
            // Divides only when it clamps: the bound is tested on the next angle `a + h·u`.
            let clamp = |u: T, a: T| {
                let next = a + h * u;
                if next > l {
                    (l - a) / h
                } else if next < -l {
                    (-l - a) / h
                } else {
                    u
                }
            };
            u = Vector2::new(clamp(u.x, joints.x), clamp(u.y, joints.y));
        }
        if T::all_finite([u.x, u.y]) {
            Ok(u)
        } else {
            Err(Error::NonFinite)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_is_first_order_log_and_clamp_holds_the_limit() {
        let nominal = State {
            alpha: Vector2::new(0.2, -0.1),
            g: Se2::new(0.3, -0.2, 0.7),
        };
        let d = Se2::new(1e-4, -2e-4, 3e-4);
        let measured = State {
            alpha: Vector2::new(0.25, -0.1),
            g: nominal.g.compose(&d),
        };
        let e = tracking_error(&nominal, &measured);
        let log = d.log();
        assert!((e[0] - 0.05).abs() < 1e-15 && e[1].abs() < 1e-15);
        for (a, b) in e[2..].iter().zip([log.x, log.y, log.z]) {
            assert!((a - b).abs() < 1e-7, "{a} vs {b}");
        }
        let mut record = [0.0; RECORD_VALUES];
        record[0] = 1.0;
        record[6] = -2.0;
        record[11] = 3.0;
        record[12] = 2.0;
        record[17] = 0.5;
        let mut t = Tracker::new();
        t.update(&record, &e);
        assert!((t.estimate() - 0.05).abs() < 1e-15);
        let u = t.control(
            &record,
            &Vector2::new(1.0, 1.0),
            &e,
            &measured.alpha,
            None,
            0.01,
        );
        assert!((u.unwrap() - Vector2::new(1.05, 1.15)).norm() < 1e-14);
        // Joint 1 at 1.495 may move at most 0.5 rad/s towards 1.5; joint 2 on −1.5 not below.
        let joints = Vector2::new(1.495, -1.5);
        let u = t.control(
            &record,
            &Vector2::new(3.0, -1.2),
            &e,
            &joints,
            Some(1.5),
            0.01,
        );
        let u = u.unwrap();
        assert!((u.x - 0.5).abs() < 1e-12 && u.y == 0.0);
        let nan = t.control(
            &record,
            &Vector2::new(f64::NAN, 0.0),
            &e,
            &joints,
            None,
            0.01,
        );
        assert_eq!(nan, Err(Error::NonFinite));
    }
}
