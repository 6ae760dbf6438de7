//! `Extremal` and `Solution`: what `purcell.solve` returns, the arrays built from the
//! solver's trajectory at their first access, read-only, and kept.

use crate::{array1, array2, py_any, refused, repr};
use numpy::{PyArray1, PyArray2};
use purcell_sim::costate_file::CostateFile;
use purcell_sim::output;
use purcell_sim::report::Solved;
use purcell_sim::words::{Front, Worded};
use purcell_solver::problem::Problem;
use purcell_solver::solver;
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyBytes, PyDict};

/// One extremal of the problem on its own grid, with its certificates (MODEL.md §4–§5).
///
/// Arrays are numpy float64, read-only, built at their first access. Units: seconds,
/// radians, metres; controls in rad/s; costates as MODEL.md §5.
#[pyclass(frozen, subclass, module = "purcell")]
pub struct Extremal {
    /// The solver's extremal.
    x: solver::Extremal,
    /// Time step `h`, seconds.
    h: f64,
    /// Its arrays, once built.
    arrays: Arrays,
}

/// An [`Extremal`]'s arrays, each built at its first access.
struct Arrays {
    mu: PyOnceLock<Py<PyArray1<f64>>>,
    xi0: PyOnceLock<Py<PyArray1<f64>>>,
    t: PyOnceLock<Py<PyArray1<f64>>>,
    alpha: PyOnceLock<Py<PyArray2<f64>>>,
    u: PyOnceLock<Py<PyArray2<f64>>>,
    g: PyOnceLock<Py<PyArray2<f64>>>,
    xi: PyOnceLock<Py<PyArray2<f64>>>,
}

/// The array in `cell`, made by `make` at the first call.
fn cached<'py, T>(
    py: Python<'py>,
    cell: &PyOnceLock<Py<T>>,
    make: impl FnOnce() -> PyResult<Bound<'py, T>>,
) -> PyResult<Bound<'py, T>> {
    let made = cell.get_or_try_init(py, || make().map(Bound::unbind))?;
    Ok(made.bind(py).clone())
}

impl Extremal {
    /// The extremal `x` of a problem with step `h`.
    pub(crate) fn new(x: solver::Extremal, h: f64) -> Self {
        let arrays = Arrays {
            mu: PyOnceLock::new(),
            xi0: PyOnceLock::new(),
            t: PyOnceLock::new(),
            alpha: PyOnceLock::new(),
            u: PyOnceLock::new(),
            g: PyOnceLock::new(),
            xi: PyOnceLock::new(),
        };
        Extremal { x, h, arrays }
    }
}

