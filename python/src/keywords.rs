//! The problem's keyword arguments, one place for `purcell.solve`, `purcell.sweep` and
//! `purcell.distributed` (python/purcell/_keywords.py checks their types and counts and
//! builds the dict): a new keyword is a field here and its line in [`ProblemKw::solve_spec`].

use crate::{input_error, refused, starts};
use purcell_sim::spec::SolveSpec;
use purcell_solver::problem::{Cost, Spec};
use pyo3::prelude::*;

/// The problem's keyword arguments (a dict with all of them).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct ProblemKw {
    horizon: f64,
    step: f64,
    alpha0: [f64; 2],
    alpha_end: Option<[f64; 2]>,
    links: [f64; 3],
    drag: f64,
    ratio: f64,
    alpha_max: Option<f64>,
    /// The running cost's name (`_keywords.py` checked it is one of [`Cost::ALL`]'s).
    cost: String,
    starts: Option<i64>,
    /// A solve's only (a sweep orders its starts by the default seed).
    #[pyo3(default)]
    seed: u64,
    /// A solve's only.
    #[pyo3(default)]
    checkpoint_every: Option<u32>,
}

impl ProblemKw {
    /// The solve of `target` these keywords ask for (not yet checked: `spec::prepare`).
    pub(crate) fn solve_spec(&self, target: [f64; 3]) -> PyResult<SolveSpec> {
        Ok(SolveSpec {
            problem: Spec {
                target,
                horizon: self.horizon,
                step: self.step,
                alpha0: self.alpha0,
                alpha_end: self.alpha_end,
                links: self.links,
                drag: self.drag,
                ratio: self.ratio,
                alpha_max: self.alpha_max,
                cost: self.cost()?,
            },
            starts: self.starts.map(starts).transpose()?,
            seed: self.seed,
            checkpoint_every: self.checkpoint_every,
        })
    }

    /// The running cost named `cost`.
    fn cost(&self) -> PyResult<Cost> {
        Cost::named(&self.cost).ok_or_else(|| input_error(format!("unknown cost {:?}", self.cost)))
    }

    /// A sweep's problem (target 0) and its search options, checked.
    pub(crate) fn sweep(&self) -> PyResult<(Spec, purcell_solver::solver::SolveOptions)> {
        let s = self.solve_spec([0.0; 3])?;
        let options = purcell_sim::spec::sweep_options(&s.problem, s.starts).map_err(refused)?;
        Ok((s.problem, options))
    }
}
