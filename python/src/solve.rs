//! `purcell.solve`: the library layer's checks (those of `purcell-sim solve`), then the
//! solver on a thread of its own while the caller's thread, the GIL released, waits, calls
//! `progress` and checks for Ctrl-C.

use crate::keywords::ProblemKw;
use crate::{detach, error, input_error, refused, solution};
use purcell_sim::find::{Unsolved, find};
use purcell_sim::report::search_warnings;
use purcell_sim::spec;
use purcell_sim::words::{Front, Worded};
use purcell_solver::solver::SolveError;
use purcell_solver::solver::continuation::Warm;
use pyo3::exceptions::PyUserWarning;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// `purcell.solve` (python/purcell/_solve.py documents it): the problem's keywords checked as
/// the command line checks its flags, the solve from `warm` or the global search.
#[pyfunction]
pub fn solve(
    py: Python<'_>,
    target: [f64; 3],
    problem: ProblemKw,
    warm: Option<Bound<'_, PyAny>>,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<Py<solution::Solution>> {
    let prepared = spec::prepare(&problem.solve_spec(target)?).map_err(refused)?;
    let warm = warm.map(|w| warm_start(&w)).transpose()?;
    let found = detach::run(py, progress.as_ref(), |progress| {
        find(&prepared, warm.as_ref(), progress)
    })?;
    let found = found.map_err(|u| no_solution(py, &u))?;
    for note in &found.notes {
        warn(py, note.words(Front::Python))?;
    }
    for w in search_warnings(&found.solution) {
        warn(py, w.words(Front::Python))?;
    }
    let checkpoint_every = prepared.checkpoint_every;
    solution::build(
        py,
        &found.problem,
        &found.solution,
        checkpoint_every,
        found.seconds,
    )
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

/// `purcell.NoSolution` for `u` (its error and what to try), with `best_residual` and
/// `best_alpha`.
fn no_solution(py: Python<'_>, u: &Unsolved) -> PyErr {
    let (residual, alpha) = match u.error {
        SolveError::Unreachable { best_residual } => (Some(best_residual), None),
        SolveError::NotRefined { best_residual, .. } => (Some(best_residual), None),
        SolveError::NoneAdmissible { best_alpha, .. } => (None, Some(best_alpha)),
    };
    let attrs = PyDict::new(py);
    match attrs
        .set_item("best_residual", residual)
        .and_then(|()| attrs.set_item("best_alpha", alpha))
    {
        Ok(()) => error("NoSolution", u.words(Front::Python), Some(&attrs)),
        Err(e) => e,
    }
}