#[pymethods]
impl Extremal {
    /// J = sum_k h/2 |u_k|^2, rad^2/s.
    #[getter]
    fn cost(&self) -> f64 {
        self.x.cost
    }
    /// The spatial momentum mu, shape (3,).
    #[getter]
    fn mu<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        cached(py, &self.arrays.mu, || array1(py, self.x.mu.as_slice()))
    }
    /// The initial shape costate xi^{-1}, shape (2,).
    #[getter]
    fn xi0<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        cached(py, &self.arrays.xi0, || array1(py, self.x.xi0.as_slice()))
    }
    /// Times t_k = k h, k = 0..N, seconds, shape (N+1,): the float nearest the decimal k h,
    /// as trajectory.csv prints it (9.9, not 9.900000000000002).
    #[getter]
    fn t<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let n = self.x.trajectory.states.len();
        cached(py, &self.arrays.t, || {
            let t: Vec<f64> = (0..n)
                .map(|k| purcell_sim::decimal::time_value(k as u64, self.h))
                .collect();
            array1(py, &t)
        })
    }
    /// Shapes alpha_k = (alpha1, alpha2), radians, shape (N+1, 2).
    #[getter]
    fn alpha<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let s = &self.x.trajectory.states;
        cached(py, &self.arrays.alpha, || {
            array2(py, s.iter().map(|s| [s.alpha.x, s.alpha.y]))
        })
    }
    /// Controls u_k = shape velocities, rad/s, shape (N, 2).
    #[getter]
    fn u<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let c = &self.x.trajectory.controls;
        cached(py, &self.arrays.u, || {
            array2(py, c.iter().map(|u| [u.x, u.y]))
        })
    }
    /// Positions g_k = (x, y, theta), metres and radians, shape (N+1, 3).
    #[getter]
    fn g<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let s = &self.x.trajectory.states;
        cached(py, &self.arrays.g, || {
            array2(py, s.iter().map(|s| s.g.to_xytheta().into()))
        })
    }
    /// The costate path xi^{k-1}, k = 0..N (the first is xi0), shape (N+1, 2).
    #[getter]
    fn xi<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let s = &self.x.trajectory.xis;
        cached(py, &self.arrays.xi, || {
            array2(py, s.iter().map(|x| [x.x, x.y]))
        })
    }
    /// Joint-limit arcs: dicts {joint (1 or 2), sign (+1/-1), first, last} (states on the limit).
    #[getter]
    fn arcs<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.x
            .arcs
            .iter()
            .map(|a| {
                let d = PyDict::new(py);
                d.set_item("joint", a.joint)?;
                d.set_item("sign", a.sign)?;
                d.set_item("first", a.first)?;
                d.set_item("last", a.last)?;
                Ok(d)
            })
            .collect()
    }
    /// Largest |alpha_i| along the path, radians.
    #[getter]
    fn max_abs_alpha(&self) -> f64 {
        self.x.max_abs_alpha
    }
    /// Whether the path is admissible (within the joint limit, or short of the overlap at pi).
    #[getter]
    fn admissible(&self) -> bool {
        self.x.admissible
    }
    /// Second-order check: a strict local minimum.
    #[getter]
    fn local_min(&self) -> bool {
        self.x.local_min
    }
    /// Terminal defect of the solver's trajectory, m / rad.
    #[getter]
    fn residual(&self) -> f64 {
        self.x.residual
    }
    /// Terminal defect after re-integrating the controls through the core, m / rad (None if
    /// not admissible).
    #[getter]
    fn terminal_residual(&self) -> Option<f64> {
        self.x.terminal_residual
    }
    /// Independent KKT residual by reverse mode through the core, rad/s (None if not admissible).
    #[getter]
    fn kkt_residual(&self) -> Option<f64> {
        self.x.kkt_residual
    }
    /// Relative deviation of the core's law from the controls (None if not admissible).
    #[getter]
    fn law_residual(&self) -> Option<f64> {
        self.x.law_residual
    }
    /// Smallest joint-limit multiplier over the arcs (None without arcs).
    #[getter]
    fn min_eta(&self) -> Option<f64> {
        self.x.min_eta
    }
    /// The solver's own stationarity residual, rad/s.
    #[getter]
    fn stationarity(&self) -> f64 {
        self.x.stationarity
    }
    /// Why the certificates do not vouch for it (None if they do).
    #[getter]
    fn uncertified(&self) -> Option<&'static str> {
        self.x.uncertified()
    }
    /// Newton iterations on the fine grid.
    #[getter]
    fn newton_iterations(&self) -> usize {
        self.x.iterations
    }
    /// Index of the start loop that first reached it.
    #[getter]
    fn start(&self) -> usize {
        self.x.start
    }
    /// How many starts reached it.
    #[getter]
    fn hits(&self) -> usize {
        self.x.hits
    }
    /// Index in `Solution.extremals` of its mirror-image twin, if found.
    #[getter]
    fn twin_of(&self) -> Option<usize> {
        self.x.twin_of
    }
    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let x = &self.x;
        repr(
            "Extremal",
            [
                ("cost", py_any(py, x.cost)),
                ("max_abs_alpha", py_any(py, x.max_abs_alpha)),
                ("admissible", py_any(py, x.admissible)),
                ("local_min", py_any(py, x.local_min)),
            ],
        )
    }
}

/// The solution of `purcell.solve`: the returned extremal (its attributes are this object's),
/// every extremal found, the report and the gait file.
#[pyclass(frozen, extends = Extremal, module = "purcell")]
pub struct Solution {
    /// Index of the returned extremal in `extremals`.
    #[pyo3(get)]
    best: usize,
    /// Every extremal carried to the problem's grid, cheapest first.
    #[pyo3(get)]
    extremals: Vec<Py<Extremal>>,
    /// `report.json` as a dict.
    #[pyo3(get)]
    report: Py<PyAny>,
    /// For a gait flown `m` times (under a tight joint limit where the search led to no gait:
    /// the loop to the target's `m`-th root, flown `m` times and refined), `m`; else `None`.
    #[pyo3(get)]
    flown: Option<usize>,
    /// Whether the gait (under a joint limit) was reached by walking one of the refinement's
    /// admissible gaits back up the central path and down again, and refining where that ended.
    #[pyo3(get)]
    recentred: bool,
    /// Its costate file, gait file and report, as the command line writes them.
    solved: Solved,
    /// The problem it solves.
    problem: Problem,
}

