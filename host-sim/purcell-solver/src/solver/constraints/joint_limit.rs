//! The joint limit `|α_{k,i}| ≤ α_max` (`k = 1 … N−1`) as the direct method sees it (MODEL.md
//! §9): nowhere ([`Limits::None`]), as a logarithmic barrier in the objective
//! ([`Limits::Barrier`]) or imposed exactly on arcs ([`Limits::Arcs`]); and the arc tables of
//! a path ([`arcs_of`], [`merged`]), and how the arcs tie a stage's controls ([`ControlMap`]).
//! How the solver moves between these is [`crate::solver::homotopy`].

use crate::solver::settings::KAPPA_SIGMA;
use crate::solver::stage::StageState;
use nalgebra::Vector2;
use purcell_core::Arc;

/// How the controls of one stage are tied by the arcs: per joint, free, fixed at zero (inside
/// an arc) or set by the state (`δu_i = −δα_i/h` at an arc's entry step).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ControlMap {
    /// `u_{k,i}` fixed at zero.
    pub fixed: [bool; 2],
    /// `u_{k,i} = (±α_max − α_{k,i})/h`.
    pub entry: [bool; 2],
}

impl ControlMap {
    /// Whether control `i` is a free variable.
    pub fn free(&self, i: usize) -> bool {
        !self.fixed[i] && !self.entry[i]
    }
}

/// How the joint limit enters the direct method.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Limits {
    /// None (only the link-overlap limit, checked afterwards).
    #[default]
    None,
    /// A logarithmic barrier `h·τ·Σ_k Σ_i −ln(α_max − α_{k,i}) − ln(α_max + α_{k,i})` added to
    /// the cost; every iterate strictly inside the limits.
    Barrier {
        /// `α_max`.
        alpha_max: f64,
        /// `τ`.
        tau: f64,
    },
    /// The limit active exactly on the given arcs (their controls fixed and entries imposed,
    /// as stage-wise substitutions), inactive elsewhere: on an arc `σ·α_{k,i} = α_max` for
    /// `first ≤ k ≤ last`, so `u_{k,i} = 0` for `first ≤ k < last`, and the control of step
    /// `first − 1` brings the joint exactly to the limit.
    Arcs {
        /// `α_max`.
        alpha_max: f64,
        /// The arcs, in any order, disjoint per joint.
        arcs: Vec<Arc>,
    },
}

/// The bound multipliers of one inner state, `(z⁺_1, z⁻_1, z⁺_2, z⁻_2)`: of the bounds
/// `d^±_i = α_max ∓ α_i ≥ 0` ([`Limits::duals`]).
pub type Duals = [f64; 4];

/// The distances `(d⁺_1, d⁻_1, d⁺_2, d⁻_2)` of a state from the limits, `d^±_i = α_max ∓ α_i`.
fn distances(alpha_max: f64, s: &StageState) -> Duals {
    [
        alpha_max - s[0],
        alpha_max + s[0],
        alpha_max - s[1],
        alpha_max + s[1],
    ]
}

/// `(φ, φ′, φ″)` of the barrier `φ(α) = −ln(A − α) − ln(A + α)`.
fn barrier(a: f64, x: f64) -> (f64, f64, f64) {
    let (p, m) = (a - x, a + x);
    (
        -(p.ln() + m.ln()),
        1.0 / p - 1.0 / m,
        1.0 / (p * p) + 1.0 / (m * m),
    )
}

impl Limits {
    /// Whether an inner state (`k = 1 … N−1`) is in the barrier's domain, strictly inside the
    /// limits (always without a barrier).
    pub fn inside(&self, s: &StageState) -> bool {
        match *self {
            Limits::Barrier { alpha_max, .. } => s[0].abs() < alpha_max && s[1].abs() < alpha_max,
            _ => true,
        }
    }

    /// The objective of the direct method from the cost `cost` of a rollout's controls: plus
    /// the barrier over its inner states if there is one.
    pub fn objective(&self, h: f64, cost: f64, states: &[StageState]) -> f64 {
        match *self {
            Limits::Barrier { alpha_max, tau } => {
                let n = states.len().saturating_sub(1);
                let sum: f64 = states
                    .iter()
                    .take(n)
                    .skip(1)
                    .map(|s| barrier(alpha_max, s[0]).0 + barrier(alpha_max, s[1]).0)
                    .sum();
                cost + h * tau * sum
            }
            _ => cost,
        }
    }

