//! Flights of a gait through a plant whose parameters differ from the model's.
//!
//! The law runs on the model (as firmware does: [`purcell_core::Replay`] with its checkpoints)
//! and gives the nominal state `(α_k, g_k)` and control `u_k^nom` at each step; the plant, a
//! [`Kinematics`] with its own drag ratio and link lengths, is driven by the control flown:
//! `α_{k+1} = α_k + h·u_k`, `g_{k+1} = g_k·exp(−h·A_plant(α_k)·u_k)`.
//!
//! - [`Control::Open`]: `u_k = u_k^nom`, the replay of the gait as it is;
//! - [`Control::Closed`]: [`purcell_core::tracking::Tracker`] with the table of
//!   [`super::gains`], on the measured state (the plant's state plus Gaussian noise,
//!   [`Noise`]).

use super::gains::Table;
use crate::seeded::{GOLDEN_GAMMA, splitmix64};
use nalgebra::Vector2;
use purcell_core::cost::RunningCost;
use purcell_core::gait::{Stored, WithReplay};
use purcell_core::tracking::{Tracker, rounded, tracking_error};
use purcell_core::{
    Error, Gait, Kinematics, Real, Replay, Sample, Se2, State, TerminalError, TrajectoryDigest,
};

/// Gaussian measurement noise: standard deviations of the pose `(x, y, θ)` (m, rad) and of
/// the joint angles (rad), from a seeded generator.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Noise {
    /// Of each of `x`, `y`, `θ`.
    pub pose: f64,
    /// Of each joint angle.
    pub shape: f64,
    /// Seed of the generator.
    pub seed: u64,
}

/// Standard normal draws by Box–Muller on SplitMix64 ([`splitmix64`]).
struct Gaussian(u64);

impl Gaussian {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(GOLDEN_GAMMA);
        // (0, 1]: 53 random bits, offset by half a unit so that ln never sees 0.
        ((splitmix64(self.0) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    fn normal(&mut self) -> f64 {
        let (u1, u2) = (self.uniform(), self.uniform());
        (-2.0 * u1.ln()).sqrt() * (2.0 * core::f64::consts::PI * u2).cos()
    }
}

/// A sensor with [`Noise`]: its draws in order, one reading after another.
pub struct Sensor {
    noise: Noise,
    rng: Gaussian,
}

impl Sensor {
    /// A sensor with `noise`, its generator at `noise.seed`.
    pub fn new(noise: &Noise) -> Self {
        Sensor {
            noise: *noise,
            rng: Gaussian(noise.seed),
        }
    }

    /// `state` as measured: each number plus its noise (the exact state without noise).
    pub fn measure(&mut self, state: &State<f64>) -> State<f64> {
        let (noise, rng) = (&self.noise, &mut self.rng);
        let mut m = *state;
        if noise.shape > 0.0 {
            m.alpha += Vector2::new(rng.normal(), rng.normal()) * noise.shape;
        }
        if noise.pose > 0.0 {
            let g = &state.g;
            let d = [rng.normal(), rng.normal(), rng.normal()].map(|n| n * noise.pose);
            m.g = Se2::new(g.x() + d[0], g.y() + d[1], g.theta() + d[2]);
        }
        m
    }
}

/// How the plant is controlled.
#[derive(Clone, Copy, Debug)]
pub enum Control<'a> {
    /// The nominal controls.
    Open,
    /// The tracking law with its table, the joints clamped to `|α_i| ≤ limit`
    /// ([`purcell_core::tracking::joint_bound`]).
    Closed {
        /// The records.
        table: &'a Table,
        /// The joints' bound.
        limit: f64,
    },
}

/// A finished flight.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// The plant's final state.
    pub end: State<f64>,
    /// `Σ h/2·|u_k|²` of the controls flown.
    pub cost: f64,
    /// `max_k max_i |α_{k,i}|` of the plant.
    pub max_abs_alpha: f64,
    /// The tracking law's final estimate `ε̂` of the drag ratio's relative error (0 open loop).
    pub estimate: f64,
    /// Per step `k = 0 … N−1`, the plant's pose error against the nominal pose before the
    /// step (the larger pose component of [`TerminalError`] against the nominal state).
    pub deviation: Vec<f64>,
    /// [`TrajectoryDigest`] of the flight: per step the control flown and the plant's state
    /// before it, then its final state (what firmware's closed-loop flight prints).
    pub digest: u64,
}

/// A flight that stopped: the step and why.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("step {step}: {error}")]
pub struct FlightFailure {
    /// The step that failed.
    pub step: u32,
    /// Why.
    pub error: Error,
}

