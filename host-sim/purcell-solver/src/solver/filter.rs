//! The line search of the direct method: a filter (Wächter & Biegler, as IPOPT's) with one
//! second-order correction of a rejected full step (the terminal constraint is curved:
//! without it the filter rejects good Newton steps, the Maratos effect), from a first step
//! bounded by the fraction to the boundary and the trust radius ([`Settings`]).

use super::grid::{Grid, Point, shape_reach};
use super::settings::{
    BACKTRACK, FILTER_ETA, FILTER_GAMMA_PHI, FILTER_GAMMA_THETA, FILTER_S_PHI, FILTER_S_THETA,
    FILTER_THETA_MAX, FILTER_THETA_MIN, FRACTION_TO_BOUNDARY, MIN_STEP, Settings, WALL_SLACK,
};
use nalgebra::{Vector2, Vector5};

/// Whether a step was accepted for lowering the cost (Armijo) or for its progress on the
/// constraint/filter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum StepKind {
    Cost,
    Constraint,
}

/// The filter of Wächter & Biegler (IPOPT's line search), for equality constraints: a trial
/// point is acceptable if no earlier pair `(θ_j, φ_j)` (constraint violation `θ = |c|₁`, cost
/// `φ = J`) dominates it, and if it either lowers the cost enough (when the step is a descent
/// direction for the cost and the iterate nearly feasible) or lowers `θ` or `φ` enough against
/// the current point. No penalty parameter: the line search does not depend on the size of
/// the multipliers.
#[derive(Clone, Debug)]
pub struct Filter {
    entries: Vec<(f64, f64)>,
    theta_max: f64,
    theta_min: f64,
}

impl Filter {
    /// The empty filter for a start whose constraint violation is `theta0`.
    pub fn new(theta0: f64) -> Self {
        Filter {
            entries: Vec::new(),
            theta_max: FILTER_THETA_MAX * theta0.max(1.0),
            theta_min: FILTER_THETA_MIN * theta0.max(1.0),
        }
    }

    /// How a trial `(th, ph)` at step `t` is acceptable from the current point `(theta,
    /// phi)` with the objective's slope `slope` along the step, if it is.
    fn acceptable(
        &self,
        theta: f64,
        phi: f64,
        slope: f64,
        t: f64,
        th: f64,
        ph: f64,
    ) -> Option<StepKind> {
        if !(th.is_finite() && ph.is_finite()) || th > self.theta_max {
            return None;
        }
        if self.entries.iter().any(|&(tj, pj)| th >= tj && ph >= pj) {
            return None;
        }
        let switching = slope < 0.0 && t * (-slope).powf(FILTER_S_PHI) > theta.powf(FILTER_S_THETA);
        if switching && theta <= self.theta_min {
            (ph <= phi + FILTER_ETA * t * slope).then_some(StepKind::Cost)
        } else {
            (th <= (1.0 - FILTER_GAMMA_THETA) * theta || ph <= phi - FILTER_GAMMA_PHI * theta)
                .then_some(StepKind::Constraint)
        }
    }

    /// Adds the current point `(theta, phi)`, with the margins, to the filter.
    fn add(&mut self, theta: f64, phi: f64) {
        let entry = (
            (1.0 - FILTER_GAMMA_THETA) * theta,
            phi - FILTER_GAMMA_PHI * theta,
        );
        self.entries
            .retain(|&(tj, pj)| !(tj >= entry.0 && pj >= entry.1));
        self.entries.push(entry);
    }
}

/// A Newton step to search along: from `point`, the controls' step `du`, the trial points
/// carrying the multiplier `nu`.
pub struct Step<'a> {
    /// The current iterate.
    pub point: &'a Point,
    /// `δu`.
    pub du: &'a [Vector2<f64>],
    /// The trial points' `ν`.
    pub nu: Vector5<f64>,
}