    /// The derivative of [`Limits::objective`] along the step `du` from the cost's,
    /// `cost_slope` (the barrier's terms added stage by stage, `δα_k = h Σ_{j<k} δu_j`).
    pub fn objective_slope(
        &self,
        h: f64,
        cost_slope: f64,
        states: &[StageState],
        du: &[Vector2<f64>],
    ) -> f64 {
        let mut slope = cost_slope;
        if let Limits::Barrier { alpha_max, tau } = *self {
            let mut da = Vector2::zeros();
            for (k, d) in du.iter().enumerate().take(du.len().saturating_sub(1)) {
                da += d * h;
                let s = &states[k + 1];
                slope += h
                    * tau
                    * (barrier(alpha_max, s[0]).1 * da.x + barrier(alpha_max, s[1]).1 * da.y);
            }
        }
        slope
    }

    /// The barrier's gradient and the diagonal of its Hessian at an inner state `s`,
    /// `h·τ·φ′(α_i)` and `h·τ·φ″(α_i)`, or with bound multipliers `z` the primal–dual
    /// `h·(z⁺_i/d⁺_i + z⁻_i/d⁻_i)` (`d^± = α_max ∓ α_i`; the two agree on the central path
    /// `z = τ/d`); `None` without a barrier.
    pub fn barrier_derivatives(
        &self,
        h: f64,
        s: &StageState,
        z: Option<&Duals>,
    ) -> Option<(Vector2<f64>, Vector2<f64>)> {
        let Limits::Barrier { alpha_max, tau } = *self else {
            return None;
        };
        let (_, g0, d0) = barrier(alpha_max, s[0]);
        let (_, g1, d1) = barrier(alpha_max, s[1]);
        let hessian = match z {
            None => Vector2::new(h * tau * d0, h * tau * d1),
            Some(z) => Vector2::from_fn(|i, _| {
                let (p, m) = (alpha_max - s[i], alpha_max + s[i]);
                h * (z[2 * i] / p + z[2 * i + 1] / m)
            }),
        };
        Some((Vector2::new(h * tau * g0, h * tau * g1), hessian))
    }

    /// The bound multipliers on the central path, `z = τ/d` at each inner state (zero at the
    /// ends, which the limit does not bind); empty without a barrier.
    pub fn duals(&self, states: &[StageState]) -> Vec<Duals> {
        let Limits::Barrier { alpha_max, tau } = *self else {
            return Vec::new();
        };
        let n = states.len().saturating_sub(1);
        (states.iter().enumerate())
            .map(|(k, s)| {
                if k == 0 || k == n {
                    return [0.0; 4];
                }
                distances(alpha_max, s).map(|d| tau / d)
            })
            .collect()
    }

    /// The bound multipliers `z` at `states` moved along the Newton step `du` (IPOPT's
    /// primal–dual step, MODEL.md §9): `δz = τ/d − z − (z/d)·δd` with
    /// `δd^± = ∓δα_k = ∓h Σ_{j<k} δu_j`, the longest step `t ≤ 1` that keeps each `z` a share
    /// `1 − fraction` of itself, then each kept within `[τ/(κ_Σ d), κ_Σ τ/d]` at the states
    /// `next` the line search accepted ([`KAPPA_SIGMA`]). Empty without a barrier.
    pub fn dual_step(
        &self,
        h: f64,
        (states, next): (&[StageState], &[StageState]),
        du: &[Vector2<f64>],
        z: &[Duals],
        fraction: f64,
    ) -> Vec<Duals> {
        let Limits::Barrier { alpha_max, tau } = *self else {
            return Vec::new();
        };
        let n = states.len().saturating_sub(1);
        let mut dz = vec![[0.0; 4]; n + 1];
        let mut da = Vector2::zeros();
        let mut t = 1.0f64;
        for k in 1..n {
            da += du[k - 1] * h;
            let d = distances(alpha_max, &states[k]);
            let dd = [-da.x, da.x, -da.y, da.y];
            for j in 0..4 {
                let step = tau / d[j] - z[k][j] - z[k][j] / d[j] * dd[j];
                if step < 0.0 {
                    t = t.min(-fraction * z[k][j] / step);
                }
                dz[k][j] = step;
            }
        }
        (0..=n)
            .map(|k| {
                if k == 0 || k == n {
                    return [0.0; 4];
                }
                let d = distances(alpha_max, &next[k]);
                core::array::from_fn(|j| {
                    let lo = tau / (KAPPA_SIGMA * d[j]);
                    (z[k][j] + t * dz[k][j]).clamp(lo, KAPPA_SIGMA * tau / d[j])
                })
            })
            .collect()
    }

