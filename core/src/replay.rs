//! Fixed-horizon replay of the control law from an initial costate, without a heap.
//!
//! [`Replay::step`] runs one step in place and lends the step's [`Sample`] (state
//! `(α_k, g_k)`, control `u_k`, costate `ξ^k`); [`Replay`] is also an iterator of owned
//! samples. The work per step is one control-law step. After the last step,
//! [`Replay::state`] is `(α_N, g_N)`.
//!
//! The forward recursion is unstable: the boundary-value problem has a Jacobian condition
//! number near `4·10⁸` on the paper's problem, and in `f32` the rounding of every step grows
//! along the unstable mode until the gait leaves the solution (on the paper's problem an
//! `f32` replay from `(μ, ξ^{−1})` alone ends `1.6·10⁻²` from `ḡ`). [`Checkpoint`]s taken from
//! an `f64` replay reset the recursion's whole state `(α_k, g_k, ξ^{k−1})` at chosen steps, so
//! the error only grows over one checkpoint interval. They must reset all of it: resetting
//! `ξ` alone, against an `(α, g)` that has drifted, puts the recursion on a different
//! extremal, and on the paper's problem that ends past the link-overlap limit (see the
//! README's table). [`Checkpoints`] stores them in fixed capacity; a [`crate::Gait`] keeps them
//! in its file, and [`crate::Gait::replay`] reads each one in place when the replay reaches it.
//!
//! [`Replay::fly`] runs a replay to the end and digests it ([`Flight`]): what the host and a
//! microcontroller compare. [`TerminalError`] is how far a replay ends from `(ᾱ, ḡ)`.

use crate::arc::{Arc, ArcTable, Exits};
use crate::cost::{Cost, Effort, RunningCost};
use crate::kinematics::{Kinematics, State};
use crate::law::{Free, LawStep, OnArcs, Rows};
use crate::sample::Sample;
use crate::table::{Table, VALUES};
use crate::{Error, Real, Se2, TrajectoryDigest};
use core::marker::PhantomData;
use nalgebra::{Vector2, Vector3};

/// The initial costate: constant spatial momentum `μ` and `ξ^{−1}`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Costate<T> {
    /// Spatial momentum `μ ∈ se(2)*`, components `(x, y, θ)`.
    pub mu: Vector3<T>,
    /// Shape costate before the first step, `ξ^{−1}`.
    pub xi: Vector2<T>,
}

/// The recursion's state at the start of step `k`, from a reference (`f64`) replay.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Checkpoint<T> {
    /// Step index `k`.
    pub k: u32,
    /// `(α_k, g_k)`.
    pub state: State<T>,
    /// `ξ^{k−1}`.
    pub xi: Vector2<T>,
}

impl<T: Real> Checkpoint<T> {
    /// The checkpoint of a stored record's values `α1 α2 x y cos θ sin θ ξ1 ξ2` (`g` as
    /// stored, not renormalised).
    #[inline]
    pub(crate) fn from_values(k: u32, [a1, a2, x, y, c, s, x1, x2]: [T; VALUES]) -> Self {
        Checkpoint {
            k,
            state: State {
                alpha: Vector2::new(a1, a2),
                g: Se2::from_rotation(x, y, c, s),
            },
            xi: Vector2::new(x1, x2),
        }
    }

    /// `Ok` if the state is admissible and every number finite.
    fn check(&self) -> Result<(), Error> {
        self.state.check()?;
        if T::all_finite([self.xi.x, self.xi.y]) {
            Ok(())
        } else {
            Err(Error::NonFinite)
        }
    }
}

/// Up to `CAP` checkpoints with strictly increasing step indices.
#[derive(Clone, Debug, Default)]
pub struct Checkpoints<T, const CAP: usize>(heapless::Vec<Checkpoint<T>, CAP>);

impl<T: Real, const CAP: usize> Checkpoints<T, CAP> {
    /// An empty table.
    pub const fn new() -> Self {
        Checkpoints(heapless::Vec::new())
    }

