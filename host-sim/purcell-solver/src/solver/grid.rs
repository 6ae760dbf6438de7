//! The problem on a time grid: `N` steps of the exact stage model ([`super::stage`]) from
//! `s_0 = (ᾱ, 0, 0, 0)` to `s_N = (β, ḡ)`, with the cost ([`super::cost`]) and the constraints
//! ([`super::constraints`]): rollouts of controls, the objective the direct method minimises
//! and its slope, how a path moves between grids ([`prolong`], [`Grid::resampled`],
//! [`Grid::resolves`]), and when two paths are the same ([`same_path`]).

use super::constraints::joint_limit::{Duals, Limits};
use super::constraints::terminal::Terminal;
use super::cost::{Costs, StageCost};
use super::settings::SAME_PATH;
use super::stage::{Rule, StageModel, StageState};
use crate::problem::Problem;
use nalgebra::{Vector2, Vector3, Vector5};
use purcell_core::{Error, Kinematics};

/// One time grid of the problem: `steps` steps over the horizon `T`.
#[derive(Clone, Debug)]
pub struct Grid {
    /// The stage model with `h = T/steps`.
    pub model: StageModel,
    /// Steps `N`.
    pub steps: usize,
    /// `s_0 = (ᾱ, 0, 0, 0)`.
    pub start: StageState,
    /// The terminal constraint `s_N = s̄ = (β, ḡ)`.
    pub terminal: Terminal,
    /// How the joint limit `|α_i| ≤ α_max` enters, if at all.
    pub limits: Limits,
    /// The running cost.
    pub cost: Costs,
}

impl Grid {
    /// The problem on a grid of `steps` steps with the connection evaluated by `rule`
    /// (`steps = problem.steps` with [`Rule::LEFT_POINT`] is the problem itself).
    pub fn new(problem: &Problem, steps: usize, rule: Rule) -> Result<Self, Error> {
        let h = problem.horizon() / steps as f64;
        let kin = Kinematics::new(*problem.kinematics::<f64>()?.swimmer(), h)?;
        let (a, b) = (problem.alpha0, problem.alpha_end);
        let t = problem.target;
        Ok(Grid {
            model: StageModel::new(kin, rule)?,
            steps,
            start: StageState::new(a.x, a.y, 0.0, 0.0, 0.0),
            terminal: Terminal {
                target: StageState::new(b.x, b.y, t.x, t.y, t.z),
            },
            limits: Limits::None,
            cost: Costs::of(problem.cost, problem.swimmer),
        })
    }

    /// The problem on `steps` steps (at most its own `N`) with the rule that mimics its
    /// discretisation ([`Rule::matching`]), or its own ([`Rule::LEFT_POINT`]) on its own grid.
    pub fn mimic(problem: &Problem, steps: usize) -> Result<Self, Error> {
        let rule = if steps == problem.steps as usize {
            Rule::LEFT_POINT
        } else {
            Rule::matching(problem.horizon() / steps as f64, problem.h)
        };
        Grid::new(problem, steps, rule)
    }

    /// The same grid with the target `ḡ = target` (the end shape `β` kept).
    pub fn aiming_at(&self, target: &Vector3<f64>) -> Grid {
        let mut grid = self.clone();
        let a = self.terminal.target;
        grid.terminal.target = StageState::new(a[0], a[1], target.x, target.y, target.z);
        grid
    }

    /// Step `h`.
    pub fn h(&self) -> f64 {
        self.model.h()
    }

    /// The same problem on `steps` steps with `rule`.
    pub fn resampled(&self, steps: usize, rule: Rule) -> Result<Self, Error> {
        let h = self.h() * self.steps as f64 / steps as f64;
        let kin = Kinematics::new(*self.model.kin.swimmer(), h)?;
        Ok(Grid {
            model: StageModel::new(kin, rule)?,
            steps,
            start: self.start,
            terminal: self.terminal,
            limits: Limits::None,
            cost: self.cost,
        })
    }

