//! What a solve gives: the extremals with their certificates ([`Extremal`], on a
//! [`Trajectory`]), the global search's evidence ([`Evidence`]), or why there is none
//! ([`SolveError`]).

use super::search;
use super::settings::{KKT_TOL, LAW_TOL, TERMINAL_TOL};
use nalgebra::{Vector2, Vector3};
use purcell_core::{Arc, Cost, State};

/// A trajectory on the grid: `k = 0..N` states, `k < N` controls, costates `ξ^{k−1}`.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Trajectory {
    /// `(α_k, g_k)`, `k = 0..=N`.
    pub states: Vec<State<f64>>,
    /// `u_k`, `k < N`.
    pub controls: Vec<Vector2<f64>>,
    /// `ξ^{k−1}`, `k = 0..=N` (the first is `ξ^{−1}`).
    pub xis: Vec<Vector2<f64>>,
}

/// One extremal of the fine problem, with its certificates.
#[derive(Clone, Debug, PartialEq)]
pub struct Extremal {
    /// `J` of the problem's cost ([`crate::problem::Problem::cost`]).
    pub cost: f64,
    /// `J` of its controls under each cost of [`Cost::ALL`] (effort, power, …), whichever the
    /// problem minimises.
    pub costs: [f64; Cost::ALL.len()],
    /// Spatial momentum `μ`.
    pub mu: Vector3<f64>,
    /// `ξ^{−1}`.
    pub xi0: Vector2<f64>,
    /// Largest `|α_i|` along the path.
    pub max_abs_alpha: f64,
    /// Whether the path is admissible ([`crate::problem::Problem::admits`]).
    pub admissible: bool,
    /// Terminal defect of the direct method's trajectory (largest component, m / rad).
    pub residual: f64,
    /// The same after re-integrating the controls through the core's kinematics
    /// ([`super::certificate::terminal_residual`]); `None` if the path is not admissible.
    pub terminal_residual: Option<f64>,
    /// Independent KKT residual ([`super::certificate::kkt`], rad/s, with the joint limit's
    /// multipliers); `None` if the path is not admissible (the core refuses shapes past the
    /// overlap limit).
    pub kkt_residual: Option<f64>,
    /// The joint limit's arcs: maximal runs of states `k = first..=last` on `σ α_{k,i} = α_max`
    /// (empty without a limit or where it is inactive), sorted by `(first, joint)` as a gait's
    /// arc table is ([`purcell_core::arc`]).
    pub arcs: Vec<Arc>,
    /// Smallest multiplier `η_k ≥ 0` of the joint limit over the arcs' states, from
    /// [`super::certificate::kkt`]; `None` without arcs.
    pub min_eta: Option<f64>,
    /// The direct method's own stationarity residual (rad/s).
    pub stationarity: f64,
    /// Relative deviation of the core's law from the controls ([`super::certificate::law_residual`]);
    /// `None` if the path is not admissible.
    pub law_residual: Option<f64>,
    /// Second-order sufficient condition: a strict local minimum.
    pub local_min: bool,
    /// Newton iterations on the fine grid.
    pub iterations: usize,
    /// Index of the start loop that first reached it in the global search (0: the zero loop,
    /// a minimum without the joint limit carried into it, or none: [`Solution::recentred`]).
    pub start: usize,
    /// How many starts of the global search reached it: those whose coarse minimum the
    /// refinement carried to it, on the problem's grid or by meeting its path on a finer grid
    /// ([`super::Stop::Repeat`]); a symmetric twin's count its own.
    pub hits: usize,
    /// For a problem that a symmetry of the swimmer maps to itself ([`super::symmetry`]): the
    /// index in [`Solution::extremals`] of this extremal's image (same cost, another loop),
    /// when found too.
    pub twin_of: Option<usize>,
    /// The trajectory with its costates.
    pub trajectory: Trajectory,
}

impl Extremal {
    /// Why its certificates do not vouch for it, if they do not: it must be admissible and a
    /// strict local minimum, land on the target through the core's kinematics within
    /// [`TERMINAL_TOL`], satisfy KKT within [`KKT_TOL`] and be reproduced by the core's law
    /// within [`LAW_TOL`] (relative); the bounds the tests hold every returned extremal to.
    pub fn uncertified(&self) -> Option<&'static str> {
        if !self.admissible {
            return Some("not admissible");
        }
        if !self.local_min {
            return Some("not a strict local minimum");
        }
        let residuals = [self.terminal_residual, self.kkt_residual, self.law_residual];
        residuals
            .into_iter()
            .zip(CERTIFICATES)
            .find(|(r, (bound, _))| !r.is_some_and(|r| r <= *bound))
            .map(|(_, (_, why))| why)
    }
}

/// The certificates' bounds, in the order [`Extremal::uncertified`] checks them, with how it
/// names a residual above each (sweep.csv's `status`).
const CERTIFICATES: [(f64, &str); 3] = [
    (TERMINAL_TOL, "terminal residual above 1e-10"),
    (KKT_TOL, "KKT residual above 1e-8"),
    (LAW_TOL, "law residual above 1e-9"),
];

/// Outcome of a solve.
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    /// Index into `extremals` of the returned one (the cheapest admissible).
    pub best: usize,
    /// Every distinct extremal carried to the fine grid, cheapest first.
    pub extremals: Vec<Extremal>,
    /// What the global search saw (`None` for a solve from a warm start, and for a gait
    /// flown `m` times).
    pub search: Option<Evidence>,
    /// `Some(m)`: no start of the search led to a gait, and the returned one was refined from
    /// the gait of the target's `m`-th root in `N/m` steps flown `m` times
    /// ([`super::periodic`]).
    pub flown: Option<usize>,
    /// Whether the returned extremal was reached by walking one of the refinement's admissible
    /// gaits back up the central path and down again, and refining where that ended
    /// ([`super::recentre`]): it was reached from no start ([`Extremal::hits`] 0).
    pub recentred: bool,
}