    /// Appends a checkpoint. Errors: [`Error::CheckpointOrder`] unless `k` is above the last
    /// one's, [`Error::NonFinite`], [`Error::ShapeLimit`] or [`Error::NotRotation`] for
    /// its state (see [`State::check`]),
    /// [`Error::CapacityExceeded`] when full. A refused checkpoint leaves the table as it was.
    pub fn push(&mut self, checkpoint: Checkpoint<T>) -> Result<(), Error> {
        checkpoint.check()?;
        if self.0.last().is_some_and(|last| last.k >= checkpoint.k) {
            return Err(Error::CheckpointOrder);
        }
        self.0.push(checkpoint).map_err(|_| Error::CapacityExceeded)
    }

    /// The checkpoints in order.
    pub fn as_slice(&self) -> &[Checkpoint<T>] {
        &self.0
    }
}

/// Where a replay's checkpoints come from: a slice, or a gait file's table read in place.
#[derive(Clone, Copy, Debug)]
pub(crate) enum CheckpointTable<'a, T> {
    /// Checkpoints in memory (e.g. a [`Checkpoints`] table).
    Slice(&'a [Checkpoint<T>]),
    /// A [`crate::Gait`]'s table stored in `T`.
    Stored(Table<'a>),
}

impl<T: Real> CheckpointTable<'_, T> {
    /// The step index of the next checkpoint.
    #[inline]
    fn next_k(&self) -> Option<u32> {
        match self {
            CheckpointTable::Slice(s) => s.first().map(|c| c.k),
            CheckpointTable::Stored(t) => t.next_k(),
        }
    }

    /// Removes the next checkpoint.
    #[inline]
    fn pop(&mut self) -> Option<Checkpoint<T>> {
        match self {
            CheckpointTable::Slice(s) => s.split_first().map(|(first, rest)| {
                *s = rest;
                *first
            }),
            CheckpointTable::Stored(t) => {
                t.pop_values().map(|(k, v)| Checkpoint::from_values(k, v))
            }
        }
    }
}

/// Runs `N` steps of the control law of the running cost `C` ([`crate::cost`]; the effort by
/// default) from a start state and an initial costate, with the joint-limit arcs of a
/// constrained gait ([`crate::arc`]) if it has any.
#[derive(Clone, Debug)]
pub struct Replay<'a, T, C = Effort> {
    kinematics: Kinematics<T>,
    mu: Vector3<T>,
    /// The step just done (its `state` is `(α_k, g_k)`, its `xi` is `ξ^k`).
    sample: Sample<T>,
    /// `(α_k, g_k)` for the next step `k`.
    state: State<T>,
    /// `ξ^{k−1}` for the next step.
    xi: Vector2<T>,
    k: u32,
    steps: u32,
    /// The next step at which a checkpoint is due or an arc begins (`u32::MAX`, which `k`
    /// never reaches, if none): the one comparison a step makes for both.
    next_event: u32,
    /// The step index of the next checkpoint (`u32::MAX` if none).
    next_checkpoint: u32,
    /// The first step of the next arc (`u32::MAX` if none).
    next_arc: u32,
    checkpoints: CheckpointTable<'a, T>,
    /// Whether the checkpoints that are no arc's exit are restored too.
    periodic: bool,
    /// The arcs not yet entered, in order.
    arcs: ArcTable<'a>,
    /// The last state of each joint's latest arc (0: none yet).
    arc_ends: [u32; 2],
    /// The joints on an arc at this step.
    on_arcs: OnArcs,
    /// The running cost whose law the replay runs.
    law: PhantomData<C>,
    failed: Option<Error>,
}

impl<'a, T: Real> Replay<'a, T> {
    /// A replay of `steps` steps. `checkpoints` must be strictly increasing in `k` with
    /// `k < steps` (a [`Checkpoints`] table's slice is); pass `&[]` for none.
    ///
    /// Errors: [`Error::NonFinite`], [`Error::ShapeLimit`], [`Error::NotRotation`] for the
    /// start state, the costate or a checkpoint (see [`State::check`]),
    /// [`Error::CheckpointOrder`] for a malformed checkpoint list.
    pub fn new(
        kinematics: Kinematics<T>,
        start: State<T>,
        costate: Costate<T>,
        steps: u32,
        checkpoints: &'a [Checkpoint<T>],
    ) -> Result<Self, Error> {
        Self::with_arcs(kinematics, start, costate, steps, checkpoints, &[])
    }

