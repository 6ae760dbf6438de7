//! `purcell.field`: the curvature of the connection over the shape plane (MODEL.md §8), as
//! `purcell-sim field` samples it for its figures and field.csv.

use crate::{array, array1, input_error};
use numpy::ndarray::Array3;
use numpy::{PyArray1, PyArray3, PyReadonlyArray2};
use purcell_solver::curvature::Field as Sampled;
use purcell_solver::problem::{Problem, Spec};
use pyo3::prelude::*;

/// Largest number of cells per axis `purcell.field` samples.
const MAX_CELLS: usize = 4096;

/// The curvature F of the connection on a grid of cells covering ]-pi, pi[^2.
#[pyclass(frozen, module = "purcell")]
pub struct Field {
    field: Sampled,
    /// `centres`, read-only.
    centres: Py<PyArray1<f64>>,
    /// `F`, read-only.
    values: Py<PyArray3<f64>>,
}

#[pymethods]
impl Field {
    /// Cell centres along each axis (the same for alpha1 and alpha2), radians, increasing,
    /// shape (n,).
    #[getter]
    fn centres<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.centres.bind(py).clone()
    }
    /// Width of one cell, radians.
    #[getter]
    fn cell(&self) -> f64 {
        self.field.cell()
    }
    /// F at the cell centres, shape (3, n, n): rows x, y (m/rad^2) and theta (1/rad); index
    /// [row, j, i] at (alpha1, alpha2) = (centres[i], centres[j]) (alpha1 along the last axis,
    /// as an image: `imshow(F[2], origin="lower")`).
    #[getter]
    #[pyo3(name = "F")]
    fn values<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        self.values.bind(py).clone()
    }
    /// The integral of F over the area the closed polygon `path` (shapes, radians, shape
    /// (M, 2)) encloses, counted with its winding number: the leading-order estimate of the
    /// net motion (x m, y m, theta rad) of the gait `path` (MODEL.md §8).
    fn integral_over<'py>(
        &self,
        py: Python<'py>,
        path: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let path = path.as_array();
        if path.ncols() != 2 || path.nrows() == 0 {
            return Err(input_error(format!(
                "path takes M >= 1 shapes (alpha1, alpha2): shape (M, 2) (got {:?})",
                path.shape()
            )));
        }
        let path: Vec<nalgebra::Vector2<f64>> = path
            .rows()
            .into_iter()
            .map(|r| nalgebra::Vector2::new(r[0], r[1]))
            .collect();
        array1(py, self.field.integral_over(&path).as_slice())
    }
    fn __repr__(&self) -> String {
        format!("Field(cells={})", self.field.centres.len())
    }
}

/// `purcell.field` (python/purcell/_model.py documents it): the curvature sampled on
/// `cells` x `cells` cells, as `purcell-sim field`'s field.csv.
#[pyfunction]
pub fn field(
    py: Python<'_>,
    links: [f64; 3],
    drag: f64,
    ratio: f64,
    cells: i64,
) -> PyResult<Field> {
    let cells = usize::try_from(cells)
        .ok()
        .filter(|c| (1..=MAX_CELLS).contains(c))
        .ok_or_else(|| input_error(format!("cells must be 1 to {MAX_CELLS} (got {cells})")))?;
    let spec = Spec {
        links,
        drag,
        ratio,
        ..Spec::default()
    };
    let problem = Problem::new(&spec).map_err(input_error)?;
    let field = py
        .detach(|| Sampled::sample(&problem.swimmer, cells))
        .map_err(input_error)?;
    let n = field.centres.len();
    let values = Array3::from_shape_fn((3, n, n), |(r, j, i)| field.at(i, j)[r]);
    Ok(Field {
        centres: array1(py, &field.centres)?.unbind(),
        values: array(py, values)?.unbind(),
        field,
    })
}
