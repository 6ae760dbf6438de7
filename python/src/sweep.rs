//! `purcell.sweep` (`purcell-sim sweep`): a lattice of targets solved by continuation from
//! neighbours, as records; and the same sweep phase by phase for `purcell.distributed`
//! ([`SweepPlan`], [`sweep_search`], [`sweep_refine`]): the searches and refinements as
//! batches anywhere, the neighbour passes where the plan is.

use crate::{detach, input_error, numbers};
use purcell_sim::spec::{self, MAX_SWEEP_TARGETS};
use purcell_sim::units::Quantity::{self, Angle, Length};
use purcell_solver::problem::{Problem, Spec};
use purcell_solver::solver::continuation::{self, Atlas, Lattice, refine_target, search_target};
use purcell_solver::solver::search::Candidate;
use purcell_solver::solver::{Extremal, SolveError, SolveOptions};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyString};
use rayon::prelude::*;

/// The problem's keyword arguments of `purcell.sweep` (a dict with all of them).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct ProblemKw {
    horizon: f64,
    step: f64,
    alpha0: Vec<f64>,
    links: Vec<f64>,
    drag: f64,
    ratio: f64,
    alpha_max: Option<f64>,
    starts: i64,
}

impl ProblemKw {
    /// The problem (target 0) and search options, with the command line's checks.
    fn checked(&self) -> PyResult<(Spec, SolveOptions)> {
        let starts = crate::starts(self.starts)?;
        let spec = Spec {
            horizon: self.horizon,
            step: self.step,
            alpha0: numbers("alpha0", &self.alpha0)?,
            alpha_end: None,
            links: numbers("links", &self.links)?,
            drag: self.drag,
            ratio: self.ratio,
            alpha_max: self.alpha_max,
            target: [0.0; 3],
        };
        let options = spec::sweep_options(&spec, starts).map_err(input_error)?;
        Ok((spec, options))
    }
}

/// One axis of the lattice: `"FROM:TO:COUNT"` or a number as text (the command line's), a
/// number, or a sequence of numbers.
fn axis_of(name: &str, kind: Quantity, v: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
    if let Ok(text) = v.cast::<PyString>() {
        return spec::axis(name, text.to_str()?, kind).map_err(input_error);
    }
    let values = match v.extract::<f64>() {
        Ok(x) => vec![x],
        Err(_) => v.extract::<Vec<f64>>().map_err(|_| {
            input_error(format!(
                "{name} takes a number, a sequence of numbers or \"FROM:TO:COUNT\""
            ))
        })?,
    };
    if values.is_empty() || values.iter().any(|x| !x.is_finite()) {
        return Err(input_error(format!(
            "{name} takes 1 to {MAX_SWEEP_TARGETS} finite numbers (got {values:?})"
        )));
    }
    Ok(values)
}

/// The lattice of the three axes, with the command line's limit on its size.
fn lattice_of(
    xs: &Bound<'_, PyAny>,
    ys: &Bound<'_, PyAny>,
    thetas: &Bound<'_, PyAny>,
) -> PyResult<Lattice> {
    spec::lattice([
        axis_of("x", Length, xs)?,
        axis_of("y", Length, ys)?,
        axis_of("theta", Angle, thetas)?,
    ])
    .map_err(input_error)
}

/// One target's record: the columns of `sweep.csv` (numbers None where it has none).
fn record<'py>(
    py: Python<'py>,
    target: [f64; 3],
    result: &Result<Extremal, SolveError>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("x", target[0])?;
    d.set_item("y", target[1])?;
    d.set_item("theta", target[2])?;
    let x = result.as_ref().ok();
    d.set_item("cost", x.map(|x| x.cost))?;
    d.set_item("residual", x.map(|x| x.residual))?;
    d.set_item("max_abs_alpha", x.map(|x| x.max_abs_alpha))?;
    d.set_item("admissible", x.map(|x| x.admissible))?;
    d.set_item("local_min", x.map(|x| x.local_min))?;
    d.set_item("kkt_residual", x.and_then(|x| x.kkt_residual))?;
    let status = match result {
        Ok(x) => x.uncertified().unwrap_or("ok").to_string(),
        Err(e) => e.to_string(),
    };
    d.set_item("status", status)?;
    Ok(d)
}