    /// [`Replay::new`] for a constrained gait: on an arc the law keeps the joint at rest
    /// ([`Kinematics::law_step`] with the joints on arcs), and each arc's exit restores its
    /// checkpoint (MODEL.md §9).
    ///
    /// Errors: those of [`Replay::new`], [`Error::ArcInvalid`] and [`Error::ArcOrder`] (see
    /// [`crate::arc::check`]), [`Error::ArcCheckpoint`] if an arc's `last` has no checkpoint.
    pub fn with_arcs(
        kinematics: Kinematics<T>,
        start: State<T>,
        costate: Costate<T>,
        steps: u32,
        checkpoints: &'a [Checkpoint<T>],
        arcs: &'a [Arc],
    ) -> Result<Self, Error> {
        Self::with_tables(
            kinematics,
            start,
            costate,
            steps,
            CheckpointTable::Slice(checkpoints),
            ArcTable::Slice(arcs),
            true,
        )
    }
}

impl<'a, T: Real, C: RunningCost> Replay<'a, T, C> {
    /// A replay with checkpoints from a slice or a gait file's table, and arcs likewise.
    /// Without `periodic`, only the arcs' exits restore their checkpoints (and only theirs are
    /// checked): the replay from `(μ, ξ^{−1})` and the arc table alone.
    pub(crate) fn with_tables(
        kinematics: Kinematics<T>,
        start: State<T>,
        costate: Costate<T>,
        steps: u32,
        checkpoints: CheckpointTable<'a, T>,
        arcs: ArcTable<'a>,
        periodic: bool,
    ) -> Result<Self, Error> {
        start.check()?;
        let (mu, xi) = (costate.mu, costate.xi);
        if !T::all_finite([mu.x, mu.y, mu.z, xi.x, xi.y]) {
            return Err(Error::NonFinite);
        }
        crate::arc::check(arcs, steps)?;
        let mut exits = Exits::new(arcs);
        let mut last: Option<u32> = None;
        let mut table = checkpoints;
        while let Some(c) = table.pop() {
            if c.k >= steps || last.is_some_and(|l| l >= c.k) {
                return Err(Error::CheckpointOrder);
            }
            let exit = exits.at(c.k)? != [None; 2];
            if periodic || exit {
                c.check()?;
            }
            last = Some(c.k);
        }
        exits.finish()?;
        let next_checkpoint = checkpoints.next_k().unwrap_or(u32::MAX);
        let next_arc = arcs.next_first().unwrap_or(u32::MAX);
        Ok(Replay {
            kinematics,
            mu: costate.mu,
            sample: Sample {
                k: 0,
                state: start,
                u: Vector2::zeros(),
                xi: costate.xi,
            },
            state: start,
            xi: costate.xi,
            k: 0,
            steps,
            next_event: next_checkpoint.min(next_arc),
            next_checkpoint,
            next_arc,
            checkpoints,
            periodic,
            arcs,
            arc_ends: [0; 2],
            on_arcs: OnArcs::NONE,
            law: PhantomData,
            failed: None,
        })
    }

    /// Runs step `k` in place and lends its sample; `Ok(None)` once all steps are done.
    ///
    /// Errors: the step's (see [`Kinematics::law_step`]); the replay then stays failed and
    /// returns the same error again.
    #[inline]
    pub fn step(&mut self) -> Result<Option<&Sample<T>>, Error> {
        if let Some(e) = self.failed {
            return Err(e);
        }
        if self.k >= self.steps {
            return Ok(None);
        }
        if self.k == self.next_event {
            self.event();
        }
        // A constant: each cost's replay compiles only its own branch.
        if C::COST != Cost::Effort {
            return if self.on_arcs == OnArcs::NONE {
                self.step_law(Free)
            } else {
                self.step_law(self.on_arcs)
            };
        }
        if self.on_arcs != OnArcs::NONE {
            return self.step_on_arcs();
        }
        // The state and ξ were checked by `new` (start, checkpoints) or as the previous
        // step's outputs, and μ by `new`.
        let step = self.kinematics.law_step_trusted(
            &self.state,
            &self.xi,
            &self.mu,
            Effort,
            Free,
            T::PASSES,
        );
        self.record(step)
    }