impl Step<'_> {
    /// `u + t·δu`.
    fn along(&self, t: f64) -> Vec<Vector2<f64>> {
        self.point
            .u
            .iter()
            .zip(self.du)
            .map(|(a, b)| a + b * t)
            .collect()
    }

    /// `u + δu + e` (a full step with a correction `e`).
    fn corrected(&self, e: &[Vector2<f64>]) -> Vec<Vector2<f64>> {
        self.point
            .u
            .iter()
            .zip(self.du)
            .zip(e)
            .map(|((a, b), e)| a + b + e)
            .collect()
    }

    /// The first step length tried: 1, or the fraction to the boundary
    /// ([`Settings::fraction_to_boundary`]), shortened so that no `α_k` moves by more than
    /// the trust radius ([`Settings::trust_radius`]).
    fn first(&self, grid: &Grid, settings: &Settings) -> f64 {
        let h = grid.h();
        let mut t = if settings.fraction_to_boundary {
            grid.limits
                .max_step(h, &self.point.states, self.du, FRACTION_TO_BOUNDARY, 0.0)
        } else {
            1.0
        };
        if settings.trust_radius.is_finite() {
            let reach = shape_reach(self.du, h);
            if reach * t > settings.trust_radius {
                t = settings.trust_radius / reach;
            }
        }
        t
    }
}

/// Outcome of [`Filter::search`].
pub struct Search {
    /// The accepted point, if a step was.
    pub point: Option<Point>,
    /// The objective `φ` at the current point.
    pub phi: f64,
    /// The last step length tried.
    pub t: f64,
}

impl Filter {
    /// The line search along `step` from a point with terminal defect `c`: steps halving
    /// ([`BACKTRACK`]) from the first (1, or the fraction to the boundary, within the trust
    /// radius) down to [`MIN_STEP`] until the filter accepts one;
    /// a rejected full step that did not lower `θ` is tried once more with the correction
    /// `correction(e)` (the least change of the controls that moves the end by `e`) for the
    /// trial's defect. A step accepted for its progress on the constraint adds the current
    /// point to the filter.
    pub fn search(
        &mut self,
        grid: &Grid,
        step: &Step,
        c: &Vector5<f64>,
        correction: impl Fn(&Vector5<f64>) -> Option<Vec<Vector2<f64>>>,
        settings: &Settings,
    ) -> Search {
        let pt = step.point;
        let theta = c.lp_norm(1);
        let phi = grid.objective(&pt.u, &pt.states);
        let slope = grid.objective_slope(&pt.u, &pt.states, step.du);
        let trial = |u: Vec<Vector2<f64>>| -> Option<(Point, f64, f64)> {
            let p = Point::new(grid, u, step.nu).ok()?;
            let th = grid.terminal.defect(&p.states).lp_norm(1);
            let ph = grid.objective(&p.u, &p.states);
            Some((p, th, ph))
        };
        let mut accepted = None;
        let mut t = step.first(grid, settings);
        // A trial that takes a state past the limit (by more than rounding) would fail in its
        // rollout: it is skipped without one.
        let wall = grid
            .limits
            .max_step(grid.h(), &pt.states, step.du, 1.0, WALL_SLACK);
        while t > MIN_STEP {
            if t <= wall
                && let Some((p, th, ph)) = trial(step.along(t))
            {
                if let Some(kind) = self.acceptable(theta, phi, slope, t, th, ph) {
                    accepted = Some((p, kind));
                    break;
                }
                // Second-order correction of a rejected full step that did not lower θ.
                if t == 1.0
                    && th >= theta
                    && let Some(corr) = correction(&(-grid.terminal.defect(&p.states)))
                    && let Some((q, thq, phq)) = trial(step.corrected(&corr))
                    && let Some(kind) = self.acceptable(theta, phi, slope, 1.0, thq, phq)
                {
                    accepted = Some((q, kind));
                    break;
                }
            }
            t *= BACKTRACK;
        }
        if let Some((_, StepKind::Constraint)) = accepted {
            self.add(theta, phi);
        }
        Search {
            point: accepted.map(|(p, _)| p),
            phi,
            t,
        }
    }
}
