//! Fixed-horizon replay of the control law from an initial costate, without a heap.
//!
//! [`Replay`] is an iterator over the `N` steps: item `k` is the state `(α_k, g_k)`, the
//! control `u_k` and the costate `ξ^k`. The work per item is one [`Kinematics::law_step`].
//! After the last step, [`Replay::state`] is `(α_N, g_N)`.
//!
//! In `f32` the costate `ξ` drifts (it integrates `h·B_k·u_k` in rounding arithmetic, and
//! the boundary-value problem is ill-conditioned), while `μ` is exactly constant. Costate
//! checkpoints `(k, ξ^{k−1})`, taken from an `f64` solution, reset `ξ` at chosen steps and
//! so bound the drift; [`Checkpoints`] stores them in fixed capacity.

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

/// The shape costate `ξ^{k−1}` to use at step `k`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Checkpoint<T> {
    /// Step index `k`.
    pub k: u32,
    /// `ξ^{k−1}`.
    pub xi: Vector2<T>,
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
    /// one's, [`Error::NonFinite`], [`Error::CapacityExceeded`] when full. A refused
    /// checkpoint leaves the table as it was.
    pub fn push(&mut self, checkpoint: Checkpoint<T>) -> Result<(), Error> {
        if !(checkpoint.xi.x.is_finite() && checkpoint.xi.y.is_finite()) {
            return Err(Error::NonFinite);
        }
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
    xi: Vector2<T>,
    state: State<T>,
    k: u32,
    steps: u32,
    checkpoints: &'a [Checkpoint<T>],
    failed: bool,
}

impl<'a, T: Real> Replay<'a, T> {
    /// A replay of `steps` steps. `checkpoints` must be strictly increasing in `k` with
    /// `k < steps` (a [`Checkpoints`] table's slice is); pass `&[]` for none.
    ///
    /// Errors: [`Error::NonFinite`], [`Error::ShapeLimit`] for the start state or costate,
    /// [`Error::CheckpointOrder`] for a malformed checkpoint list.
    pub fn new(
        kinematics: Kinematics<T>,
        start: State<T>,
        costate: Costate<T>,
        steps: u32,
        checkpoints: &'a [Checkpoint<T>],
    ) -> Result<Self, Error> {
        start.check()?;
        let finite = |v: &[T]| v.iter().all(|x| x.is_finite());
        if !(finite(costate.mu.as_slice()) && finite(costate.xi.as_slice())) {
            return Err(Error::NonFinite);
        }
        let mut last: Option<u32> = None;
        for c in checkpoints {
            if c.k >= steps || last.is_some_and(|l| l >= c.k) {
                return Err(Error::CheckpointOrder);
            }
            if !finite(c.xi.as_slice()) {
                return Err(Error::NonFinite);
            }
            last = Some(c.k);
        }
        Ok(Replay {
            kinematics,
            mu: costate.mu,
            xi: costate.xi,
            state: start,
            k: 0,
            steps,
            checkpoints,
            failed: false,
        })
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
        for item in self.by_ref() {
            item?;
        }
        Ok(self.state)
    }
}

impl<T: Real> Iterator for Replay<'_, T> {
    type Item = Result<Sample<T>, Error>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failed || self.k >= self.steps {
            return None;
        }
        if let Some((first, rest)) = self.checkpoints.split_first()
            && first.k == self.k
        {
            self.xi = first.xi;
            self.checkpoints = rest;
        }
        match self.kinematics.law_step(&self.state, &self.xi, &self.mu) {
            Ok(step) => {
                let sample = Sample {
                    k: self.k,
                    state: self.state,
                    u: step.u,
                    xi: step.xi,
                };
                self.state = step.next;
                self.xi = step.xi;
                self.k += 1;
                Some(Ok(sample))
            }
            Err(e) => {
                self.failed = true;
                Some(Err(e))
            }
        }
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = if self.failed {
            0
        } else {
            (self.steps - self.k) as usize
        };
        (0, Some(left))
    }
}

impl<T: Real> core::iter::FusedIterator for Replay<'_, T> {}