    /// The largest `t ≤ 1` for which the step `t·du` on a grid of step `h` keeps every state
    /// `k = 1 … N−1` a share `1 − fraction` of its distance `d` from each limit, less `slack`
    /// (`δα_k = h Σ_{j<k} δu_j` is linear in `t`): `t ≤ (fraction·d + slack)/δd`.
    /// `(FRACTION_TO_BOUNDARY, 0)` is IPOPT's fraction to the boundary; `(1, slack)` where the
    /// step leaves the barrier's domain. 1 without a barrier.
    ///
    /// [`FRACTION_TO_BOUNDARY`]: crate::solver::settings::FRACTION_TO_BOUNDARY
    pub fn max_step(
        &self,
        h: f64,
        states: &[StageState],
        du: &[Vector2<f64>],
        fraction: f64,
        slack: f64,
    ) -> f64 {
        let Limits::Barrier { alpha_max, .. } = *self else {
            return 1.0;
        };
        let mut t = 1.0f64;
        let mut da = Vector2::zeros();
        for (k, d) in du.iter().enumerate().take(du.len().saturating_sub(1)) {
            da += d * h;
            let s = &states[k + 1];
            for i in 0..2 {
                // Toward `+α_max` or toward `−α_max`.
                let (dist, toward) = if da[i] > 0.0 {
                    (alpha_max - s[i], da[i])
                } else {
                    (alpha_max + s[i], -da[i])
                };
                if toward > 0.0 {
                    t = t.min((fraction * dist + slack) / toward);
                }
            }
        }
        t
    }

    /// The control maps of the arcs on a grid of `steps` steps, one per stage (`None` without
    /// arcs).
    pub fn control_maps(&self, steps: usize) -> Option<Vec<ControlMap>> {
        let Limits::Arcs { arcs, .. } = self else {
            return None;
        };
        let mut maps = vec![ControlMap::default(); steps];
        for a in arcs {
            let (i, first, last) = (a.index(), a.first as usize, a.last as usize);
            if let Some(m) = first.checked_sub(1).and_then(|k| maps.get_mut(k)) {
                m.entry[i] = true;
            }
            for m in maps.iter_mut().take(last).skip(first) {
                m.fixed[i] = true;
            }
        }
        Some(maps)
    }

    /// The controls `u` (from the shape `alpha0`, step `h`) made to satisfy the arcs exactly:
    /// zero inside each arc, and the entry control bringing the joint to the limit (the shape
    /// path recomputed from `alpha0`). Unchanged without arcs.
    pub fn snap(&self, u: &[Vector2<f64>], alpha0: Vector2<f64>, h: f64) -> Vec<Vector2<f64>> {
        let (Limits::Arcs { alpha_max, arcs }, Some(maps)) = (self, self.control_maps(u.len()))
        else {
            return u.to_vec();
        };
        let mut alpha = alpha0;
        let mut out = Vec::with_capacity(u.len());
        for (k, v) in u.iter().enumerate() {
            let mut w = *v;
            for i in 0..2 {
                if maps[k].fixed[i] {
                    w[i] = 0.0;
                } else if maps[k].entry[i] {
                    let sign = arcs
                        .iter()
                        .find(|a| a.index() == i && a.first as usize == k + 1)
                        .map_or(1.0, |a| f64::from(a.sign));
                    w[i] = (sign * alpha_max - alpha[i]) / h;
                }
            }
            alpha += w * h;
            out.push(w);
        }
        out
    }
}

/// The arcs of a path: maximal stretches of states `k = 1 … N−1` within `near` of `±α_max`,
/// by joint, side (`+` first) and first state.
pub fn arcs_of(states: &[StageState], alpha_max: f64, near: f64) -> Vec<Arc> {
    let n = states.len().saturating_sub(1);
    let mut arcs = Vec::new();
    for i in [0, 1] {
        for sign in [1i8, -1] {
            let on = |k: usize| f64::from(sign) * states[k][i] >= alpha_max - near;
            let mut k = 1;
            while k < n {
                if on(k) {
                    let first = k;
                    while k + 1 < n && on(k + 1) {
                        k += 1;
                    }
                    arcs.push(Arc::new(Arc::joint_of(i), sign, first as u32, k as u32));
                }
                k += 1;
            }
        }
    }
    arcs
}

