//! What a solve writes, for every front end: its costate file, binary gait and
//! `report.json`, built once ([`Solved`]), the files of its output directory
//! ([`Solved::files`]), and the warnings of its search ([`search_warnings`]), which each
//! front end words itself.

use crate::costate_file::CostateFile;
use crate::plots::{self, PlotError};
use crate::{output, replay};
use purcell_core::{Arc, Gait};
use purcell_solver::problem::Problem;
use purcell_solver::solver::{Evidence, Extremal, Minimum, Solution, Unrefined};
use serde_json::json;

/// Why a solve's outputs could not be built.
#[derive(Debug, thiserror::Error)]
pub enum SolvedError {
    /// The costate file does not make a gait file.
    #[error("the solution's gait: {0}")]
    Gait(purcell_core::Error),
    /// The report does not serialise.
    #[error(transparent)]
    Json(#[from] serde_json::Error),
    /// A figure failed.
    #[error("plotting: {0}")]
    Plot(#[from] PlotError),
}

/// A solve's stored outputs: its costate file, binary gait file and report.
#[derive(Clone, Debug)]
pub struct Solved {
    /// The costate file.
    pub file: CostateFile,
    /// The binary gait file of `file`.
    pub gait: Vec<u8>,
    /// `report.json` ([`report_json`]).
    pub report: serde_json::Value,
    /// `report.json` as written.
    pub report_text: String,
}

impl Solved {
    /// The outputs of `solution` to `problem`, costate checkpoints every `every` steps,
    /// found in `seconds`.
    pub fn new(
        problem: &Problem,
        solution: &Solution,
        every: u32,
        seconds: f64,
    ) -> Result<Self, SolvedError> {
        let best = &solution.extremals[solution.best];
        let file = output::costate_file(problem, best, every);
        let gait = file.to_gait().map_err(SolvedError::Gait)?;
        let parsed = Gait::from_bytes(&gait).map_err(SolvedError::Gait)?;
        let report = report_json(problem, solution, &file, &parsed, seconds);
        let report_text = serde_json::to_string_pretty(&report)? + "\n";
        Ok(Solved {
            file,
            gait,
            report,
            report_text,
        })
    }

    /// The files of the output directory of `best`, the returned extremal of `problem`:
    /// `trajectory.csv`, `costate.json`, `report.json` and, with `figures`, the figures.
    pub fn files(
        &self,
        problem: &Problem,
        best: &Extremal,
        figures: Option<&plots::Options>,
    ) -> Result<Vec<(String, Vec<u8>)>, SolvedError> {
        let mut files = vec![
            (
                "trajectory.csv".to_string(),
                output::trajectory_csv(problem, best).into_bytes(),
            ),
            ("costate.json".to_string(), self.file.to_json().into_bytes()),
            (
                "report.json".to_string(),
                self.report_text.clone().into_bytes(),
            ),
        ];
        if let Some(options) = figures {
            let (t, file) = (&best.trajectory, &self.file);
            files.extend(plots::figures(
                problem, t, &best.arcs, &best.mu, file, options,
            )?);
        }
        Ok(files)
    }
}

/// A warning of a search, for its front end to word.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SearchWarning<'a> {
    /// The search used its budget of starts before its stopping rule was met; `unseen`: the
    /// estimated chance that another start finds an unseen minimum no dearer than the gait.
    BudgetSpent {
        /// The budget.
        budget: usize,
        /// The estimate.
        unseen: f64,
    },
    /// `count` minima left unrefined are cheaper than the gait returned, `cheapest` first.
    Unrefined {
        /// The cheapest of them.
        cheapest: &'a Unrefined,
        /// How many.
        count: usize,
    },
}

/// The warnings of `solution`'s search: a search that gave up early, minima left unrefined
/// that may be cheaper (one warning, for the cheapest).
pub fn search_warnings(solution: &Solution) -> Vec<SearchWarning<'_>> {
    let mut warnings = Vec::new();
    if let Some(e) = solution.search.as_ref().filter(|e| !e.satisfied) {
        warnings.push(SearchWarning::BudgetSpent {
            budget: e.budget,
            unseen: e.unseen,
        });
    }
    // Cheapest first, as the search's minima.
    let unrefined = solution.search.iter().flat_map(|e| &e.unrefined);
    let cheaper: Vec<_> = unrefined.filter(|u| u.cheaper).collect();
    if let Some(&cheapest) = cheaper.first() {
        let count = cheaper.len();
        warnings.push(SearchWarning::Unrefined { cheapest, count });
    }
    warnings
}

