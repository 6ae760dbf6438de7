//! `robustness --replan`: a gait flown through a mismatched plant, re-planned from the measured
//! state with the estimated plant (docs/ROBUSTNESS.md, "Re-planning"; MODEL.md §12).
//!
//! The flight starts on the gait's own controls (the open loop). At step [`Rule::from`] and
//! every [`Rule::every`] steps after it, while at least [`Rule::left`] of the horizon is
//! left, [`estimate::fit`] fits the drag ratio's relative error `ε̂` to the flight so far. If
//! a drag-ratio error does not explain the data ([`estimate::Fit::verdict`]: a link-length
//! error, say), the estimate is given up and the flight stays on its current plan to the end
//! (the open loop, if no re-plan came before). Otherwise, whenever `|ε̂ − ε̂_plan|` exceeds
//! both [`Rule::moved`] and [`SIGNIFICANT`] standard errors of `ε̂` (`ε̂_plan` the estimate of
//! the current plan, 0 for the gait), the rest is
//! re-planned: the transition problem from the state `(α_k, ĝ_k)` over the time left
//! `(N − k)h`, the model at drag ratio `r(1 + ε̂)`, target `ĝ_k⁻¹ḡ` and end shape the gait's,
//! solved by [`find`] from the current plan's remaining controls (its costates carried to the
//! frame at step `k`: `μ' = Ad_{g_k}ᵀμ`), the global search where that reaches no admissible
//! extremal; at the first re-plan (where the estimate jumps from 0 and the gait's family may
//! no longer be the cheapest, or may leave the shapes) also the global search, the cheaper
//! kept. The flight goes on with the new plan's controls.
//!
//! The state: `α_k = ᾱ + h·Σ_{j<k} u_j`, the joint angles as commanded (the joints follow
//! their commands exactly, in plant and model: MODEL.md §10; the encoders' noise does not
//! enter), and `ĝ_k` the pose the fit's model predicts from every pose measured so far
//! ([`estimate::Fit::pose`]), not the last measurement alone.

pub mod estimate;

use estimate::Verdict;

use crate::find::{Note, find};
use crate::spec::{CHECKPOINT_EVERY, Prepared};
use nalgebra::{Vector2, Vector3};
use purcell_core::gait::GaitParams;
use purcell_core::{Kinematics, State};
use purcell_solver::problem::{Problem, Spec};
use purcell_solver::solver::continuation::Warm;
use purcell_solver::solver::progress::Within;
use purcell_solver::solver::{Progress, SolveOptions, Trajectory};
use purcell_solver::tracking::{FlightFailure, Noise, Sensor, pose_deviation};
use serde::Serialize;
use std::time::Instant;

/// When the flight is estimated and re-planned (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rule {
    /// The step of the first estimate.
    pub from: u32,
    /// Steps between estimates.
    pub every: u32,
    /// The least share of the horizon left for an estimate and re-plan.
    pub left: f64,
    /// The change of `ε̂` since the current plan that re-plans.
    pub moved: f64,
    /// The global search's options where the warm start fails.
    pub options: SolveOptions,
}

impl Default for Rule {
    /// From step 500 (5 s of the paper's gait, the tracking law's first estimate), every 500
    /// steps while a fifth of the horizon is left, re-planning on a change of 0.001 in `ε̂`
    /// (a tenth of a percent of `r`) beyond three standard errors; the search with 128 starts.
    fn default() -> Self {
        Rule {
            from: 500,
            every: 500,
            left: 0.2,
            moved: 0.001,
            options: SolveOptions {
                starts: Some(128),
                min_starts: Some(64),
                ..SolveOptions::default()
            },
        }
    }
}

/// How many standard errors of `ε̂` a change must exceed to re-plan (besides
/// [`Rule::moved`]): a noise-driven estimate does not re-plan.
pub const SIGNIFICANT: f64 = 3.0;

/// One re-plan.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Replan {
    /// Its step `k`.
    pub step: u32,
    /// `k·h`, seconds.
    pub time: f64,
    /// The estimate `ε̂` it planned with.
    pub ratio_error: f64,
    /// The fit's residual over the drift ([`estimate::Fit`]).
    pub unexplained: f64,
    /// The new plan's cost over the time left.
    pub cost: f64,
    /// How it was found: `"warm start"`, `"global search"` or `"overlap margin"` (the
    /// search's cheapest within the overlap's margin, [`Note::OverlapMargin`]); or why it
    /// failed (the flight stays on its plan).
    pub route: String,
    /// Wall seconds it took.
    pub seconds: f64,
}

/// A re-planned flight.
#[derive(Clone, Debug, PartialEq)]
pub struct Replanned {
    /// The plant's final state.
    pub end: State<f64>,
    /// `Σ h/2·|u_k|²` flown.
    pub cost: f64,
    /// Largest `|α_i|` of the plant.
    pub max_abs_alpha: f64,
    /// The last estimate `ε̂` (0 if none).
    pub estimate: f64,
    /// The pose error against the gait's nominal pose, per step.
    pub deviation: Vec<f64>,
    /// The re-plans, in order.
    pub replans: Vec<Replan>,
    /// Why the estimate was given up, if it was (module docs).
    pub given_up: Option<String>,
}

