//! The discrete optimal-control problem (MODEL.md §4) and the validation of its inputs.
//!
//! Minimise `J = Σ_{k<N} h/2·|u_k|²` (or another [`Cost`], MODEL.md §11) subject to the
//! exact kinematics, `α_0 = ᾱ`, `α_N = β` (the end shape; `β = ᾱ` for a loop, the default),
//! `g_0 = e`, `g_N = ḡ`, with `N = T/h` a whole number of steps.

use nalgebra::{Vector2, Vector3};
use purcell_core::gait::{CheckpointRecord, GaitParams};
use purcell_core::{Kinematics, Real, Se2, Swimmer};

/// Largest horizon accepted, in steps (the replay is linear in `N`; this keeps a run bounded).
pub const MAX_STEPS: u64 = 10_000_000;

/// Why the inputs of a problem were refused, before any work.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum InputError {
    /// A number is NaN or infinite.
    #[error("{0} must be a finite number")]
    NonFinite(&'static str),
    /// `h ≤ 0`.
    #[error("step h must be positive (got {0:?} s)")]
    Step(f64),
    /// `T ≤ 0`.
    #[error("horizon T must be positive (got {0:?} s)")]
    Horizon(f64),
    /// `T/h` is not a whole number.
    #[error(
        "horizon T = {horizon:?} s is not a whole number of steps h = {step:?} s (T/h = {ratio:?})"
    )]
    NotWholeSteps {
        /// `T`.
        horizon: f64,
        /// `h`.
        step: f64,
        /// `T/h`.
        ratio: f64,
    },
    /// `T/h` above [`MAX_STEPS`].
    #[error("horizon needs {0:e} steps, more than the limit {MAX_STEPS}")]
    TooManySteps(f64),
    /// A non-positive link length, drag coefficient or drag ratio.
    #[error("{0} must be positive (got {1:?})")]
    NonPositive(&'static str, f64),
    /// `|α0_i| ≥ π` or beyond the admissibility limit.
    #[error(
        "alpha0 = ({0:?}, {1:?}) rad: each |alpha0_i| must be below alpha-max = {2:?} rad (at most pi)"
    )]
    ShapeOutOfRange(f64, f64, f64),
    /// The end shape `|β_i| ≥ π` or beyond the admissibility limit.
    #[error(
        "alpha-end = ({0:?}, {1:?}) rad: each |alpha-end_i| must be below alpha-max = {2:?} rad (at most pi)"
    )]
    EndOutOfRange(f64, f64, f64),
    /// The joint limit is outside `]0, π[`.
    #[error("alpha-max must be in ]0, pi[ rad: the links overlap at pi (got {0:?})")]
    AlphaMax(f64),
    /// The connection cannot be computed at `ᾱ` (or `β`): the swimmer's parameters, not the
    /// law.
    #[error(
        "the swimmer's connection A(alpha) cannot be computed at {at} with links {} m and \
         drag ratio {ratio}: {why}",
        list(links)
    )]
    Connection {
        /// `"alpha0"` or `"alpha-end"`.
        at: &'static str,
        /// `(L0, L1, L2)`.
        links: [f64; 3],
        /// `r`.
        ratio: f64,
        /// What went wrong (the drag matrix is degenerate, or `ᾱ` rounds to the limit).
        why: &'static str,
    },
    /// Valid in `f64`, but not in the precision the result is also replayed in.
    #[error("{what} in {precision}, the precision the costate is also replayed in")]
    Precision {
        /// What does not fit.
        what: String,
        /// `"f32"`.
        precision: &'static str,
    },
}

/// Numbers as they are typed on the command line: `1e39,1.0,1.0`.
fn list(values: &[f64]) -> String {
    values
        .iter()
        .map(|v| format!("{v:?}"))
        .collect::<Vec<_>>()
        .join(",")
}

/// Why `Swimmer::connection_with_derivatives` failed at an admissible `ᾱ`, in words that
/// blame the parameters (the drag matrix `W_ξ`), not the control law.
fn connection_failure(e: purcell_core::Error) -> &'static str {
    match e {
        purcell_core::Error::ShapeLimit => {
            "the shape rounds to the link-overlap limit |alpha_i| = pi"
        }
        _ => {
            "its drag matrix is numerically singular or overflows (parameters of too \
             different scales)"
        }
    }
}

