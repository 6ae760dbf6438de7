//! `purcell._purcell`, the native module behind the Python package `purcell`: the solver
//! (`purcell-solver`), the replay through the core (`purcell-core`) and the connection, with
//! the command line's checks (`purcell-sim`'s library layer, its refusals in Python's words).
//! The Python package (`python/purcell/`) holds the public signatures, defaults and
//! docstrings and calls these functions with its arguments checked for type and count; its
//! exceptions are Python classes (`purcell/_errors.py`) raised from here ([`error`]).

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use purcell_sim::words::{Front, Worded};
use purcell_solver::problem::{Cost, Problem, Spec};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

mod detach;
mod field;
mod keywords;
mod replay;
mod solution;
mod solve;
mod sweep;

/// The exception `name` of `purcell` (python/purcell/_errors.py) with `message`, its
/// attributes the keyword arguments `attrs`.
pub(crate) fn error(name: &str, message: String, attrs: Option<&Bound<'_, PyDict>>) -> PyErr {
    Python::attach(|py| {
        let raised = py
            .import("purcell._errors")
            .and_then(|m| m.getattr(name))
            .and_then(|class| class.call((message,), attrs));
        match raised {
            Ok(e) => PyErr::from_value(e),
            Err(e) => e,
        }
    })
}

/// `purcell.InputError` with `message`.
pub(crate) fn input_error(message: impl ToString) -> PyErr {
    error("InputError", message.to_string(), None)
}

/// `purcell.InputError` with the library's refusal `e` in Python's words.
pub(crate) fn refused(e: impl Worded) -> PyErr {
    input_error(e.words(Front::Python))
}

/// The start budget `n` as a count: a negative one is refused with the library's message.
pub(crate) fn starts(n: i64) -> PyResult<usize> {
    usize::try_from(n).map_err(|_| refused(purcell_sim::spec::SpecError::Starts(n.into())))
}

/// `a`, read-only: what it holds is a result, not the user's to change (an assignment
/// raises instead of being lost).
fn frozen<T: pyo3::PyTypeCheck>(a: Bound<'_, T>) -> PyResult<Bound<'_, T>> {
    let flags = PyDict::new(a.py());
    flags.set_item("write", false)?;
    a.as_any().call_method("setflags", (), Some(&flags))?;
    Ok(a)
}

/// Rows of `n` numbers as an `(rows.len(), n)` array, read-only.
pub(crate) fn array2<'py, const N: usize>(
    py: Python<'py>,
    rows: impl ExactSizeIterator<Item = [f64; N]>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let len = rows.len();
    let flat: Vec<f64> = rows.flatten().collect();
    match Array2::from_shape_vec((len, N), flat) {
        Ok(a) => frozen(a.into_pyarray(py)),
        Err(_) => unreachable!("every row has N numbers"),
    }
}

/// A vector as a 1-D array, read-only.
pub(crate) fn array1<'py>(py: Python<'py>, v: &[f64]) -> PyResult<Bound<'py, PyArray1<f64>>> {
    frozen(PyArray1::from_slice(py, v))
}

/// An array of any shape, read-only.
pub(crate) fn array<'py, D: numpy::ndarray::Dimension>(
    py: Python<'py>,
    a: numpy::ndarray::Array<f64, D>,
) -> PyResult<Bound<'py, numpy::PyArray<f64, D>>> {
    frozen(a.into_pyarray(py))
}

/// `name(key=value, ...)` with each value's Python `repr`, as a dataclass shows itself.
pub(crate) fn repr<'py>(
    name: &str,
    fields: impl IntoIterator<Item = (&'static str, PyResult<Bound<'py, PyAny>>)>,
) -> PyResult<String> {
    let mut parts = Vec::new();
    for (key, value) in fields {
        parts.push(format!("{key}={}", value?.repr()?));
    }
    Ok(format!("{name}({})", parts.join(", ")))
}

/// `v` as a Python object, for [`repr`].
pub(crate) fn py_any<'py, T: IntoPyObject<'py>>(
    py: Python<'py>,
    v: T,
) -> PyResult<Bound<'py, PyAny>> {
    pyo3::IntoPyObjectExt::into_bound_py_any(v, py)
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
    da: Py<numpy::PyArray3<f64>>,
}

#[pymethods]
impl Connection {
    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        repr(
            "Connection",
            [("A", Ok(self.a.bind(py).clone().into_any()))],
        )
    }
}

/// The local connection at `alpha` (purcell.connection documents it).
#[pyfunction]
fn connection(
    py: Python<'_>,
    alpha: [f64; 2],
    links: [f64; 3],
    drag: f64,
    ratio: f64,
) -> PyResult<Connection> {
    let spec = Spec {
        links,
        drag,
        ratio,
        alpha0: alpha,
        ..Spec::default()
    };
    // The shape is the problem's alpha0 here.
    let problem =
        Problem::new(&spec).map_err(|e| input_error(e.to_string().replace("alpha0", "alpha")))?;
    let c = problem
        .swimmer
        .connection_with_derivatives(&nalgebra::Vector2::new(alpha[0], alpha[1]))
        .map_err(input_error)?;
    let da = numpy::ndarray::Array3::from_shape_fn((2, 3, 2), |(i, r, j)| c.da[i][(r, j)]);
    Ok(Connection {
        a: array2(py, (0..3).map(|r| [c.a[(r, 0)], c.a[(r, 1)]]))?.unbind(),
        da: array(py, da)?.unbind(),
    })
}

/// The native module.
#[pymodule]
fn _purcell(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // The costs' names, `cost=`'s values (the core's one table, `purcell_core::for_each_cost!`).
    m.add("COSTS", PyTuple::new(m.py(), Cost::ALL.map(Cost::name))?)?;
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