/// The local sweep (`purcell.sweep`, which documents it): one record per target, `x` slowest,
/// `theta` fastest.
#[pyfunction]
#[pyo3(signature = (xs, ys, thetas, problem, progress = None))]
pub fn sweep<'py>(
    py: Python<'py>,
    xs: &Bound<'py, PyAny>,
    ys: &Bound<'py, PyAny>,
    thetas: &Bound<'py, PyAny>,
    problem: ProblemKw,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let lattice = lattice_of(xs, ys, thetas)?;
    let (spec, options) = problem.checked()?;
    // Each target ticks once when searched and once when refined, as the command line's bar.
    let points = detach::run(py, progress.as_ref(), |progress| {
        continuation::sweep(&spec, &lattice, &options, progress)
    })?
    .map_err(input_error)?;
    points
        .iter()
        .map(|p| record(py, p.target.into(), &p.result))
        .collect()
}

/// Coarse extremals as bytes (little-endian f64: per extremal its cost, largest |alpha|,
/// start, hits, nu (5), N and the N controls), for a trip between processes. The start
/// loop is not carried (the refinement does not use it).
fn encode(list: &[Candidate]) -> Vec<u8> {
    let mut v: Vec<f64> = Vec::new();
    for c in list {
        v.extend([c.cost, c.max_abs_alpha, c.start as f64, c.hits as f64]);
        v.extend(c.nu.iter());
        v.push(c.u.len() as f64);
        v.extend(c.u.iter().flat_map(|u| [u.x, u.y]));
    }
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// The coarse extremals of [`encode`]'s bytes.
fn decode(bytes: &[u8]) -> PyResult<Vec<Candidate>> {
    let bad = || input_error("not a list of coarse extremals of purcell.distributed");
    if !bytes.len().is_multiple_of(8) {
        return Err(bad());
    }
    let v: Vec<f64> = bytes
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap_or_default()))
        .collect();
    let mut out = Vec::new();
    let mut rest = v.as_slice();
    while !rest.is_empty() {
        let (head, tail) = rest.split_at_checked(10).ok_or_else(bad)?;
        let n = head[9] as usize;
        let (u, tail) = tail.split_at_checked(2 * n).ok_or_else(bad)?;
        out.push(Candidate {
            cost: head[0],
            max_abs_alpha: head[1],
            start: head[2] as usize,
            hits: head[3] as usize,
            nu: nalgebra::Vector5::from_column_slice(&head[4..9]),
            u: u.chunks_exact(2)
                .map(|p| nalgebra::Vector2::new(p[0], p[1]))
                .collect(),
            start_loop: None,
        });
        rest = tail;
    }
    Ok(out)
}

/// A target's own coarse extremals, those the neighbour passes brought (bytes of
/// [`encode`]) and its search's smallest defect.
type Cell<'py> = (Bound<'py, PyBytes>, Bound<'py, PyBytes>, f64);

/// A sweep's lattice and problem, its phases one by one (`purcell.distributed`): phase 1's
/// searches ([`sweep_search`]) and phase 3's refinements ([`sweep_refine`]) run anywhere;
/// the neighbour passes (phase 2, [`SweepPlan::passes`]) here.
#[pyclass(frozen, module = "purcell")]
pub struct SweepPlan {
    atlas: Atlas,
}

