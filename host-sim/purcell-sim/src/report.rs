//! What a solve writes, for every front end: its costate file, binary gait and
//! `report.json`, built once ([`Solved`]), the files of its output directory
//! ([`Solved::files`]), and the warnings of its search ([`search_warnings`]), worded for
//! each front end.

use crate::costate_file::CostateFile;
use crate::plots::{self, PlotError};
use crate::words::{Front, Worded};
use crate::{output, replay};
use purcell_core::{Arc, Gait};
use purcell_solver::problem::{Cost, Problem, Spec};
use purcell_solver::solver::continuation::{Lattice, SweepPoint};
use purcell_solver::solver::{Evidence, Extremal, Minimum, Solution, Unrefined};
use serde::Serialize;

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
    /// `report.json`.
    pub report: SolveReport,
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
        let report = SolveReport::new(problem, solution, &parsed, seconds);
        let report_text = report.to_json()?;
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

/// A warning of a search, worded by each front end ([`Worded`]).
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

impl Worded for SearchWarning<'_> {
    fn words(&self, f: Front) -> String {
        match *self {
            SearchWarning::BudgetSpent { budget, unseen } => format!(
                "the search used its budget of {budget} starts before its stopping rule was met \
                 (estimated chance that another start finds an unseen minimum no dearer than the \
                 gait returned: {unseen:.3}); this is the cheapest gait found: raise {} to \
                 search on",
                f.arg("starts")
            ),
            SearchWarning::Unrefined { cheapest, count } => {
                let report = match f {
                    Front::Cli => "report.json's search.unrefined",
                    Front::Python => "report[\"search\"][\"unrefined\"]",
                };
                format!(
                    "{cheapest} ({count} such minima in {report}): raise {} (without {}, \
                     another {} also orders the starts differently)",
                    f.arg("starts"),
                    f.arg("alpha_max"),
                    f.arg("seed")
                )
            }
        }
    }
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

/// `report.json` of a solve (schema: `docs/schemas/solve-report.schema.json`): the returned
/// extremal, found in `solve_seconds`, then every extremal, the search's evidence and the
/// standard replays of the gait. Written through a JSON map ([`SolveReport::to_json`]), so
/// its keys, the returned extremal's among them, are in alphabetical order, the order the
/// file has always had.
#[derive(Clone, Debug, Serialize)]
pub struct SolveReport {
    /// The returned extremal.
    #[serde(flatten)]
    pub best: CertifiedReport,
    /// Every extremal, cheapest first.
    pub extremals: Vec<ExtremalReport>,
    /// `m` if the gait was refined from its `m`-th part's gait flown `m` times (the search's
    /// start loops reached no gait within the limit; [`purcell_solver::solver::periodic`]).
    pub flown: Option<usize>,
    /// [`REPORT_FORMAT`].
    pub format: &'static str,
    /// The problem.
    pub problem: ProblemReport,
    /// Terminal errors of the stored costate replayed through the core, as the firmware
    /// flies it (f32 with checkpoints) beside f64.
    pub replays: Vec<replay::ReplayReport>,
    /// Whether the gait was reached by walking the search's cheapest gait back up the central
    /// path and down again ([`purcell_solver::solver::recentre`]).
    pub recentred: bool,
    /// The index of `best` in `extremals`.
    pub returned: usize,
    /// The global search's evidence (`None` after a warm start, and for a gait flown `m`
    /// times).
    pub search: Option<EvidenceReport>,
    /// Seconds the solve took.
    pub solve_seconds: f64,
    /// [`REPORT_VERSION`].
    pub version: u64,
}

/// What `report.json` says of an extremal, returned or not: its cost and certificates.
#[derive(Clone, Debug, Serialize)]
pub struct CertifiedReport {
    /// Whether it is admissible.
    pub admissible: bool,
    /// Its joint-limit arcs.
    pub arcs: Vec<ArcReport>,
    /// Its cost `J`, rad²/s.
    pub cost: f64,
    /// Its cost under each cost the solver knows, by name.
    pub costs: Costs,
    /// Its KKT residual through the core (`None` if not admissible).
    pub kkt_residual: Option<f64>,
    /// Its law residual (`None` if not admissible).
    pub law_residual: Option<f64>,
    /// Whether it is a strict local minimum.
    pub local_min: bool,
    /// Its largest `|α_i|`, rad.
    pub max_abs_alpha: f64,
    /// Its smallest arc multiplier (`None` without arcs).
    pub min_eta: Option<f64>,
    /// `μ`, the position costate.
    pub mu: [f64; 3],
    /// Its terminal defect.
    pub residual: f64,
    /// Its terminal defect through the core (`None` if not admissible).
    pub terminal_residual: Option<f64>,
    /// `ξ⁰`, the initial shape costate.
    pub xi0: [f64; 2],
}

/// The problem in `report.json`: a sweep's ([`SweepProblemReport`]) with its steps and
/// target (which sort after it: the fields stay in alphabetical order).
#[derive(Clone, Debug, Serialize)]
pub struct ProblemReport {
    /// Every field a sweep's problem has.
    #[serde(flatten)]
    pub common: SweepProblemReport,
    /// `N`.
    pub steps: u32,
    /// `ḡ` (x m, y m, θ rad).
    pub target: [f64; 3],
}

