//! `purcell.solve`: the command line's checks (`purcell-sim solve`), then the solver on a
//! thread of its own while the caller's thread, the GIL released, waits, calls `progress` and
//! checks for Ctrl-C.

use crate::{InputError, NoSolution, input_error, solution};
use purcell_sim::cli::MAX_STARTS;
use purcell_sim::cli::args::{ModelArgs, OutDirArgs, PrintArgs, ProblemArgs};
use purcell_sim::cli::solve::{SearchArgs, SolveArgs, checked_problem};
use purcell_solver::problem::Problem;
use purcell_solver::solver::{self, SolveError, SolveOptions};
use pyo3::exceptions::PyUserWarning;
use pyo3::prelude::*;
use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering::Relaxed};
use std::sync::{Condvar, Mutex};
use std::time::{Duration, Instant};

/// How often the waiting thread calls `progress` and checks for signals.
const POLL: Duration = Duration::from_millis(100);

/// The solver's outcome, or the panic that ended it (a cancel included).
type Outcome = std::thread::Result<Result<solver::Solution, SolveError>>;

/// The payload a cancelled solve unwinds with (from its progress tick).
struct Cancelled;

/// The cheapest admissible gait that moves the swimmer from the origin to `target`
/// (MODEL.md §4), as `purcell-sim solve` finds it, with the same defaults and checks.
///
/// target: (x, y, theta), metres and radians (theta taken modulo 2 pi into ]-pi, pi]).
/// horizon: T, seconds, a whole number of steps. step: h, seconds. alpha0: the start and end
/// shape, radians. links: (L0 middle, L1 front, L2 rear), metres. drag: k. ratio: normal over
/// tangential drag. alpha_max: joint limit |alpha_i| <= alpha_max, radians, below pi (None:
/// only the links' overlap). starts: budget of start loops (1 to 4096). seed: orders the
/// starts. checkpoint_every: costate checkpoint spacing in steps (None: 100; 0: none).
/// progress: called as progress(done, total) every 0.1 s and at the end, from the calling
/// thread: start loops finished of starts + 1 (the zero loop included), as the command line's
/// progress bar counts them.
///
/// The GIL is released while the solver runs (on all cores); Ctrl-C, or an exception raised
/// by `progress`, cancels the search. Raises InputError (a ValueError, the command line's
/// message) for bad input and NoSolution where the command line exits 3.
#[pyfunction]
#[pyo3(signature = (
    target, *, horizon = 100.0, step = 0.01, alpha0 = vec![0.0, 0.0],
    links = vec![1.0, 1.0, 1.0], drag = 1.0, ratio = 2.0, alpha_max = None,
    starts = SolveOptions::default().starts as i64, seed = 0, checkpoint_every = None,
    progress = None
))]
#[allow(clippy::too_many_arguments)]
pub fn solve(
    py: Python<'_>,
    target: Vec<f64>,
    horizon: f64,
    step: f64,
    alpha0: Vec<f64>,
    links: Vec<f64>,
    drag: f64,
    ratio: f64,
    alpha_max: Option<f64>,
    starts: i64,
    seed: u64,
    checkpoint_every: Option<u32>,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<Py<solution::Solution>> {
    let Ok(starts) = usize::try_from(starts) else {
        return Err(input_error(format!(
            "--starts must be 1 to {MAX_STARTS} (got {starts})"
        )));
    };
    let args = SolveArgs {
        target,
        problem: ProblemArgs {
            horizon,
            step,
            alpha0,
            model: ModelArgs { links, drag, ratio },
            search: SearchArgs { starts, seed },
            alpha_max,
        },
        checkpoint_every,
        no_plots: true,
        degrees: false,
        from: None,
        output: OutDirArgs {
            out: Default::default(),
            force: false,
        },
        print: PrintArgs { json: false },
    };
    let (problem, every) = checked_problem(&args).map_err(|f| InputError::new_err(f.message))?;
    let options = SolveOptions {
        starts,
        seed,
        ..SolveOptions::default()
    };
    let t0 = Instant::now();
    let found = run(py, &problem, &options, progress.as_ref())?;
    let seconds = t0.elapsed().as_secs_f64();
    let found = found.map_err(|e| no_solution(py, &e))?;
    if let Some(e) = found.search.as_ref().filter(|e| !e.satisfied) {
        let message = format!(
            "the search used its budget of {} starts before its stopping rule was met \
             (estimated chance that another start finds an unseen minimum no dearer than the \
             gait returned: {:.3}); this is the cheapest gait found: raise starts to search on",
            e.budget, e.unseen
        );
        PyErr::warn(
            py,
            &py.get_type::<PyUserWarning>(),
            &std::ffi::CString::new(message)?,
            1,
        )?;
    }
    solution::build(py, &problem, &found, every, seconds)
}

/// [`NoSolution`] for `e`, with `best_residual` and `best_alpha`.
fn no_solution(py: Python<'_>, e: &SolveError) -> PyErr {
    let (residual, alpha) = match *e {
        SolveError::Unreachable { best_residual } => (Some(best_residual), None),
        SolveError::NotRefined { best_residual, .. } => (Some(best_residual), None),
        SolveError::NoneAdmissible { best_alpha, .. } => (None, Some(best_alpha)),
    };
    let err = NoSolution::new_err(e.to_string());
    let value = err.value(py);
    match value
        .setattr("best_residual", residual)
        .and_then(|()| value.setattr("best_alpha", alpha))
    {
        Ok(()) => err,
        Err(e) => e,
    }
}

/// Runs the solver on a thread of its own; meanwhile, with the GIL released, waits, and every
/// [`POLL`] calls `progress` and checks for signals. An error from either cancels the solve
/// (at its next finished start) and is returned once the solver thread has stopped.
fn run(
    py: Python<'_>,
    problem: &Problem,
    options: &SolveOptions,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<Result<solver::Solution, SolveError>> {
    let done = AtomicUsize::new(0);
    let cancel = AtomicBool::new(false);
    let slot: (Mutex<Option<Outcome>>, Condvar) = (Mutex::new(None), Condvar::new());
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
            let outcome = catch_unwind(AssertUnwindSafe(|| solver::solve(problem, options, &tick)));
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
            let checked = progress.map_or(Ok(()), |p| {
                p.call1((done.load(Relaxed), options.starts + 1)).map(drop)
            });
            if let Err(e) = checked.and_then(|()| py.check_signals()) {
                cancel.store(true, Relaxed);
                interrupted = Some(e);
            }
        };
        if let (None, Some(p)) = (&interrupted, progress) {
            p.call1((done.load(Relaxed), options.starts + 1))?;
        }
        match (interrupted, outcome) {
            (Some(e), _) => Err(e),
            (None, Ok(found)) => Ok(found),
            (None, Err(panic)) => resume_unwind(panic),
        }
    })
}