/// `Ok` if every value converts to `T` finite (and nonzero where `positive`).
pub fn check_fits<T: Real>(
    name: &str,
    values: &[f64],
    positive: bool,
    precision: &'static str,
) -> Result<(), InputError> {
    let fits = |x: f64| {
        let y = T::from_f64(x);
        y.is_finite() && !(positive && y <= T::zero())
    };
    if values.iter().all(|&x| fits(x)) {
        Ok(())
    } else {
        Err(InputError::Precision {
            what: format!("{name} = {} overflows or rounds to zero", list(values)),
            precision,
        })
    }
}

/// `Ok` if a stored gait (`params` and `checkpoints`) is also valid replayed in scalar `T`
/// (named `precision` in messages): its problem ([`Problem::check_precision`]), and every
/// costate and checkpoint number finite there.
pub fn check_gait_precision<T: Real>(
    params: &GaitParams,
    checkpoints: impl IntoIterator<Item = CheckpointRecord>,
    precision: &'static str,
) -> Result<(), InputError> {
    Problem::of_gait(params)?.check_precision::<T>(precision)?;
    check_fits::<T>("mu", &params.mu, false, precision)?;
    check_fits::<T>("xi0", &params.xi0, false, precision)?;
    for c in checkpoints {
        let at = |what| format!("{what} of the checkpoint at k = {}", c.k);
        check_fits::<T>(&at("alpha"), &c.alpha, false, precision)?;
        check_fits::<T>(&at("g"), &c.g, false, precision)?;
        check_fits::<T>(&at("xi"), &c.xi, false, precision)?;
    }
    Ok(())
}

/// The inputs of a solve, as given by a user (SI units, radians).
#[derive(Clone, Debug, PartialEq)]
pub struct Spec {
    /// Target `ḡ = (x, y, θ)`, metres and radians.
    pub target: [f64; 3],
    /// Horizon `T`, seconds.
    pub horizon: f64,
    /// Time step `h`, seconds.
    pub step: f64,
    /// Start shape `ᾱ`, radians.
    pub alpha0: [f64; 2],
    /// End shape `β`, radians; `None`: `β = ᾱ` (a loop).
    pub alpha_end: Option<[f64; 2]>,
    /// Link lengths `(L0 middle, L1 front, L2 rear)`, metres.
    pub links: [f64; 3],
    /// Drag coefficient `k`.
    pub drag: f64,
    /// Drag ratio `r` (normal over tangential).
    pub ratio: f64,
    /// Joint limit `|α_i| ≤ α_max` along the whole path, radians, below `π`; `None`: only
    /// the links' overlap, `|α_i| < π`.
    pub alpha_max: Option<f64>,
    /// The running cost minimised (MODEL.md §11).
    pub cost: Cost,
}

impl Default for Spec {
    /// The paper's experiment: `ḡ = (0.1, 0.1, 0)`, `T = 100 s`, `h = 0.01 s`, `ᾱ = 0`,
    /// a loop, unit links, `k = 1`, `r = 2`, no joint limit, the joints' effort.
    fn default() -> Self {
        Spec {
            target: [0.1, 0.1, 0.0],
            horizon: 100.0,
            step: 0.01,
            alpha0: [0.0, 0.0],
            alpha_end: None,
            links: [1.0; 3],
            drag: 1.0,
            ratio: 2.0,
            alpha_max: None,
            cost: Cost::Effort,
        }
    }
}

/// The costs a problem can minimise (MODEL.md §11): the core's, whose law replays their
/// costates; their evaluation is `crate::solver::cost`'s.
pub use purcell_core::Cost;

/// `Ok` if the start shape and the end shape `end` of `spec` lie strictly within its joint
/// limit (or the overlap without one).
fn within_bound(spec: &Spec, end: [f64; 2]) -> Result<(), InputError> {
    let bound = spec.alpha_max.unwrap_or(OVERLAP);
    let inside = |[x, y]: [f64; 2]| x.abs() < bound && y.abs() < bound;
    let [[a1, a2], [b1, b2]] = [spec.alpha0, end];
    if !inside(spec.alpha0) {
        Err(InputError::ShapeOutOfRange(a1, a2, bound))
    } else if !inside(end) {
        Err(InputError::EndOutOfRange(b1, b2, bound))
    } else {
        Ok(())
    }
}

/// Relative excess over the joint limit counted as rounding ([`Problem::admits`]).
pub const LIMIT_ROUNDING: f64 = 1e-13;