    /// [`Replay::step`] of the effort on an arc: the law with the joints on it at rest
    /// ([`Kinematics::law_step`] with the joints on arcs). Out of line, so that the free step
    /// stays the code it is without arcs (measured on the M4F: an arc step costs no more than a
    /// free one).
    #[inline(never)]
    fn step_on_arcs(&mut self) -> Result<Option<&Sample<T>>, Error> {
        let step = self.kinematics.law_step_trusted(
            &self.state,
            &self.xi,
            &self.mu,
            Effort,
            self.on_arcs,
            T::PASSES,
        );
        self.record(step)
    }

    /// [`Replay::step`] of a cost other than the effort ([`Kinematics::law_step_for`]) solving
    /// `rows`: [`Free`] off the arcs (no test of the joints in its solves), the joints off their
    /// arcs on one. Out of line, as [`Replay::step_on_arcs`].
    #[inline(never)]
    fn step_law<R: Rows<T>>(&mut self, rows: R) -> Result<Option<&Sample<T>>, Error> {
        let step = self.kinematics.law_step_of(
            C::COST,
            &self.state,
            &self.xi,
            &self.mu,
            rows,
            C::COST.passes::<T>(),
        );
        self.record(step)
    }

    /// The running cost whose law the replay runs, `C`'s.
    pub fn cost(&self) -> Cost {
        C::COST
    }

    /// Takes the result of step `k`: the sample, the next state and `ξ^k`, or the failure.
    #[inline(always)]
    fn record(&mut self, step: Result<LawStep<T>, Error>) -> Result<Option<&Sample<T>>, Error> {
        match step {
            Ok(step) => {
                self.sample = Sample {
                    k: self.k,
                    state: self.state,
                    u: step.u,
                    xi: step.xi,
                };
                self.state = step.next;
                self.xi = step.xi;
                self.k += 1;
                Ok(Some(&self.sample))
            }
            Err(e) => {
                self.failed = Some(e);
                Err(e)
            }
        }
    }

    /// At a step where a checkpoint is due or an arc begins (an arc ends where a checkpoint
    /// is due: `new` checked that): enters the arcs that begin here, restores
    /// `(α_k, g_k, ξ^{k−1})` from the checkpoint due here (validated by `new`; skipped unless
    /// `periodic` or an arc exits here), and sets the joints on an arc and the next event.
    /// Inlined: a call would cost a checkpoint's step more than its restore (M4F).
    #[inline(always)]
    fn event(&mut self) {
        let k = self.k;
        if k == self.next_arc {
            self.enter_arcs();
        }
        if k == self.next_checkpoint {
            if let Some(c) = self.checkpoints.pop()
                && (self.periodic || self.arc_ends.contains(&k))
            {
                self.state = c.state;
                self.xi = c.xi;
            }
            // An arc may exit here.
            if self.arc_ends != [0; 2] {
                self.on_arcs = OnArcs(self.arc_ends.map(|end| k < end));
            }
            self.next_checkpoint = self.checkpoints.next_k().unwrap_or(u32::MAX);
        }
        self.next_event = self.next_checkpoint.min(self.next_arc);
    }

    /// Enters the arcs that begin at this step (at most one per joint in a checked table; each
    /// turn takes one).
    #[inline(never)]
    fn enter_arcs(&mut self) {
        let k = self.k;
        while k == self.next_arc {
            if let Some(a) = self.arcs.next()
                && let Some(end) = self.arc_ends.get_mut(a.index())
            {
                *end = a.last;
            }
            self.next_arc = self.arcs.next_first().unwrap_or(u32::MAX);
        }
        self.on_arcs = OnArcs(self.arc_ends.map(|end| k < end));
    }

    /// The current state: `(α_k, g_k)` before step `k`, `(α_N, g_N)` at the end.
    pub fn state(&self) -> &State<T> {
        &self.state
    }

    /// The sample [`Replay::step`] lent last (`None` before the first step): for a caller
    /// that cannot keep the borrow between steps, such as the C API.
    pub fn last_sample(&self) -> Option<&Sample<T>> {
        (self.k > 0).then_some(&self.sample)
    }

    /// The joints at rest on a joint-limit arc at the step [`Replay::step`] did last
    /// ([`OnArcs::NONE`] before the first step and off the arcs).
    pub fn on_arcs(&self) -> OnArcs {
        self.on_arcs
    }

