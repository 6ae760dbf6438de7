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
//! README's table). [`Checkpoints`] stores them in fixed capacity.

use crate::kinematics::{Kinematics, State};
use crate::{Error, Real};
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
    /// one's, [`Error::NonFinite`] or [`Error::ShapeLimit`] for its state,
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

/// One replayed step.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sample<T> {
    /// Step index `k`.
    pub k: u32,
    /// `(α_k, g_k)`.
    pub state: State<T>,
    /// `u_k`.
    pub u: Vector2<T>,
    /// `ξ^k`.
    pub xi: Vector2<T>,
}

/// Runs `N` steps of the control law from a start state and an initial costate.
#[derive(Clone, Debug)]
pub struct Replay<'a, T> {
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
    checkpoints: &'a [Checkpoint<T>],
    failed: Option<Error>,
}

impl<'a, T: Real> Replay<'a, T> {
    /// A replay of `steps` steps. `checkpoints` must be strictly increasing in `k` with
    /// `k < steps` (a [`Checkpoints`] table's slice is); pass `&[]` for none.
    ///
    /// Errors: [`Error::NonFinite`], [`Error::ShapeLimit`] for the start state, the costate
    /// or a checkpoint, [`Error::CheckpointOrder`] for a malformed checkpoint list.
    pub fn new(
        kinematics: Kinematics<T>,
        start: State<T>,
        costate: Costate<T>,
        steps: u32,
        checkpoints: &'a [Checkpoint<T>],
    ) -> Result<Self, Error> {
        start.check()?;
        let (mu, xi) = (costate.mu, costate.xi);
        if !T::all_finite([mu.x, mu.y, mu.z, xi.x, xi.y]) {
            return Err(Error::NonFinite);
        }
        let mut last: Option<u32> = None;
        for c in checkpoints {
            if c.k >= steps || last.is_some_and(|l| l >= c.k) {
                return Err(Error::CheckpointOrder);
            }
            c.check()?;
            last = Some(c.k);
        }
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
            checkpoints,
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
        if let Some((first, rest)) = self.checkpoints.split_first()
            && first.k == self.k
        {
            self.state = first.state;
            self.xi = first.xi;
            self.checkpoints = rest;
        }
        // The state and ξ were checked by `new` (start, checkpoints) or as the previous
        // step's outputs, and μ by `new`.
        match self
            .kinematics
            .law_step_trusted(&self.state, &self.xi, &self.mu, T::PASSES)
        {
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

    /// The current state: `(α_k, g_k)` before step `k`, `(α_N, g_N)` at the end.
    pub fn state(&self) -> &State<T> {
        &self.state
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
}

/// Owned samples; after an error the iterator yields it once and then ends.
impl<T: Real> Iterator for Replay<'_, T> {
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

impl<T: Real> core::iter::FusedIterator for Replay<'_, T> {}