/// A joint-limit arc in `report.json`, as the costate file stores it (`purcell_core::Arc`:
/// joint 1 or 2, the limit's sign ±1, the first and last state on it; fields in
/// alphabetical order).
#[derive(Clone, Debug, Serialize)]
pub struct ArcReport {
    /// The first state on the limit.
    pub first: u32,
    /// The joint, 1 or 2.
    pub joint: u8,
    /// The last state on the limit.
    pub last: u32,
    /// The limit's sign, ±1.
    pub sign: i8,
}

/// One extremal in `report.json`, with how the search found it (keys in alphabetical order
/// through [`SolveReport::to_json`]).
#[derive(Clone, Debug, Serialize)]
pub struct ExtremalReport {
    /// Its cost and certificates.
    #[serde(flatten)]
    pub certified: CertifiedReport,
    /// How many starts reached it.
    pub hits: usize,
    /// Newton iterations of its refinement.
    pub newton_iterations: usize,
    /// The start that found it.
    pub start: usize,
    /// Its stationarity residual.
    pub stationarity: f64,
    /// The extremal it is a twin of, if any.
    pub twin_of: Option<usize>,
}

/// The global search's evidence in `report.json` (an infinite estimate as `null`; fields
/// in alphabetical order).
#[derive(Clone, Debug, Serialize)]
pub struct EvidenceReport {
    /// Its budget of starts.
    pub budget: usize,
    /// The distinct minima found.
    pub distinct_minima: usize,
    /// The estimated number of minima.
    pub expected_minima: Option<f64>,
    /// The minima, cheapest first.
    pub minima: Vec<MinimumReport>,
    /// Whether the stopping rule was met.
    pub rule_met: bool,
    /// The starts run.
    pub starts: usize,
    /// The minima left unrefined.
    pub unrefined: Vec<UnrefinedReport>,
    /// The estimated chance that another start finds an unseen minimum no dearer.
    pub unseen_estimate: f64,
}

/// A minimum of the coarse search in `report.json`.
#[derive(Clone, Debug, Serialize)]
#[allow(missing_docs)]
pub struct MinimumReport {
    pub cost: f64,
    pub hits: usize,
    pub max_abs_alpha: f64,
}

/// A minimum left unrefined in `report.json`: the minimum, its defect where the refinement
/// stopped and whether it may be cheaper than the gait returned.
#[derive(Clone, Debug, Serialize)]
#[allow(missing_docs)]
pub struct UnrefinedReport {
    pub cheaper: bool,
    pub cost: f64,
    pub defect: Option<f64>,
    pub hits: usize,
    pub max_abs_alpha: f64,
}

/// An infinite estimate as `None` (`null`).
fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// An extremal's cost under each cost the solver knows, by name (`{"effort": …, "power": …}`).
pub type Costs = std::collections::BTreeMap<&'static str, f64>;

/// The costs of `x` ([`Costs`]).
fn costs(x: &Extremal) -> Costs {
    Cost::ALL
        .into_iter()
        .map(|c| c.name())
        .zip(x.costs)
        .collect()
}

impl SolveReport {
    /// The report of `solution` to `problem`, whose returned extremal's `gait` is written,
    /// found in `seconds`.
    pub fn new(problem: &Problem, solution: &Solution, gait: &Gait<'_>, seconds: f64) -> Self {
        SolveReport {
            best: CertifiedReport::new(&solution.extremals[solution.best]),
            extremals: solution.extremals.iter().map(ExtremalReport::new).collect(),
            flown: solution.flown,
            recentred: solution.recentred,
            format: REPORT_FORMAT,
            problem: ProblemReport {
                common: SweepProblemReport {
                    alpha0: [problem.alpha0.x, problem.alpha0.y],
                    alpha_end: [problem.alpha_end.x, problem.alpha_end.y],
                    alpha_max: problem.alpha_max,
                    cost: problem.cost.name(),
                    drag: problem.swimmer.drag(),
                    horizon: problem.horizon(),
                    links: problem.swimmer.lengths(),
                    ratio: problem.swimmer.ratio(),
                    step: problem.h,
                },
                steps: problem.steps,
                target: [problem.target.x, problem.target.y, problem.target.z],
            },
            replays: replay::standard_replays(gait),
            returned: solution.best,
            search: solution.search.as_ref().map(EvidenceReport::new),
            solve_seconds: seconds,
            version: REPORT_VERSION,
        }
    }

    /// `report.json`'s text: pretty JSON through a JSON map, whose keys are sorted.
    pub fn to_json(&self) -> Result<String, serde_json::Error> {
        Ok(serde_json::to_string_pretty(&serde_json::to_value(self)?)? + "\n")
    }
}

