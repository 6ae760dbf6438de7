//! `purcell.solve`: the command line's checks (`purcell-sim solve`), then the solver on a
//! thread of its own while the caller's thread, the GIL released, waits, calls `progress` and
//! checks for Ctrl-C.

use crate::{NoSolution, detach, input_error, numbers, solution};
use purcell_sim::report::{SearchWarning, search_warnings};
use purcell_sim::spec::{self, SolveSpec};
use purcell_solver::problem::Spec;
use purcell_solver::solver::continuation::{self, Warm};
use purcell_solver::solver::{self, SolveError, SolveOptions};
use pyo3::exceptions::PyUserWarning;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::time::Instant;

/// The cheapest admissible gait that moves the swimmer from the origin to `target`
/// (MODEL.md §4), as `purcell-sim solve` finds it, with the same defaults and checks.
///
/// target: (x, y, theta), metres and radians (theta taken modulo 2 pi into ]-pi, pi]).
/// horizon: T, seconds, a whole number of steps. step: h, seconds. alpha0: the start shape,
/// radians. alpha_end: the end shape, radians (None: alpha0, a closed loop). links: (L0 middle, L1 front, L2 rear), metres. drag: k. ratio: normal over
/// tangential drag. alpha_max: joint limit |alpha_i| <= alpha_max, radians, below pi (None:
/// only the links' overlap). starts: budget of start loops (1 to 4096). seed: orders the
/// starts. checkpoint_every: costate checkpoint spacing in steps (None: 100; 0: none).
/// warm: a Solution, or the path of a costate file (costate.json), whose extremal (replayed)
/// starts the solve (the command line's `--from`): continuation from its target to this one,
/// or the global search with a UserWarning if that reaches no admissible extremal; the same
/// swimmer required. progress: called as progress(done, total, phase) every 0.1 s and at the
/// end with (total, total, phase), from the calling thread: the phases "search" (start loops
/// finished of starts + 1, the zero loop included; the search may stop sooner) and
/// "refinement" (candidates carried to the problem's grid), or with warm "continuation"
/// first, as the command line's progress counts them.
///
/// The GIL is released while the solver runs (on all cores); Ctrl-C, or an exception raised
/// by `progress`, cancels the search. Raises InputError (a ValueError, the command line's
/// message) for bad input and NoSolution where the command line exits 3.
#[pyfunction]
#[pyo3(signature = (
    target, *, horizon = 100.0, step = 0.01, alpha0 = vec![0.0, 0.0], alpha_end = None,
    links = vec![1.0, 1.0, 1.0], drag = 1.0, ratio = 2.0, alpha_max = None,
    starts = SolveOptions::default().starts as i64, seed = 0, checkpoint_every = None,
    warm = None, progress = None
))]
#[allow(clippy::too_many_arguments)]
pub fn solve(
    py: Python<'_>,
    target: Vec<f64>,
    horizon: f64,
    step: f64,
    alpha0: Vec<f64>,
    alpha_end: Option<Vec<f64>>,
    links: Vec<f64>,
    drag: f64,
    ratio: f64,
    alpha_max: Option<f64>,
    starts: i64,
    seed: u64,
    checkpoint_every: Option<u32>,
    warm: Option<Bound<'_, PyAny>>,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<Py<solution::Solution>> {
    let starts = crate::starts(starts)?;
    let spec = SolveSpec {
        problem: Spec {
            target: numbers("target", &target)?,
            horizon,
            step,
            alpha0: numbers("alpha0", &alpha0)?,
            alpha_end: alpha_end.map(|a| numbers("alpha_end", &a)).transpose()?,
            links: numbers("links", &links)?,
            drag,
            ratio,
            alpha_max,
        },
        starts,
        seed,
        checkpoint_every,
    };
    let prepared = spec::prepare(&spec).map_err(input_error)?;
    let (problem, options) = (&prepared.problem, &prepared.options);
    let warm = warm.map(|w| warm_start(&w)).transpose()?;
    let t0 = Instant::now();
    let (found, failed) = detach::run(py, progress.as_ref(), |progress| match &warm {
        None => (solver::solve(problem, options, progress), None),
        Some(w) => continuation::solve_from(problem, w, options, progress),
    })?;
    let seconds = t0.elapsed().as_secs_f64();
    if let Some(e) = failed {
        warn(
            py,
            format!(
                "warm reached no admissible extremal of this problem ({e}); solved by the \
                 global search instead"
            ),
        )?;
    }
    let found = found.map_err(|e| no_solution(py, &e))?;
    warn_search(py, &found)?;
    solution::build(py, problem, &found, prepared.checkpoint_every, seconds)
}

/// The search's warnings: its budget spent before its stopping rule was met; minima it left
/// unrefined that may be cheaper (one warning, for the cheapest).
fn warn_search(py: Python<'_>, found: &solver::Solution) -> PyResult<()> {
    for w in search_warnings(found) {
        let message = match w {
            SearchWarning::BudgetSpent { budget, unseen } => format!(
                "the search used its budget of {budget} starts before its stopping rule was met \
                 (estimated chance that another start finds an unseen minimum no dearer than the \
                 gait returned: {unseen:.3}); this is the cheapest gait found: raise starts to \
                 search on"
            ),
            SearchWarning::Unrefined { cheapest, count } => {
                format!("{cheapest} ({count} such minima): try another seed or more starts")
            }
        };
        warn(py, message)?;
    }
    Ok(())
}

/// A `UserWarning` with `message`.
fn warn(py: Python<'_>, message: String) -> PyResult<()> {
    let message = std::ffi::CString::new(message)?;
    PyErr::warn(py, &py.get_type::<PyUserWarning>(), &message, 1)
}

/// The start `warm` names (`solve --from`): a `Solution`'s extremal (its costate file,
/// replayed) or a costate file's path, of any swimmer.
fn warm_start(warm: &Bound<'_, PyAny>) -> PyResult<Warm> {
    let found = match warm.cast::<solution::Solution>() {
        Ok(s) => spec::warm_of(s.get().file(), "warm"),
        Err(_) => {
            let path: PathBuf = warm.extract().map_err(|_| {
                input_error("warm takes a Solution or the path of a costate file (costate.json)")
            })?;
            spec::warm_start(&path)
        }
    };
    found.map_err(input_error)
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