/// Flies the nominal samples `nominal` (a model replay in `T`, e.g. `f32` as on the M4F)
/// through `plant` (in `f64`) from `start` under `control`, measuring with `noise`; the
/// tracking law runs in `T` on the measured state and the table rounded to `T`.
///
/// Errors: the first step that fails (the replay's, the tracking law's or the plant's, e.g.
/// a joint driven to the overlap limit), or [`Error::CapacityExceeded`] if the replay has
/// more steps than its table.
pub fn fly<T: Real, I>(
    nominal: I,
    plant: &Kinematics<f64>,
    start: State<f64>,
    control: Control<'_>,
    noise: &Noise,
) -> Result<Outcome, FlightFailure>
where
    I: Iterator<Item = Result<Sample<T>, Error>>,
{
    let mut sensor = Sensor::new(noise);
    let mut tracker = Tracker::<T>::new();
    let (limit_t, h_t) = match control {
        Control::Closed { limit, .. } => (T::from_f64(limit), T::from_f64(plant.h())),
        Control::Open => (T::zero(), T::from_f64(plant.h())),
    };
    let (mut state, mut cost, mut max_abs_alpha) = (start, 0.0, 0.0f64);
    let (mut deviation, mut digest) = (Vec::new(), TrajectoryDigest::new());
    let h = plant.h();
    for (k, sample) in nominal.enumerate() {
        let step = k as u32;
        let fail = |error| FlightFailure { step, error };
        let sample = sample.map_err(fail)?;
        let nominal = State {
            alpha: sample.state.alpha.map(T::to_f64),
            g: Se2::from_rotation(
                sample.state.g.x().to_f64(),
                sample.state.g.y().to_f64(),
                sample.state.g.cos().to_f64(),
                sample.state.g.sin().to_f64(),
            ),
        };
        deviation.push(pose_deviation(&nominal, &state));
        max_abs_alpha = max_abs_alpha
            .max(state.alpha.x.abs())
            .max(state.alpha.y.abs());
        let u = match control {
            Control::Open => sample.u,
            Control::Closed { table, .. } => {
                let (record, first) = table.at(k).ok_or(fail(Error::CapacityExceeded))?;
                let record = record.map(T::from_f64);
                let measured = rounded::<T>(&sensor.measure(&state));
                let e = tracking_error(&sample.state, &measured);
                if first {
                    tracker.update(&record, &e);
                }
                let joints = rounded::<T>(&state).alpha;
                tracker
                    .control(&record, &sample.u, &e, &joints, Some(limit_t), h_t)
                    .map_err(fail)?
            }
        }
        .map(T::to_f64);
        cost += 0.5 * h * u.norm_squared();
        digest.push(u.x);
        digest.push(u.y);
        digest.push_state(&state);
        state = plant.step(&state, &u).map_err(fail)?;
    }
    max_abs_alpha = max_abs_alpha
        .max(state.alpha.x.abs())
        .max(state.alpha.y.abs());
    digest.push_state(&state);
    Ok(Outcome {
        end: state,
        cost,
        max_abs_alpha,
        estimate: tracker.estimate().to_f64(),
        deviation,
        digest: digest.value(),
    })
}

/// The larger component of the pose error of `state` against `nominal`.
pub fn pose_deviation(nominal: &State<f64>, state: &State<f64>) -> f64 {
    TerminalError::new(state, &nominal.alpha, &nominal.g).g
}

/// [`fly`] of `gait`'s replay in `T` with its checkpoints, the law of the gait's own cost
/// ([`Gait::with_replay`]), from the gait's start: the flight, or why it stopped.
///
/// Errors: the replay's, before any step (the gait cannot be replayed in `T`).
pub fn fly_gait<T: Stored>(
    gait: &Gait<'_>,
    plant: &Kinematics<f64>,
    control: Control<'_>,
    noise: &Noise,
) -> Result<Result<Outcome, FlightFailure>, Error> {
    /// [`fly`] of a replay of any cost.
    struct Flying<'p> {
        plant: &'p Kinematics<f64>,
        start: State<f64>,
        control: Control<'p>,
        noise: &'p Noise,
    }
    impl<'a, T: Stored> WithReplay<'a, T> for Flying<'_> {
        type Output = Result<Outcome, FlightFailure>;
        fn run<C: RunningCost>(self, replay: Replay<'a, T, C>) -> Self::Output {
            fly(replay, self.plant, self.start, self.control, self.noise)
        }
    }
    let start = gait.params().start();
    gait.with_replay::<T, _>(
        true,
        Flying {
            plant,
            start,
            control,
            noise,
        },
    )
}