/// `report.json`'s `format` tag (schema: `docs/schemas/solve-report.schema.json`).
pub const REPORT_FORMAT: &str = "purcell-solve-report";
/// `report.json`'s version: 1 is the first tagged one.
pub const REPORT_VERSION: u64 = 1;

/// `report.json`: the returned extremal of `solution` (whose costate `file` and `gait` are
/// written), found in `seconds`, then every extremal, the search's evidence and the
/// standard replays of the gait.
pub fn report_json(
    problem: &Problem,
    solution: &Solution,
    file: &CostateFile,
    gait: &Gait<'_>,
    seconds: f64,
) -> serde_json::Value {
    let best = &solution.extremals[solution.best];
    let extremals: Vec<_> = solution.extremals.iter().map(extremal_json).collect();
    json!({
        "format": REPORT_FORMAT, "version": REPORT_VERSION,
        "cost": best.cost,
        "residual": best.residual,
        "terminal_residual": best.terminal_residual,
        "kkt_residual": best.kkt_residual,
        "arcs": arcs_json(&best.arcs),
        "min_eta": best.min_eta,
        "law_residual": best.law_residual,
        "local_min": best.local_min,
        "max_abs_alpha": best.max_abs_alpha,
        "admissible": best.admissible,
        "returned": solution.best,
        "solve_seconds": seconds,
        "search": solution.search.as_ref().map(evidence_json),
        "mu": file.mu, "xi0": file.xi0,
        "problem": {"target": file.target, "horizon": problem.horizon(), "step": problem.h,
                    "steps": problem.steps, "alpha0": file.alpha0,
                    "alpha_end": file.end_shape(), "links": file.model.links,
                    "drag": file.model.drag, "ratio": file.model.ratio,
                    "alpha_max": problem.alpha_max},
        "extremals": extremals,
        // Terminal errors of the stored costate replayed through the core, as the firmware
        // flies it (f32 with checkpoints) beside f64.
        "replays": replay::standard_replays(gait),
    })
}

/// One extremal in `report.json`.
fn extremal_json(x: &Extremal) -> serde_json::Value {
    json!({
        "cost": x.cost, "max_abs_alpha": x.max_abs_alpha, "admissible": x.admissible,
        "local_min": x.local_min, "residual": x.residual,
        "terminal_residual": x.terminal_residual, "kkt_residual": x.kkt_residual,
        "arcs": arcs_json(&x.arcs), "min_eta": x.min_eta,
        "stationarity": x.stationarity, "law_residual": x.law_residual,
        "newton_iterations": x.iterations, "start": x.start, "hits": x.hits, "twin_of": x.twin_of,
        "mu": [x.mu.x, x.mu.y, x.mu.z], "xi0": [x.xi0.x, x.xi0.y],
    })
}

/// The global search's evidence in `report.json` (an infinite estimate as `null`).
fn evidence_json(e: &Evidence) -> serde_json::Value {
    let finite = |x: f64| x.is_finite().then_some(x);
    json!({
        "starts": e.starts, "budget": e.budget, "rule_met": e.satisfied,
        "unseen_estimate": e.unseen, "expected_minima": finite(e.expected_minima),
        "distinct_minima": e.minima.len(),
        "minima": e.minima.iter().map(minimum_json).collect::<Vec<_>>(),
        "unrefined": e.unrefined.iter().map(|u| {
            let mut m = minimum_json(&u.minimum);
            m["defect"] = json!(finite(u.defect));
            m["cheaper"] = json!(u.cheaper);
            m
        }).collect::<Vec<_>>(),
    })
}

/// A minimum of the coarse search in `report.json`.
fn minimum_json(m: &Minimum) -> serde_json::Value {
    json!({"cost": m.cost, "max_abs_alpha": m.max_abs_alpha, "hits": m.hits})
}

/// Joint-limit arcs in `report.json`, as the costate file stores them (`purcell_core::Arc`:
/// joint 1 or 2, as `α_1`, `α_2`, the limit's sign ±1, the first and last state on it).
fn arcs_json(arcs: &[Arc]) -> serde_json::Value {
    arcs.iter().map(|a| json!(a)).collect()
}