#[pymethods]
impl SweepPlan {
    #[new]
    fn new(
        xs: &Bound<'_, PyAny>,
        ys: &Bound<'_, PyAny>,
        thetas: &Bound<'_, PyAny>,
        problem: ProblemKw,
    ) -> PyResult<Self> {
        let lattice = lattice_of(xs, ys, thetas)?;
        let (spec, options) = problem.checked()?;
        let atlas = Atlas::new(&spec, lattice, &options).map_err(input_error)?;
        Ok(SweepPlan { atlas })
    }
    /// The targets (x m, y m, theta rad), x slowest, theta fastest.
    #[getter]
    fn targets(&self) -> Vec<(f64, f64, f64)> {
        let t = &self.atlas.targets;
        t.iter().map(|t| (t.x, t.y, t.z)).collect()
    }
    /// Indices of the targets whose global search runs (one per orbit of the symmetries).
    fn searched(&self) -> Vec<usize> {
        self.atlas.searched()
    }
    /// Phase 2 from the searches' outcomes [(index, extremals, defect)] of `searched()`:
    /// every target's (own extremals, extremals the neighbour passes brought, defect).
    fn passes<'py>(
        &self,
        py: Python<'py>,
        searched: Vec<(usize, Bound<'py, PyBytes>, f64)>,
    ) -> PyResult<Vec<Cell<'py>>> {
        let n = self.atlas.targets.len();
        let searched = searched
            .into_iter()
            .map(|(i, b, r)| match i < n {
                true => Ok((i, decode(b.as_bytes())?, r)),
                false => Err(input_error(format!("target {i} is not in the plan"))),
            })
            .collect::<PyResult<Vec<_>>>()?;
        let (own, residual, brought) = py.detach(|| {
            let (own, residual) = self.atlas.spread(searched, &|| {});
            let brought = self.atlas.neighbour_passes(&own, &|| ());
            (own, residual, brought)
        });
        (0..n)
            .map(|i| {
                let (a, b) = (encode(&own[i]), encode(&brought[i]));
                Ok((PyBytes::new(py, &a), PyBytes::new(py, &b), residual[i]))
            })
            .collect()
    }
}

/// Phase 1 for a batch of targets [(x, y, theta)]: each one's coarse extremals (bytes) and
/// smallest defect, in the targets' order. The GIL is released.
#[pyfunction]
pub fn sweep_search<'py>(
    py: Python<'py>,
    targets: Vec<[f64; 3]>,
    problem: ProblemKw,
) -> PyResult<Vec<(Bound<'py, PyBytes>, f64)>> {
    let (spec, options) = problem.checked()?;
    let problems = problems(&spec, &targets)?;
    let found: Vec<(Vec<u8>, f64)> = py.detach(|| {
        problems
            .par_iter()
            .map(|p| {
                let (list, residual) = search_target(p, &options, &|| ());
                (encode(&list), residual)
            })
            .collect()
    });
    Ok(found
        .into_iter()
        .map(|(b, r)| (PyBytes::new(py, &b), r))
        .collect())
}

/// Phase 3 for a batch of cells [((x, y, theta), (own, brought, defect))] of
/// `SweepPlan.passes`: each target's record. The GIL is released.
#[pyfunction]
pub fn sweep_refine<'py>(
    py: Python<'py>,
    cells: Vec<([f64; 3], Cell<'py>)>,
    problem: ProblemKw,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let (spec, options) = problem.checked()?;
    let targets: Vec<[f64; 3]> = cells.iter().map(|c| c.0).collect();
    let problems = problems(&spec, &targets)?;
    let lists = cells
        .iter()
        .map(|(_, (own, brought, r))| {
            Ok((decode(own.as_bytes())?, decode(brought.as_bytes())?, *r))
        })
        .collect::<PyResult<Vec<_>>>()?;
    let results: Vec<Result<Extremal, SolveError>> = py.detach(|| {
        problems
            .par_iter()
            .zip(&lists)
            .map(|(p, (own, brought, r))| refine_target(p, own, brought, *r, &options, &|| ()))
            .collect()
    });
    targets
        .iter()
        .zip(&results)
        .map(|(t, r)| record(py, *t, r))
        .collect()
}

/// The problems of `spec` at `targets`, as a sweep builds them.
fn problems(spec: &Spec, targets: &[[f64; 3]]) -> PyResult<Vec<Problem>> {
    targets
        .iter()
        .map(|&target| {
            Problem::new(&Spec {
                target,
                ..spec.clone()
            })
            .map_err(input_error)
        })
        .collect()
}