/// A plan: a trajectory in its own frame (its first pose the identity) from flight step
/// `first` on, with its momentum.
struct Plan {
    first: usize,
    t: Trajectory,
    mu: Vector3<f64>,
}

impl Plan {
    /// `Σ h/2·|u_k|²` of its controls.
    fn cost(&self, h: f64) -> f64 {
        self.t
            .controls
            .iter()
            .map(|u| 0.5 * h * u.norm_squared())
            .sum()
    }

    /// The warm start of `problem` (from flight step `k`) from this plan's remaining controls,
    /// its momentum carried to the frame of its pose at `k`, its target where the controls
    /// take `problem`'s model; `None` if they leave the shapes.
    fn warm(&self, k: usize, problem: &Problem) -> Option<Warm> {
        let j = k - self.first;
        let controls = self.t.controls.get(j..)?.to_vec();
        let mu = self.t.states.get(j)?.g.adjoint_transpose_mul(&self.mu);
        let kin = problem.kinematics::<f64>().ok()?;
        let mut s = State::at_origin(problem.alpha0);
        for u in &controls {
            s = kin.step(&s, u).ok()?;
        }
        let t = Trajectory {
            states: vec![s],
            controls,
            xis: vec![*self.t.xis.last()?],
        };
        Warm::from_trajectory(&t, &mu, problem.horizon())
    }
}

/// What a flight re-plans with: the gait, its nominal trajectory (the `f64` replay with its
/// costates, [`purcell_solver::tracking::nominal`]) and the rule.
pub struct Replanner<'a> {
    /// The gait's parameters.
    pub params: &'a GaitParams,
    /// Its nominal trajectory.
    pub nominal: &'a Trajectory,
    /// When to estimate and re-plan.
    pub rule: Rule,
}

/// What steers the flight: its plan, the estimate it was planned with (`None`: the gait), the
/// last estimate, the re-plans so far, and why the estimate was given up, if it was.
struct Steering {
    plan: Plan,
    planned: Option<f64>,
    estimate: f64,
    replans: Vec<Replan>,
    given_up: Option<String>,
}

/// The flight so far: the plant's state, what was measured and flown.
struct Flight {
    state: State<f64>,
    /// The joint angles as commanded.
    alpha: Vector2<f64>,
    /// Per step: the joint angles as commanded and the pose as measured.
    measured: Vec<State<f64>>,
    flown: Vec<Vector2<f64>>,
    cost: f64,
    max_abs_alpha: f64,
    deviation: Vec<f64>,
}

impl<'a> Replanner<'a> {
    /// The gait of `params` with its nominal trajectory, by the default [`Rule`].
    pub fn new(params: &'a GaitParams, nominal: &'a Trajectory) -> Self {
        Replanner {
            params,
            nominal,
            rule: Rule::default(),
        }
    }

    /// Whether step `k` estimates (module docs).
    fn due(&self, k: usize) -> bool {
        let (r, n) = (&self.rule, self.params.steps as usize);
        let (from, every) = (r.from as usize, r.every.max(1) as usize);
        k >= from && (k - from).is_multiple_of(every) && (n - k) as f64 >= r.left * n as f64
    }

    /// Flies the gait through `plant`, measured with `noise`, re-planning by the rule (module
    /// docs); `progress` pulsed within the re-plans.
    ///
    /// Errors: the plant's step that fails.
    pub fn fly(
        &self,
        plant: &Kinematics<f64>,
        noise: &Noise,
        progress: &dyn Progress,
    ) -> Result<Replanned, FlightFailure> {
        let p = self.params;
        let mut sensor = Sensor::new(noise);
        let mut s = Steering {
            plan: Plan {
                first: 0,
                t: self.nominal.clone(),
                mu: Vector3::from(p.mu),
            },
            planned: None,
            estimate: 0.0,
            replans: Vec::new(),
            given_up: None,
        };
        let mut f = Flight {
            state: p.start(),
            alpha: Vector2::from(p.alpha0),
            measured: Vec::new(),
            flown: Vec::new(),
            cost: 0.0,
            max_abs_alpha: 0.0,
            deviation: Vec::new(),
        };
        for k in 0..self.nominal.controls.len() {
            let fail = |error| FlightFailure {
                step: k as u32,
                error,
            };
            f.measured.push(State {
                alpha: f.alpha,
                g: sensor.measure(&f.state).g,
            });
            f.deviation
                .push(pose_deviation(&self.nominal.states[k], &f.state));
            f.max_abs_alpha = f.max_abs_alpha.max(f.state.alpha.amax());
            if s.given_up.is_none() && self.due(k) {
                self.steer(k, &f, &mut s, noise.pose, progress)
                    .map_err(fail)?;
            }
            let u = s.plan.t.controls[k - s.plan.first];
            f.cost += 0.5 * p.h * u.norm_squared();
            f.flown.push(u);
            f.alpha += u * p.h;
            f.state = plant.step(&f.state, &u).map_err(fail)?;
        }
        Ok(Replanned {
            end: f.state,
            cost: f.cost,
            max_abs_alpha: f.max_abs_alpha.max(f.state.alpha.amax()),
            estimate: s.estimate,
            deviation: f.deviation,
            replans: s.replans,
            given_up: s.given_up,
        })
    }

