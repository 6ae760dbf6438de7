//! Long work off the Python thread: the work runs on a thread of its own while the caller's
//! thread, the GIL released, waits, calls `progress` and checks for Ctrl-C.

use pyo3::prelude::*;
use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering::Relaxed};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

/// How often the waiting thread calls `progress` and checks for signals.
const POLL: Duration = Duration::from_millis(100);

/// The payload a cancelled job unwinds with (from its progress tick).
struct Cancelled;

/// Runs `job` on a thread of its own, giving it a tick to call as it goes; meanwhile, with
/// the GIL released, waits, and every [`POLL`] calls `progress(ticks, total)` and checks for
/// signals. An error from either cancels the job (its next tick unwinds) and is returned once
/// the job's thread has stopped; `progress` is called once more at the end.
pub(crate) fn run<T: Send>(
    py: Python<'_>,
    total: usize,
    progress: Option<&Bound<'_, PyAny>>,
    job: impl FnOnce(&(dyn Fn() + Sync)) -> T + Send,
) -> PyResult<T> {
    let done = AtomicUsize::new(0);
    let cancel = AtomicBool::new(false);
    let slot: (Mutex<Option<std::thread::Result<T>>>, Condvar) = (Mutex::new(None), Condvar::new());
    let (done, cancel, slot) = (&done, &cancel, &slot);
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
            let tick = || {
                if cancel.load(Relaxed) {
                    resume_unwind(Box::new(Cancelled));
                }
                done.fetch_add(1, Relaxed);
            };
            let outcome = catch_unwind(AssertUnwindSafe(|| job(&tick)));
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
            let checked =
                progress.map_or(Ok(()), |p| p.call1((done.load(Relaxed), total)).map(drop));
            if let Err(e) = checked.and_then(|()| py.check_signals()) {
                cancel.store(true, Relaxed);
                interrupted = Some(e);
            }
        };
        if let (None, Some(p)) = (&interrupted, progress) {
            p.call1((done.load(Relaxed), total))?;
        }
        match (interrupted, outcome) {
            (Some(e), _) => Err(e),
            (None, Ok(found)) => Ok(found),
            (None, Err(panic)) => resume_unwind(panic),
        }
    })
}