impl CertifiedReport {
    fn new(x: &Extremal) -> Self {
        CertifiedReport {
            admissible: x.admissible,
            arcs: arcs(&x.arcs),
            cost: x.cost,
            costs: costs(x),
            kkt_residual: x.kkt_residual,
            law_residual: x.law_residual,
            local_min: x.local_min,
            max_abs_alpha: x.max_abs_alpha,
            min_eta: x.min_eta,
            mu: [x.mu.x, x.mu.y, x.mu.z],
            residual: x.residual,
            terminal_residual: x.terminal_residual,
            xi0: [x.xi0.x, x.xi0.y],
        }
    }
}

impl ExtremalReport {
    fn new(x: &Extremal) -> Self {
        ExtremalReport {
            certified: CertifiedReport::new(x),
            hits: x.hits,
            newton_iterations: x.iterations,
            start: x.start,
            stationarity: x.stationarity,
            twin_of: x.twin_of,
        }
    }
}

impl EvidenceReport {
    fn new(e: &Evidence) -> Self {
        EvidenceReport {
            budget: e.budget,
            distinct_minima: e.minima.len(),
            expected_minima: finite(e.expected_minima),
            minima: e.minima.iter().map(MinimumReport::new).collect(),
            rule_met: e.satisfied,
            starts: e.starts,
            unrefined: e.unrefined.iter().map(UnrefinedReport::new).collect(),
            unseen_estimate: e.unseen,
        }
    }
}

impl MinimumReport {
    fn new(m: &Minimum) -> Self {
        MinimumReport {
            cost: m.cost,
            hits: m.hits,
            max_abs_alpha: m.max_abs_alpha,
        }
    }
}

impl UnrefinedReport {
    fn new(u: &Unrefined) -> Self {
        UnrefinedReport {
            cheaper: u.cheaper,
            cost: u.minimum.cost,
            defect: finite(u.defect),
            hits: u.minimum.hits,
            max_abs_alpha: u.minimum.max_abs_alpha,
        }
    }
}

/// Joint-limit arcs as the report holds them.
fn arcs(arcs: &[Arc]) -> Vec<ArcReport> {
    arcs.iter()
        .map(|a| ArcReport {
            first: a.first,
            joint: a.joint,
            last: a.last,
            sign: a.sign,
        })
        .collect()
}

/// The sweep's `report.json`'s `format` tag (schema: `docs/schemas/sweep-report.schema.json`).
pub const SWEEP_REPORT_FORMAT: &str = "purcell-sweep-report";
/// The sweep's `report.json`'s version: 1 is the first tagged one.
pub const SWEEP_REPORT_VERSION: u64 = 1;

/// `report.json` of a sweep: its lattice, problem, how many targets were solved and in what
/// time (fields in alphabetical order, the order the file has always had).
#[derive(Clone, Debug, Serialize)]
pub struct SweepReport {
    /// The lattice's axes.
    pub axes: AxesReport,
    /// [`SWEEP_REPORT_FORMAT`].
    pub format: &'static str,
    /// The problem (its target unused).
    pub problem: SweepProblemReport,
    /// Targets with an admissible extremal.
    pub solved: usize,
    /// Seconds the sweep took.
    pub sweep_seconds: f64,
    /// Targets in all.
    pub targets: usize,
    /// [`SWEEP_REPORT_VERSION`].
    pub version: u64,
}

/// A sweep's axes: theta rad, x m, y m.
#[derive(Clone, Debug, Serialize)]
#[allow(missing_docs)]
pub struct AxesReport {
    pub theta: Vec<f64>,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
}

/// A sweep's problem in its `report.json` (fields in alphabetical order).
#[derive(Clone, Debug, Serialize)]
pub struct SweepProblemReport {
    /// `ᾱ`, rad.
    pub alpha0: [f64; 2],
    /// The end shape `β` (`ᾱ` for a loop), rad.
    pub alpha_end: [f64; 2],
    /// The joint limit, rad.
    pub alpha_max: Option<f64>,
    /// The running cost minimised (its name).
    pub cost: &'static str,
    /// `k`.
    pub drag: f64,
    /// `T`, s.
    pub horizon: f64,
    /// `(L0, L1, L2)`, m.
    pub links: [f64; 3],
    /// `r`.
    pub ratio: f64,
    /// `h`, s.
    pub step: f64,
}

impl SweepReport {
    /// The report of a sweep of `spec` over `lattice` that found `points` in `seconds`.
    pub fn new(spec: &Spec, lattice: &Lattice, points: &[SweepPoint], seconds: f64) -> Self {
        let [x, y, theta] = lattice.axes.clone();
        let admissible = |p: &&SweepPoint| p.result.as_ref().is_ok_and(|x| x.admissible);
        SweepReport {
            axes: AxesReport { theta, x, y },
            format: SWEEP_REPORT_FORMAT,
            problem: SweepProblemReport {
                alpha0: spec.alpha0,
                alpha_end: spec.alpha_end.unwrap_or(spec.alpha0),
                alpha_max: spec.alpha_max,
                cost: spec.cost.name(),
                drag: spec.drag,
                horizon: spec.horizon,
                links: spec.links,
                ratio: spec.ratio,
                step: spec.step,
            },
            solved: points.iter().filter(admissible).count(),
            sweep_seconds: seconds,
            targets: points.len(),
            version: SWEEP_REPORT_VERSION,
        }
    }
}