    /// At an estimate's step `k` of flight `f` (pose noise `sigma`): the fit's verdict, and a
    /// re-plan if it calls for one (module docs), into `s`.
    ///
    /// Errors: the fit's.
    fn steer(
        &self,
        k: usize,
        f: &Flight,
        s: &mut Steering,
        sigma: f64,
        progress: &dyn Progress,
    ) -> Result<(), purcell_core::Error> {
        let p = self.params;
        let model = p.kinematics::<f64>()?;
        let fit = estimate::fit(&model, &p.start::<f64>().g, &f.measured, &f.flown)?;
        let (e, error) = match fit.verdict(sigma) {
            Verdict::Agrees => return Ok(()),
            Verdict::Unexplained(share) => {
                s.given_up = Some(format!(
                    "at step {k}: a drag-ratio error leaves {:.0} % of the drift unexplained \
                     (at most {:.0} %): kept on the current plan",
                    100.0 * share,
                    100.0 * estimate::UNEXPLAINED
                ));
                return Ok(());
            }
            Verdict::Ratio { estimate, error } => (estimate, error),
        };
        let moved = self.rule.moved.max(SIGNIFICANT * error);
        if (e - s.planned.unwrap_or(0.0)).abs() <= moved {
            return Ok(());
        }
        s.estimate = e;
        let at = State {
            alpha: f.alpha,
            g: fit.pose,
        };
        let t0 = Instant::now();
        let (route, cost) = match self.replan(k, &at, e, &s.plan, progress) {
            Ok((new, route)) => {
                let cost = new.cost(p.h);
                (s.plan, s.planned) = (new, Some(e));
                (route.to_string(), cost)
            }
            Err(why) => (why, f64::NAN),
        };
        s.replans.push(Replan {
            step: k as u32,
            time: p.h * k as f64,
            ratio_error: e,
            unexplained: fit.residual / fit.drift,
            cost,
            route,
            seconds: t0.elapsed().as_secs_f64(),
        });
        Ok(())
    }

    /// The rest of the flight from step `k` at the measured `at`, planned with `ε̂ = eps`
    /// from `plan`: the new plan and how it was found, or why there is none.
    fn replan(
        &self,
        k: usize,
        at: &State<f64>,
        eps: f64,
        plan: &Plan,
        progress: &dyn Progress,
    ) -> Result<(Plan, &'static str), String> {
        let p = self.params;
        let target = at.g.between(&p.target());
        let left = p.steps as usize - k;
        let problem = Problem::new(&Spec {
            target: [target.x(), target.y(), target.theta()],
            horizon: p.h * left as f64,
            step: p.h,
            alpha0: [at.alpha.x, at.alpha.y],
            alpha_end: Some(p.end_shape()),
            links: p.model.links,
            drag: p.model.drag,
            ratio: p.model.ratio * (1.0 + eps),
            alpha_max: p.alpha_max,
            cost: p.cost,
        })
        .map_err(|e| format!("no plan: {e}"))?;
        let prepared = Prepared {
            problem,
            checkpoint_every: CHECKPOINT_EVERY,
            options: self.rule.options,
        };
        let warm = plan.warm(k, &problem);
        let within = Within(progress);
        let found = |warm: Option<&Warm>| {
            let found = find(&prepared, warm, &within).ok()?;
            let route = match (warm, found.notes.last()) {
                (_, Some(Note::OverlapMargin { .. })) => "overlap margin",
                (None, _) | (_, Some(Note::WarmFailed(_))) => "global search",
                (Some(_), None) => "warm start",
            };
            let x = found
                .solution
                .extremals
                .into_iter()
                .nth(found.solution.best)?;
            Some((x, route))
        };
        let warmed = found(warm.as_ref());
        let searched = if plan.first == 0 && warm.is_some() {
            found(None)
        } else {
            None
        };
        let (x, route) = [warmed, searched]
            .into_iter()
            .flatten()
            .min_by(|a, b| a.0.cost.total_cmp(&b.0.cost))
            .ok_or("no plan: neither the warm start nor the search found one")?;
        let plan = Plan {
            first: k,
            t: x.trajectory,
            mu: x.mu,
        };
        Ok((plan, route))
    }
}