/// Where the links overlap, `|α_i| = π`: every admissible shape has `|α_i| <` [`OVERLAP`],
/// and a joint limit lies below it.
pub const OVERLAP: f64 = core::f64::consts::PI;

/// A validated problem.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Problem {
    /// Swimmer parameters.
    pub swimmer: Swimmer<f64>,
    /// Time step `h`, seconds.
    pub h: f64,
    /// Number of steps `N`.
    pub steps: u32,
    /// `ᾱ`, the start shape.
    pub alpha0: Vector2<f64>,
    /// `β`, the end shape (`ᾱ` for a loop).
    pub alpha_end: Vector2<f64>,
    /// `ḡ` as `(x, y, θ)`.
    pub target: Vector3<f64>,
    /// Joint limit `|α_i| ≤ α_max` along the whole path, radians, in `]0, π[`; `None`: only the
    /// links' overlap, `|α_i| <` [`OVERLAP`].
    pub alpha_max: Option<f64>,
    /// The running cost minimised (MODEL.md §11).
    pub cost: Cost,
}

impl Problem {
    /// Validates a [`Spec`]. Every refusal names the offending input.
    pub fn new(spec: &Spec) -> Result<Self, InputError> {
        let finite = |name: &'static str, v: &[f64]| {
            if v.iter().all(|x| x.is_finite()) {
                Ok(())
            } else {
                Err(InputError::NonFinite(name))
            }
        };
        finite("target", &spec.target)?;
        finite("horizon", &[spec.horizon])?;
        finite("step", &[spec.step])?;
        finite("alpha0", &spec.alpha0)?;
        let end = spec.alpha_end.unwrap_or(spec.alpha0);
        finite("alpha-end", &end)?;
        finite("links", &spec.links)?;
        finite("drag", &[spec.drag])?;
        finite("ratio", &[spec.ratio])?;
        if let Some(a) = spec.alpha_max {
            finite("alpha-max", &[a])?;
        }
        if spec.step <= 0.0 {
            return Err(InputError::Step(spec.step));
        }
        if spec.horizon <= 0.0 {
            return Err(InputError::Horizon(spec.horizon));
        }
        let ratio = spec.horizon / spec.step;
        if ratio > MAX_STEPS as f64 {
            return Err(InputError::TooManySteps(ratio));
        }
        let steps = ratio.round();
        if steps < 1.0 || (ratio - steps).abs() > 1e-9 * steps.max(1.0) {
            return Err(InputError::NotWholeSteps {
                horizon: spec.horizon,
                step: spec.step,
                ratio,
            });
        }
        for (name, v) in [
            ("link length L0", spec.links[0]),
            ("link length L1", spec.links[1]),
            ("link length L2", spec.links[2]),
            ("drag k", spec.drag),
            ("drag ratio r", spec.ratio),
        ] {
            if v <= 0.0 {
                return Err(InputError::NonPositive(name, v));
            }
        }
        if let Some(a) = spec.alpha_max
            && !(a > 0.0 && a < OVERLAP)
        {
            return Err(InputError::AlphaMax(a));
        }
        let ([a1, a2], [b1, b2]) = (spec.alpha0, end);
        within_bound(spec, end)?;
        let swimmer = Swimmer::new(spec.links, spec.drag, spec.ratio)
            .map_err(|_| InputError::NonPositive("swimmer parameter", f64::NAN))?;
        for (at, [x, y]) in [("alpha0", spec.alpha0), ("alpha-end", end)] {
            swimmer
                .connection_with_derivatives(&Vector2::new(x, y))
                .map_err(|e| InputError::Connection {
                    at,
                    links: spec.links,
                    ratio: spec.ratio,
                    why: connection_failure(e),
                })?;
        }
        Ok(Problem {
            swimmer,
            h: spec.step,
            steps: steps as u32,
            alpha0: Vector2::new(a1, a2),
            alpha_end: Vector2::new(b1, b2),
            target: Vector3::from(spec.target),
            alpha_max: spec.alpha_max,
            cost: spec.cost,
        })
    }

    /// The same problem minimising `cost`.
    pub fn with_cost(self, cost: Cost) -> Self {
        Problem { cost, ..self }
    }

    /// The problem a stored gait (a costate or gait file) belongs to, validated like
    /// command-line input: its `N` within [`MAX_STEPS`] included.
    pub fn of_gait(p: &GaitParams) -> Result<Self, InputError> {
        Problem::new(&Spec {
            target: p.target,
            horizon: p.h * f64::from(p.steps),
            step: p.h,
            alpha0: p.alpha0,
            alpha_end: p.alpha_end,
            links: p.model.links,
            drag: p.model.drag,
            ratio: p.model.ratio,
            alpha_max: p.alpha_max,
            cost: p.cost,
        })
    }

    /// The paper's experiment (MODEL.md §4).
    pub fn paper() -> Self {
        match Problem::new(&Spec::default()) {
            Ok(p) => p,
            // The default spec is valid by construction (tested).
            Err(_) => unreachable!("the paper's problem is valid"),
        }
    }

    /// Whether the end shape is the start shape (a loop, the paper's problem).
    pub fn is_loop(&self) -> bool {
        self.alpha_end == self.alpha0
    }

    /// The end shape as a gait stores it: `None` for a loop ([`GaitParams::alpha_end`]).
    pub fn stored_end(&self) -> Option<[f64; 2]> {
        (!self.is_loop()).then_some([self.alpha_end.x, self.alpha_end.y])
    }

    /// The bound on `|α_i|`: the joint limit, or [`OVERLAP`] without one.
    pub fn shape_bound(&self) -> f64 {
        self.alpha_max.unwrap_or(OVERLAP)
    }

    /// Whether a path whose largest `|α_i|` is `max_abs_alpha` is admissible: within the
    /// joint limit to rounding ([`LIMIT_ROUNDING`]: a path on the limit lands there as the
    /// sum of its steps), or short of the overlap [`OVERLAP`] without one.
    pub fn admits(&self, max_abs_alpha: f64) -> bool {
        match self.alpha_max {
            Some(a) => max_abs_alpha <= a * (1.0 + LIMIT_ROUNDING),
            None => max_abs_alpha < OVERLAP,
        }
    }

    /// The displacement asked for, `|(x̄, ȳ, L0·θ̄)|` (metres; the heading at the middle
    /// link's length).
    pub fn displacement(&self) -> f64 {
        let t = self.target;
        let l = self.swimmer.lengths()[0];
        (t.x * t.x + t.y * t.y + (l * t.z).powi(2)).sqrt()
    }

    /// Horizon `T = N·h`, seconds.
    pub fn horizon(&self) -> f64 {
        self.h * f64::from(self.steps)
    }

    /// The discrete kinematics in scalar type `T` (fails only if a parameter overflows `T`).
    pub fn kinematics<T: Real>(&self) -> Result<Kinematics<T>, purcell_core::Error> {
        let [l0, l1, l2] = self.swimmer.lengths();
        let c = T::from_f64;
        let swimmer = Swimmer::new(
            [c(l0), c(l1), c(l2)],
            c(self.swimmer.drag()),
            c(self.swimmer.ratio()),
        )?;
        Kinematics::new(swimmer, c(self.h))
    }

    /// `Ok` if the problem is also valid in scalar `T` (named `precision` in messages): every
    /// parameter converts finite (and positive where it must be), and the connection can be
    /// computed at `ᾱ` and `β` there.
    pub fn check_precision<T: Real>(&self, precision: &'static str) -> Result<(), InputError> {
        let sw = &self.swimmer;
        check_fits::<T>("links", &sw.lengths(), true, precision)?;
        check_fits::<T>("drag k", &[sw.drag()], true, precision)?;
        check_fits::<T>("drag ratio r", &[sw.ratio()], true, precision)?;
        check_fits::<T>("step h", &[self.h], true, precision)?;
        check_fits::<T>("target", self.target.as_slice(), false, precision)?;
        let kin = self.kinematics::<T>().map_err(|e| InputError::Precision {
            what: format!("the swimmer or step is invalid ({e})"),
            precision,
        })?;
        for (at, shape) in [("alpha0", self.alpha0), ("alpha-end", self.alpha_end)] {
            kin.swimmer()
                .connection_with_derivatives(&shape.map(T::from_f64))
                .map_err(|e| InputError::Precision {
                    what: format!(
                        "the connection A(alpha) cannot be computed at {at}: {}",
                        connection_failure(e)
                    ),
                    precision,
                })?;
        }
        Ok(())
    }

    /// The target `ḡ` in scalar type `T`.
    pub fn target_se2<T: Real>(&self) -> Se2<T> {
        let t = self.target.map(T::from_f64);
        Se2::new(t.x, t.y, t.z)
    }
}