/// The arcs with those of one joint and side that overlap or touch joined into one, in the
/// order of [`arcs_of`] (joint, side, first step).
pub fn merged(mut arcs: Vec<Arc>) -> Vec<Arc> {
    arcs.sort_by_key(|a| (a.joint, -a.sign, a.first));
    let mut out: Vec<Arc> = Vec::with_capacity(arcs.len());
    for a in arcs {
        match out.last_mut() {
            Some(b) if b.joint == a.joint && b.sign == a.sign && a.first <= b.last + 1 => {
                b.last = b.last.max(a.last);
            }
            _ => out.push(a),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The primal–dual barrier's pieces ([`Limits::dual_step`]): on the central path
    /// `z = τ/d` its Hessian is the primal one; a step whose multipliers stay clear of the
    /// fraction to the boundary and the `κ_Σ` bounds meets the linearised complementarity
    /// `(z + δz)·d + z·δd = τ` at every inner state; and the multipliers of a step that
    /// would overshoot keep `1 − fraction` of themselves.
    #[test]
    fn the_dual_step_linearises_complementarity() {
        let (alpha_max, tau, h) = (1.2, 1e-3, 0.5);
        let limits = Limits::Barrier { alpha_max, tau };
        let states: Vec<StageState> = (0..6)
            .map(|k| {
                let t = k as f64;
                StageState::new((0.9 * t).sin(), (0.7 * t).cos() - 0.2, 0.0, 0.0, 0.0)
            })
            .collect();
        let central = limits.duals(&states);
        for (s, z) in states.iter().zip(&central).skip(1).take(4) {
            let (_, primal) = limits.barrier_derivatives(h, s, None).unwrap();
            let (_, dual) = limits.barrier_derivatives(h, s, Some(z)).unwrap();
            assert!(
                (primal - dual).amax() <= 1e-12 * primal.amax(),
                "{primal} {dual}"
            );
        }
        // Off the central path, a small step.
        let z: Vec<Duals> = (central.iter().enumerate())
            .map(|(k, z)| z.map(|v| v * (1.0 + 0.1 * (k as f64).sin())))
            .collect();
        let du: Vec<Vector2<f64>> = (0..5)
            .map(|k| Vector2::new(1e-3 * (k as f64 - 2.0), -2e-3 * k as f64))
            .collect();
        let next = |du: &[Vector2<f64>]| -> Vec<StageState> {
            let mut a = Vector2::zeros();
            let mut out = states.clone();
            for (k, s) in out.iter_mut().enumerate().skip(1) {
                a += du[k - 1] * h;
                s[0] += a.x;
                s[1] += a.y;
            }
            out
        };
        let moved = next(&du);
        let stepped = limits.dual_step(h, (&states, &moved), &du, &z, 0.99);
        for k in 1..5 {
            let (d, d1) = (
                distances(alpha_max, &states[k]),
                distances(alpha_max, &moved[k]),
            );
            for j in 0..4 {
                let lin = stepped[k][j] * d[j] + z[k][j] * (d1[j] - d[j]);
                assert!((lin - tau).abs() <= 1e-9 * tau, "{k} {j}: {lin}");
            }
        }
        assert_eq!((stepped[0], stepped[5]), ([0.0; 4], [0.0; 4]));
        // A step towards the limit that would drive some z negative stops at the fraction.
        let big: Vec<Vector2<f64>> = du.iter().map(|d| d * 400.0).collect();
        let stepped = limits.dual_step(h, (&states, &states), &big, &z, 0.99);
        let kept = (1..5)
            .flat_map(|k| (0..4).map(move |j| (k, j)))
            .map(|(k, j)| stepped[k][j] / z[k][j])
            .fold(f64::INFINITY, f64::min);
        assert!((kept - 0.01).abs() <= 1e-9, "{kept}");
    }

    #[test]
    fn touching_or_overlapping_arcs_of_one_joint_and_side_merge() {
        let arcs = vec![
            Arc::new(2, 1, 20, 25),
            Arc::new(1, 1, 5, 9),
            Arc::new(1, 1, 10, 12),
            Arc::new(1, -1, 13, 14),
            Arc::new(2, 1, 24, 30),
            Arc::new(2, 1, 32, 33),
        ];
        assert_eq!(
            merged(arcs),
            vec![
                Arc::new(1, 1, 5, 12),
                Arc::new(1, -1, 13, 14),
                Arc::new(2, 1, 20, 30),
                Arc::new(2, 1, 32, 33),
            ]
        );
    }
}
