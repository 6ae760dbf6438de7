//! `purcell._purcell`, the native module behind the Python package `purcell`: the solver
//! (`purcell-solver`), the replay through the core (`purcell-core`) and the connection, with
//! the command line's defaults, checks and messages (`purcell-sim`). The Python package
//! (`python/purcell/`) re-exports it with type stubs.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use purcell_sim::spec::SpecError;
use purcell_solver::problem::{Problem, Spec};
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

mod detach;
mod field;
mod replay;
mod solution;
mod solve;
mod sweep;

create_exception!(
    _purcell,
    InputError,
    PyValueError,
    "Bad input, refused before any work, with the command line's message (its exit code 2)."
);
create_exception!(
    _purcell,
    NoSolution,
    PyRuntimeError,
    "The search reached no admissible extremal (the command line's exit code 3). \
     Attributes: `best_residual` (smallest terminal defect reached, m / rad, or None) and \
     `best_alpha` (smallest largest |alpha_i| of the extremals found, rad, or None)."
);
create_exception!(
    _purcell,
    ReplayFailed,
    PyRuntimeError,
    "A replay stopped early (the command line's exit code 3). Attribute: `step`, the step \
     it failed at (None if it did not start)."
);

/// An [`InputError`] with `message`.
pub(crate) fn input_error(message: impl ToString) -> PyErr {
    InputError::new_err(message.to_string())
}

/// The start budget `n` as a count: a negative one is refused with the command line's
/// `--starts` message.
pub(crate) fn starts(n: i64) -> PyResult<usize> {
    usize::try_from(n).map_err(|_| input_error(SpecError::Starts(n.into())))
}

/// Rows of `n` numbers as an `(rows.len(), n)` array.
pub(crate) fn array2<'py, const N: usize>(
    py: Python<'py>,
    rows: impl ExactSizeIterator<Item = [f64; N]>,
) -> Bound<'py, PyArray2<f64>> {
    let len = rows.len();
    let flat: Vec<f64> = rows.flatten().collect();
    match Array2::from_shape_vec((len, N), flat) {
        Ok(a) => a.into_pyarray(py),
        Err(_) => unreachable!("every row has N numbers"),
    }
}

/// A vector as a 1-D array.
pub(crate) fn array1<'py>(py: Python<'py>, v: &[f64]) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, v)
}

/// The local connection at a shape, with its derivatives.
#[pyclass(frozen, module = "purcell", get_all)]
pub struct Connection {
    /// `A(alpha)`, shape (3, 2): rows x, y, theta; columns alpha1, alpha2 (m/rad, m/rad,
    /// rad/rad). The body velocity is `xi = -A(alpha) @ alpha_dot`.
    #[pyo3(name = "A")]
    a: Py<PyArray2<f64>>,
    /// `[dA/dalpha1, dA/dalpha2]`, shape (2, 3, 2), per radian.
    #[pyo3(name = "dA")]
    da: Py<PyAny>,
}

#[pymethods]
impl Connection {
    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        Ok(format!("Connection(A={})", self.a.bind(py).repr()?))
    }
}

/// The local connection A(alpha) of the swimmer and its derivatives (MODEL.md §2).
///
/// alpha: the shape (alpha1, alpha2), radians, each |alpha_i| < pi. links (m), drag and
/// ratio as in `solve`. Raises InputError with the command line's message
/// (`purcell-sim connection`).
#[pyfunction]
#[pyo3(signature = (alpha, *, links = vec![1.0, 1.0, 1.0], drag = 1.0, ratio = 2.0))]
fn connection(
    py: Python<'_>,
    alpha: Vec<f64>,
    links: Vec<f64>,
    drag: f64,
    ratio: f64,
) -> PyResult<Connection> {
    let alpha: [f64; 2] = numbers("alpha", &alpha)?;
    let spec = Spec {
        links: numbers("links", &links)?,
        drag,
        ratio,
        alpha0: alpha,
        ..Spec::default()
    };
    let problem =
        Problem::new(&spec).map_err(|e| input_error(e.to_string().replace("alpha0", "alpha")))?;
    let c = problem
        .swimmer
        .connection_with_derivatives(&nalgebra::Vector2::new(alpha[0], alpha[1]))
        .map_err(input_error)?;
    let rows = |m: &nalgebra::Matrix3x2<f64>| (0..3).map(|r| [m[(r, 0)], m[(r, 1)]]).collect();
    let da: Vec<Vec<[f64; 2]>> = vec![rows(&c.da[0]), rows(&c.da[1])];
    let np = py.import("numpy")?;
    Ok(Connection {
        a: array2(py, (0..3).map(|r| [c.a[(r, 0)], c.a[(r, 1)]])).unbind(),
        da: np.call_method1("array", (da,))?.unbind(),
    })
}

/// `N` numbers of argument `name`, with the command line's message for another count.
pub(crate) fn numbers<const N: usize>(name: &str, v: &[f64]) -> PyResult<[f64; N]> {
    <[f64; N]>::try_from(v).map_err(|_| {
        input_error(format!(
            "--{name} takes {N} comma-separated numbers (got {})",
            v.len()
        ))
    })
}

/// The native module.
#[pymodule]
fn _purcell(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("NoSolution", py.get_type::<NoSolution>())?;
    m.add("ReplayFailed", py.get_type::<ReplayFailed>())?;
    m.add_class::<Connection>()?;
    m.add_class::<solution::Extremal>()?;
    m.add_class::<solution::Solution>()?;
    m.add_class::<replay::Replay>()?;
    m.add_function(wrap_pyfunction!(connection, m)?)?;
    m.add_function(wrap_pyfunction!(solve::solve, m)?)?;
    m.add_function(wrap_pyfunction!(replay::replay, m)?)?;
    m.add_class::<sweep::SweepPlan>()?;
    m.add_class::<field::Field>()?;
    m.add_function(wrap_pyfunction!(field::field, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep_search, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep_refine, m)?)?;
    Ok(())
}