    /// The current shape costate `ξ^{k−1}`.
    pub fn xi(&self) -> &Vector2<T> {
        &self.xi
    }

    /// Steps done so far (the index of the next step).
    pub fn steps_done(&self) -> u32 {
        self.k
    }

    /// Runs the remaining steps and returns the final state `(α_N, g_N)`.
    pub fn finish(mut self) -> Result<State<T>, Error> {
        while self.step()?.is_some() {}
        Ok(self.state)
    }

    /// Runs the remaining steps through `step` (which must advance the replay by one step in
    /// place, as [`Replay::step`] does: pass it, or a wrapper that times it) and digests every
    /// sample it lends, then the final state ([`TrajectoryDigest::push_sample`],
    /// [`TrajectoryDigest::push_state`]). Two runs that compute the same numbers have the same
    /// [`Flight`]: this is what the host and a microcontroller compare.
    ///
    /// Errors: the first error of a step.
    pub fn fly<F>(mut self, mut step: F) -> Result<Flight<T>, Error>
    where
        F: for<'r> FnMut(&'r mut Self) -> Result<Option<&'r Sample<T>>, Error>,
    {
        let mut digest = TrajectoryDigest::new();
        while let Some(sample) = step(&mut self)? {
            digest.push_sample(sample);
        }
        digest.push_state(&self.state);
        Ok(Flight {
            digest,
            end: self.state,
            steps: self.k,
        })
    }
}

/// A finished replay: the digest of its trajectory and where it ended ([`Replay::fly`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Flight<T> {
    /// Every sample `(u_k, α_k, g_k)`, then `(α_N, g_N)`.
    pub digest: TrajectoryDigest,
    /// `(α_N, g_N)`.
    pub end: State<T>,
    /// Steps run.
    pub steps: u32,
}

impl<T: Real> Flight<T> {
    /// The bit patterns of `(α1, α2, x, y, cos θ, sin θ)` of the final state (widened to 64
    /// bits for `f32`, as in the digest).
    pub fn final_bits(&self) -> [u64; 6] {
        let (a, g) = (&self.end.alpha, &self.end.g);
        [a.x, a.y, g.x(), g.y(), g.cos(), g.sin()].map(T::to_bits)
    }
}

/// How far a replay ends from `(ᾱ, ḡ)`: the largest absolute component of `α_N − ᾱ` (rad) and
/// of `log(ḡ⁻¹ g_N)` (`(x, y, θ)`: m, m, rad), computed in `f64` from the final state widened
/// to `f64`.
///
/// The one terminal error of this workspace (`purcell-sim replay`, the firmware checker and the
/// documentation quote it). The largest component rather than a Euclidean norm: the
/// components have different units, and the solver's residuals are largest components too.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TerminalError {
    /// `max |α_N,i − ᾱ_i|`, radians.
    pub alpha: f64,
    /// `max |log(ḡ⁻¹ g_N)_j|`, metres or radians.
    pub g: f64,
}

impl TerminalError {
    /// The error of `end` against `alpha_bar` and `target`.
    pub fn new<T: Real>(end: &State<T>, alpha_bar: &Vector2<f64>, target: &Se2<f64>) -> Self {
        let (a, g) = (&end.alpha, &end.g);
        let theta = g.sin().to_f64().atan2(g.cos().to_f64());
        let g = Se2::new(g.x().to_f64(), g.y().to_f64(), theta);
        let largest = |xs: &[f64]| xs.iter().fold(0.0, |m: f64, x| m.max(x.abs()));
        let log = target.between(&g).log();
        TerminalError {
            alpha: largest(&[a.x.to_f64() - alpha_bar.x, a.y.to_f64() - alpha_bar.y]),
            g: largest(&[log.x, log.y, log.z]),
        }
    }
}

/// Owned samples; after an error the iterator yields it once and then ends.
impl<T: Real, C: RunningCost> Iterator for Replay<'_, T, C> {
    type Item = Result<Sample<T>, Error>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failed.is_some() {
            return None;
        }
        self.step().map(|s| s.copied()).transpose()
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = if self.failed.is_some() {
            0
        } else {
            (self.steps - self.k) as usize
        };
        (0, Some(left))
    }
}

impl<T: Real, C: RunningCost> core::iter::FusedIterator for Replay<'_, T, C> {}