impl Solution {
    /// The binary gait file.
    pub(crate) fn gait_bytes(&self) -> &[u8] {
        &self.solved.gait
    }
    /// The costate file.
    pub(crate) fn file(&self) -> &CostateFile {
        &self.solved.file
    }
}

#[pymethods]
impl Solution {
    /// The binary gait file (`purcell-sim export`'s bytes), for firmware or `purcell.replay`.
    fn gait<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        PyBytes::new(py, &self.solved.gait)
    }
    /// The costate file, JSON text (`costate.json`), for `purcell-sim replay --costate`.
    fn costate(&self) -> String {
        self.solved.file.to_json()
    }
    /// Writes ``purcell-sim solve --out``'s files to the directory `out`.
    ///
    /// trajectory.csv, costate.json, report.json and the figures (SVG and PNG), with the
    /// command line's safety rules: `out` must be missing, empty or a previous result of
    /// `solve`; the files are written next to it and put in its place in one step.
    ///
    /// Parameters
    /// ----------
    /// out : str or os.PathLike
    ///     The directory.
    /// force : bool, default False
    ///     Replace whatever `out` holds.
    /// plots : bool, default True
    ///     Write the figures.
    /// degrees : bool, default False
    ///     The figures' shape axes in degrees.
    ///
    /// Raises
    /// ------
    /// InputError
    ///     `out` refused (it holds something else, and `force` is not set).
    /// OSError
    ///     Writing failed.
    #[pyo3(signature = (out, *, force = false, plots = true, degrees = false))]
    fn save(
        slf: PyRef<'_, Self>,
        py: Python<'_>,
        out: std::path::PathBuf,
        force: bool,
        plots: bool,
        degrees: bool,
    ) -> PyResult<()> {
        let x = &slf.as_super().x;
        let dir = output::OutputDir::prepare(output::Claim::new(&out, "solve", force, &[]))
            .map_err(refused)?;
        let (problem, solved) = (&slf.problem, &slf.solved);
        py.detach(|| {
            let options = purcell_sim::plots::Options { degrees };
            let files = solved
                .files(problem, x, plots.then_some(&options))
                .map_err(|e| e.to_string())?;
            dir.commit(&files).map_err(|e| e.words(Front::Python))
        })
        .map_err(PyOSError::new_err)
    }
    fn __repr__(slf: PyRef<'_, Self>, py: Python<'_>) -> PyResult<String> {
        let x = &slf.as_super().x;
        repr(
            "Solution",
            [
                ("cost", py_any(py, x.cost)),
                ("mu", py_any(py, x.mu.as_slice())),
                ("xi0", py_any(py, x.xi0.as_slice())),
                ("admissible", py_any(py, x.admissible)),
                ("extremals", py_any(py, slf.extremals.len())),
            ],
        )
    }
}

/// The Python `Solution` of `solution` to `problem`, with costate checkpoints every `every`
/// steps, found in `seconds`: the same costate file, gait and report as `purcell-sim solve`.
pub(crate) fn build(
    py: Python<'_>,
    problem: &Problem,
    solution: &solver::Solution,
    every: u32,
    seconds: f64,
) -> PyResult<Py<Solution>> {
    let best = &solution.extremals[solution.best];
    let solved = Solved::new(problem, solution, every, seconds)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    let report = py
        .import("json")?
        .call_method1("loads", (solved.report_text.as_str(),))?;
    let extremals = solution
        .extremals
        .iter()
        .map(|x| Py::new(py, Extremal::new(x.clone(), problem.h)))
        .collect::<PyResult<_>>()?;
    let init =
        PyClassInitializer::from(Extremal::new(best.clone(), problem.h)).add_subclass(Solution {
            best: solution.best,
            extremals,
            report: report.unbind(),
            flown: solution.flown,
            recentred: solution.recentred,
            solved,
            problem: *problem,
        });
    Py::new(py, init)
}