    /// Whether the net motion of the controls `u` is resolved by this grid: the end of their
    /// shape path integrated 16 times finer by the midpoint rule (second order) lies within a
    /// fifth of the displacement asked for from the end of `u`'s own rollout (for a transition,
    /// of the larger of it and a fifth of the farthest the path goes from the start: a
    /// transition back to the start pose asks for none). A solution that
    /// exists only through the discretisation error of a coarse grid (e.g. with equal drag
    /// along and across the links, where no loop moves the body) fails this.
    pub fn resolves(&self, u: &[Vector2<f64>]) -> bool {
        let (Ok(fine), Ok(own)) = (
            self.resampled(16 * self.steps, Rule::MIDPOINT),
            self.rollout(u),
        ) else {
            return false;
        };
        let Ok(accurate) = fine.rollout(&prolong(u, fine.steps)) else {
            return false;
        };
        let (Some(a), Some(b)) = (accurate.last(), own.last()) else {
            return false;
        };
        let scale = self.model.kin.swimmer().lengths()[0];
        let dist = |p: &StageState, q: &StageState| {
            ((p[2] - q[2]).powi(2) + (p[3] - q[3]).powi(2) + (scale * (p[4] - q[4])).powi(2)).sqrt()
        };
        let asked = dist(&self.terminal.target, &self.start);
        // A transition may be asked to return the body where it started (`ḡ = e`): its scale
        // is then the motion along the path, a fifth of the farthest the accurate path goes.
        let transition = (0..2).any(|i| self.terminal.target[i] != self.start[i]);
        let scale = if transition {
            let reach = accurate
                .iter()
                .fold(0.0, |m: f64, p| m.max(dist(p, &self.start)));
            asked.max(0.2 * reach)
        } else {
            asked
        };
        dist(a, b) <= 0.2 * scale
    }

    /// The states `s_0 … s_N` under the controls `u`; with a barrier, `Err(ShapeLimit)` unless
    /// every `|α_{k,i}| < α_max` (`k = 1 … N−1`).
    pub fn rollout(&self, u: &[Vector2<f64>]) -> Result<Vec<StageState>, Error> {
        let mut s = self.start;
        let mut out = Vec::with_capacity(u.len() + 1);
        out.push(s);
        for (k, uk) in u.iter().enumerate() {
            s = self.model.step(&s, uk)?;
            if k + 1 < u.len() && !self.limits.inside(&s) {
                return Err(Error::ShapeLimit);
            }
            out.push(s);
        }
        Ok(out)
    }

    /// The cost `J` of the controls `u` along their rollout `states` ([`Grid::cost`]'s field).
    pub fn cost(&self, u: &[Vector2<f64>], states: &[StageState]) -> f64 {
        self.cost.value(self.h(), states, u)
    }

    /// What the direct method minimises: `J`, plus the barrier if there is one
    /// ([`Limits::objective`]).
    pub fn objective(&self, u: &[Vector2<f64>], states: &[StageState]) -> f64 {
        self.limits
            .objective(self.h(), self.cost(u, states), states)
    }

    /// The derivative of [`Grid::objective`] along the step `du`.
    pub fn objective_slope(
        &self,
        u: &[Vector2<f64>],
        states: &[StageState],
        du: &[Vector2<f64>],
    ) -> f64 {
        let h = self.h();
        self.limits
            .objective_slope(h, self.cost.slope(h, states, u, du), states, du)
    }
}

/// An iterate: controls, their rollout and a terminal multiplier estimate.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// `u_0 … u_{N−1}`.
    pub u: Vec<Vector2<f64>>,
    /// `s_0 … s_N`.
    pub states: Vec<StageState>,
    /// `ν`.
    pub nu: Vector5<f64>,
    /// The bound multipliers of a primal–dual barrier step ([`Limits::duals`]); empty until
    /// the first such step.
    pub z: Vec<Duals>,
}

impl Point {
    /// The controls `u` with multiplier `nu` on `grid`; `Err` if the rollout fails.
    pub fn new(grid: &Grid, u: Vec<Vector2<f64>>, nu: Vector5<f64>) -> Result<Self, Error> {
        let states = grid.rollout(&u)?;
        Ok(Point {
            u,
            states,
            nu,
            z: Vec::new(),
        })
    }
}

/// The largest `|α_i|` along a path of stage states.
pub fn max_abs_alpha(states: &[StageState]) -> f64 {
    states
        .iter()
        .map(|s| s[0].abs().max(s[1].abs()))
        .fold(0.0, f64::max)
}

/// The largest `|Σ_{j≤k} h·v_j|` over `k` and both joints: how far controls `v` take the
/// shape from where it starts (for a Newton step `du`: how far it moves the shape path).
pub fn shape_reach(v: &[Vector2<f64>], h: f64) -> f64 {
    let mut offset = Vector2::zeros();
    let mut reach = 0.0f64;
    for d in v {
        offset += d * h;
        reach = reach.max(offset.amax());
    }
    reach
}