/// The global search's evidence for its answer ([`search`]'s stopping rule).
#[derive(Clone, Debug, PartialEq)]
pub struct Evidence {
    /// Start loops run.
    pub starts: usize,
    /// The budget ([`super::SolveOptions::budget`]).
    pub budget: usize,
    /// The distinct minima of the coarse problem, cheapest first.
    pub minima: Vec<Minimum>,
    /// Estimated chance that a further start reaches an unseen minimum no dearer than the
    /// cheapest admissible one ([`search::Search::unseen`]).
    pub unseen: f64,
    /// Boender and Rinnooy Kan's estimate of the number of minima
    /// ([`search::Search::expected_minima`]).
    pub expected_minima: f64,
    /// Whether the stopping rule was met within the budget.
    pub satisfied: bool,
    /// The minima the refinement tried and could not carry to the problem's grid.
    pub unrefined: Vec<Unrefined>,
    /// Distinct minima the start loops reached ([`search::Search::from_starts`]; under a
    /// joint limit the others are the free minima carried into it).
    pub from_starts: usize,
}

/// One distinct minimum of the coarse problem.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Minimum {
    /// `J` on the coarse grid.
    pub cost: f64,
    /// Largest `|α_i|` along it.
    pub max_abs_alpha: f64,
    /// How many starts reached it.
    pub hits: usize,
}

/// A minimum of the coarse problem whose refinement failed: Newton did not converge on a
/// finer grid, even from the fallbacks of [`super::refine`] (silently dropped, it may have
/// been the cheapest gait).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Unrefined {
    /// The coarse minimum.
    pub minimum: Minimum,
    /// The terminal defect on the finest grid its refinement reached (`∞`: no iterate to
    /// measure; skipped as a minimum the coarse grid does not resolve: its path's on the
    /// next grid, [`super::settings::UNRESOLVED`]).
    pub defect: f64,
    /// Whether it costs less on the coarse grid than the minimum the returned extremal was
    /// refined from: the extremal returned may then not be the cheapest.
    pub cheaper: bool,
}

impl core::fmt::Display for Unrefined {
    /// What a user is told of it (a warning when it is [`Unrefined::cheaper`]).
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "a minimum of the coarse search (J {:.6} on its grid, reached from {} start(s)) \
             could not be carried to the problem's grid (terminal defect {:.1e} on the finest \
             grid reached)",
            self.minimum.cost, self.minimum.hits, self.defect
        )?;
        if self.cheaper {
            write!(
                f,
                "; it is cheaper there than the gait returned, which may not be the cheapest"
            )?;
        }
        Ok(())
    }
}

impl Minimum {
    /// The coarse minimum of a search's candidate.
    pub fn of(c: &search::Candidate) -> Self {
        Minimum {
            cost: c.cost,
            max_abs_alpha: c.max_abs_alpha,
            hits: c.hits,
        }
    }
}

impl Evidence {
    /// The evidence of a finished search with budget `budget`, whose refinement left
    /// `unrefined`.
    pub(super) fn of(found: &search::Search, budget: usize, unrefined: Vec<Unrefined>) -> Self {
        Evidence {
            starts: found.starts,
            budget,
            minima: found.candidates.iter().map(Minimum::of).collect(),
            unseen: found.unseen,
            expected_minima: found.expected_minima(),
            satisfied: found.satisfied,
            unrefined,
            from_starts: found.from_starts,
        }
    }
}

/// Why no extremal was returned.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// No start converged.
    #[error("no start reached the target: best residual {best_residual:.3e}")]
    Unreachable {
        /// Smallest terminal defect reached by any start.
        best_residual: f64,
    },
    /// The search found extremals on its coarse grid, but none could be carried to the
    /// problem's grid.
    #[error(
        "{found} extremal(s) of the coarse search, none carried to the problem's grid: smallest terminal defect {best_residual:.3e}{}",
        stalled_stationarity(*.stationarity)
    )]
    NotRefined {
        /// How many were tried.
        found: usize,
        /// Smallest terminal defect where a refinement stopped.
        best_residual: f64,
        /// Smallest stationarity residual of the refinements that met their terminal defect
        /// and stalled there ([`super::Stop::Stationarity`]); `None` if none did.
        stationarity: Option<f64>,
    },
    /// Extremals were found but none is admissible.
    #[error(
        "{found} extremal(s) found, none admissible: the smallest largest |alpha_i| is {best_alpha:.4} rad, at or past the joint limit (or the links' overlap at pi)"
    )]
    NoneAdmissible {
        /// How many.
        found: usize,
        /// Smallest of their largest `|α_i|`.
        best_alpha: f64,
    },
}

/// [`SolveError::NotRefined`]'s words for refinements that stalled in stationarity.
fn stalled_stationarity(stationarity: Option<f64>) -> String {
    stationarity.map_or(String::new(), |s| {
        format!("; Newton met the terminal defect there but its stationarity stalled at {s:.1e}")
    })
}

#[cfg(test)]
mod tests {
    use super::CERTIFICATES;

    #[test]
    fn each_certificate_message_names_its_bound() {
        for (bound, why) in CERTIFICATES {
            assert!(why.ends_with(&format!(" above {bound:e}")), "{why}");
        }
    }
}
