//! Long work off the Python thread: the work runs on a thread of its own while the caller's
//! thread, the GIL released, waits, calls `progress` and checks for Ctrl-C.

use purcell_solver::solver::Progress;
use pyo3::prelude::*;
use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering::Relaxed};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

/// How often the waiting thread calls `progress` and checks for signals.
const POLL: Duration = Duration::from_millis(100);

/// The payload a cancelled job unwinds with (from its progress tick).
struct Cancelled;

/// What the job has told of its progress, read by the waiting thread; a tick or pulse after
/// `cancel` unwinds the job.
#[derive(Default)]
struct Shared {
    phase: Mutex<(String, usize)>,
    done: AtomicUsize,
    cancel: AtomicBool,
}

impl Shared {
    fn check(&self) {
        if self.cancel.load(Relaxed) {
            resume_unwind(Box::new(Cancelled));
        }
    }

    /// `(done, total, phase)` now; with `end`, the phase completed: `(total, total, phase)`.
    fn now(&self, end: bool) -> (usize, usize, String) {
        let (phase, total) = self.phase.lock().unwrap_or_else(|p| p.into_inner()).clone();
        let done = if end {
            total
        } else {
            self.done.load(Relaxed).min(total)
        };
        (done, total, phase)
    }
}

impl Progress for Shared {
    fn phase(&self, name: &str, total: usize, _: &str) {
        self.check();
        *self.phase.lock().unwrap_or_else(|p| p.into_inner()) = (name.to_string(), total);
        self.done.store(0, Relaxed);
    }

    fn tick(&self) {
        self.check();
        self.done.fetch_add(1, Relaxed);
    }

    fn pulse(&self) {
        self.check();
    }
}

/// Runs `job` on a thread of its own, giving it a [`Progress`] to tell as it goes; meanwhile,
/// with the GIL released, waits, and every [`POLL`] calls `progress(done, total, phase)` and
/// checks for signals. An error from either cancels the job (its next tick or pulse unwinds)
/// and is returned once the job's thread has stopped; at the end `progress` is called once
/// more, with the last phase complete: `(total, total, phase)`.
pub(crate) fn run<T: Send>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    job: impl FnOnce(&dyn Progress) -> T + Send,
) -> PyResult<T> {
    let shared = Shared::default();
    let slot: (Mutex<Option<std::thread::Result<T>>>, Condvar) = (Mutex::new(None), Condvar::new());
    let (shared, slot) = (&shared, &slot);
    let wait = |timeout: Duration| {
        py.detach(|| {
            let guard = slot.0.lock().unwrap_or_else(|p| p.into_inner());
            let (mut guard, _) = slot
                .1
                .wait_timeout_while(guard, timeout, |o| o.is_none())
                .unwrap_or_else(|p| p.into_inner());
            guard.take()
        })
    };
    std::thread::scope(|s| {
        s.spawn(move || {
            let outcome = catch_unwind(AssertUnwindSafe(|| job(shared)));
            *slot.0.lock().unwrap_or_else(|p| p.into_inner()) = Some(outcome);
            slot.1.notify_all();
        });
        let mut interrupted: Option<PyErr> = None;
        let outcome = loop {
            if let Some(outcome) = wait(POLL) {
                break outcome;
            }
            if interrupted.is_some() {
                continue;
            }
            let checked = progress.map_or(Ok(()), |p| p.call1(shared.now(false)).map(drop));
            if let Err(e) = checked.and_then(|()| py.check_signals()) {
                shared.cancel.store(true, Relaxed);
                interrupted = Some(e);
            }
        };
        if let (None, Some(p)) = (&interrupted, progress) {
            p.call1(shared.now(true))?;
        }
        match (interrupted, outcome) {
            (Some(e), _) => Err(e),
            (None, Ok(found)) => Ok(found),
            (None, Err(panic)) => resume_unwind(panic),
        }
    })
}