/// The controls of `u` (a grid of `u.len()` steps over the same horizon) on a grid of
/// `steps` steps: the same piecewise-linear shape path `α(t)`, sampled.
pub fn prolong(u: &[Vector2<f64>], steps: usize) -> Vec<Vector2<f64>> {
    let n = u.len();
    // α(t) relative to ᾱ at the coarse nodes, in units where the horizon is n.
    let mut nodes = Vec::with_capacity(n + 1);
    let mut a = Vector2::zeros();
    nodes.push(a);
    for v in u {
        a += v;
        nodes.push(a);
    }
    let at = |j: usize| -> Vector2<f64> {
        let x = j as f64 * n as f64 / steps as f64;
        let i = (x.floor() as usize).min(n.saturating_sub(1));
        let frac = x - i as f64;
        nodes[i] + u[i] * frac
    };
    // u_f = Δα/h_f with α in units of h_c: multiply by h_c/h_f = steps/n.
    let scale = steps as f64 / n as f64;
    let mut out = Vec::with_capacity(steps);
    let mut prev = at(0);
    for j in 1..=steps {
        let next = if j == steps { nodes[n] } else { at(j) };
        out.push((next - prev) * scale);
        prev = next;
    }
    out
}

/// Whether two control sequences run the same shape path (to [`SAME_PATH`] at every node).
pub fn same_path(a: &[Vector2<f64>], b: &[Vector2<f64>], h: f64) -> bool {
    let mut d = Vector2::zeros();
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            d += (x - y) * h;
            d.amax() <= SAME_PATH
        })
}

/// The largest distance `max_k |α_k − β_k|_∞` between the shape paths of two control
/// sequences of one grid (step `h`) from the same start shape (∞ if their lengths differ):
/// the distance [`same_path`] bounds by [`SAME_PATH`].
pub fn path_distance(a: &[Vector2<f64>], b: &[Vector2<f64>], h: f64) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    let mut d = Vector2::zeros();
    (a.iter().zip(b)).fold(0.0, |most: f64, (x, y)| {
        d += (x - y) * h;
        most.max(d.amax())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Spec;
    use crate::solver::settings::FRACTION_TO_BOUNDARY;

    /// Two paths are the same exactly when their distance is within [`SAME_PATH`]; the
    /// distance is that of the shapes, not of the controls.
    #[test]
    fn the_same_path_is_one_within_its_distance() {
        let h = 0.5;
        let a = vec![Vector2::new(1.0, -2.0); 8];
        let mut b = a.clone();
        assert_eq!(path_distance(&a, &b, h), 0.0);
        // One step's control off by 1e-3 and the next back: the shape 5e-4 off at one node.
        b[3].x += 1e-3;
        b[4].x -= 1e-3;
        assert!((path_distance(&a, &b, h) - 5e-4).abs() < 1e-15);
        assert!(!same_path(&a, &b, h));
        b[3].x -= 1e-3 - 1e-6;
        b[4].x += 1e-3 - 1e-6;
        assert!(path_distance(&a, &b, h) <= SAME_PATH && same_path(&a, &b, h));
        assert_eq!(path_distance(&a, &b[1..], h), f64::INFINITY);
    }

    /// `max_step(…, 1, 0)` is where the step's rollout leaves the barrier's domain.
    #[test]
    fn the_wall_is_where_the_rollout_leaves_the_limit() {
        let p = Problem::new(&Spec {
            alpha_max: Some(1.5),
            ..Spec::default()
        })
        .unwrap();
        let mut grid = Grid::new(&p, 64, Rule::LEFT_POINT).unwrap();
        grid.limits = Limits::Barrier {
            alpha_max: 1.5,
            tau: 1e-6,
        };
        let wave = |a: f64, b: f64| -> Vec<Vector2<f64>> {
            (0..64)
                .map(|k| {
                    let t = core::f64::consts::TAU * k as f64 / 64.0;
                    Vector2::new(a * t.cos(), b * (t + 1.0).cos())
                })
                .collect()
        };
        let u = wave(0.05, 0.04);
        let states = grid.rollout(&u).unwrap();
        for (a, b) in [(0.3, -0.2), (-0.5, 0.1), (0.05, 0.6)] {
            let du = wave(a, b);
            let wall = grid.limits.max_step(grid.h(), &states, &du, 1.0, 0.0);
            assert!(0.0 < wall && wall < 1.0, "{wall}");
            let at = |t: f64| -> Vec<Vector2<f64>> {
                u.iter().zip(&du).map(|(x, d)| x + d * t).collect()
            };
            assert!(grid.rollout(&at(wall * (1.0 - 1e-9))).is_ok());
            assert_eq!(
                grid.rollout(&at(wall * (1.0 + 1e-9))),
                Err(Error::ShapeLimit)
            );
            let fraction = grid
                .limits
                .max_step(grid.h(), &states, &du, FRACTION_TO_BOUNDARY, 0.0);
            assert!((fraction - FRACTION_TO_BOUNDARY * wall).abs() <= 1e-12 * wall);
        }
    }
}
