//! A prepared solve run, the same for every front end: from a warm start or the global
//! search, the fallback inside the links' overlap, and what to tell the user (notes on the
//! way, advice when nothing is found), worded per front end ([`Worded`]).

use crate::spec::{MAX_STARTS, Prepared};
use crate::words::{Front, Worded};
use purcell_solver::problem::{OVERLAP, Problem};
use purcell_solver::solver::continuation::{self, Warm};
use purcell_solver::solver::settings::OVERLAP_MARGIN;
use purcell_solver::solver::{Progress, Solution, SolveError, SolveOptions, solve, starts};
use std::time::Instant;

/// A solve that found a gait.
#[derive(Debug)]
pub struct Found {
    /// The solution.
    pub solution: Solution,
    /// The problem it solves: the prepared one, or with the overlap's margin as its joint
    /// limit ([`Note::OverlapMargin`]).
    pub problem: Problem,
    /// Seconds spent solving.
    pub seconds: f64,
    /// What the user is told on the way, in order.
    pub notes: Vec<Note>,
}

/// Something the user is told on the way to a gait.
#[derive(Debug)]
pub enum Note {
    /// The warm start reached no admissible extremal (`0`); the global search ran instead.
    WarmFailed(SolveError),
    /// Every extremal found crosses the links' overlap (`error`); the gait returned is the
    /// cheapest within [`OVERLAP_MARGIN`] of it, the problem with joint limit `alpha_max`.
    OverlapMargin {
        /// Why the problem as given has no gait.
        error: SolveError,
        /// `π − OVERLAP_MARGIN`.
        alpha_max: f64,
    },
}

impl Worded for Note {
    fn words(&self, f: Front) -> String {
        match self {
            Note::WarmFailed(e) => format!(
                "{} reached no admissible extremal of this problem ({e}); solved by the global \
                 search instead",
                f.arg(warm_arg(f))
            ),
            Note::OverlapMargin { error, alpha_max } => format!(
                "{error}: no gait found inside the links' overlap; solving for the cheapest \
                 within {OVERLAP_MARGIN} rad of it ({}); the gait returned rests on that bound \
                 where it has arcs ({}: alpha_max)",
                f.given("alpha_max", format!("{alpha_max:.4}")),
                match f {
                    Front::Cli => "report.json",
                    Front::Python => "report[\"problem\"]",
                }
            ),
        }
    }
}

/// The problem of an [`Unsolved`] solve without its joint limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Free {
    /// Solved: the largest `|α_i|` of its gait.
    Reach(f64),
    /// Not solved either: a looser limit would not help.
    Unsolved,
}

/// A solve that found no gait: why, and what to try.
#[derive(Debug)]
pub struct Unsolved {
    /// Why.
    pub error: SolveError,
    /// The problem as prepared.
    pub problem: Problem,
    /// Its budget of starts.
    pub starts: usize,
    /// Its seed.
    pub seed: u64,
    /// Under a joint limit, when no extremal was found past it: the same problem solved
    /// without it.
    pub free: Option<Free>,
}

impl Worded for Unsolved {
    /// The error, then on a line of its own what to try, by its cause: more starts (never more
    /// than the family holds), another seed (without a joint limit), a warm start, and a
    /// looser joint limit: when the extremals found lie past it, one that admits the nearest
    /// of them; otherwise one that admits the gait found without a limit, and none if that
    /// problem is not solved either.
    fn words(&self, f: Front) -> String {
        let (e, problem, starts) = (&self.error, &self.problem, self.starts);
        let boxes = problem.alpha_max.is_none();
        let family = starts::family(1.0, &problem.alpha0, 0, MAX_STARTS, boxes).len();
        let mut tries = Vec::new();
        if starts < family {
            let more = f.given("starts", (4 * starts).min(family));
            tries.push(format!("more starts ({more}; {starts} now)"));
        }
        // Under a joint limit every seed runs the same starts (the solver's `search`).
        if boxes {
            tries.push(format!("another {} ({} now)", f.arg("seed"), self.seed));
        }
        tries.push(format!(
            "a warm start from the gait of a nearer target, solved first ({})",
            match f {
                Front::Cli => "--from DIR/costate.json".into(),
                Front::Python => format!("{}=<its Solution>", warm_arg(f)),
            }
        ));
        // A limit that admits the gait without one solves (the search carries that gait in).
        let admits_free = match self.free {
            Some(Free::Reach(reach)) => Some(looser(reach))
                .filter(|l| problem.alpha_max.is_some_and(|limit| *l > limit) && *l < OVERLAP),
            _ => None,
        };
        match (e, problem.alpha_max) {
            (SolveError::NoneAdmissible { best_alpha, .. }, Some(limit)) => {
                // The nearest extremal found is admitted by a limit just above its reach.
                let looser = looser(*best_alpha);
                tries.push(if looser < OVERLAP {
                    format!(
                        "a looser joint limit ({}, which admits the nearest extremal found; \
                         {limit} now)",
                        f.given("alpha_max", looser)
                    )
                } else {
                    format!("a looser joint limit ({}; {limit} now)", f.arg("alpha_max"))
                });
            }
            (_, Some(limit)) if let Some(looser) = admits_free => tries.push(format!(
                "a looser joint limit ({}, which admits the gait found without one; {limit} \
                 now; tighter ones may solve too)",
                f.given("alpha_max", looser)
            )),
            (_, Some(_)) if self.free == Some(Free::Unsolved) => {}
            (SolveError::Unreachable { .. }, _) => {}
            (_, Some(limit)) => tries.push(format!(
                "a looser joint limit ({}; {limit} now)",
                f.arg("alpha_max")
            )),
            (SolveError::NoneAdmissible { .. }, None) => tries.push(format!(
                "another start shape if it is yours to choose ({}): every extremal found \
                 crosses the links' overlap",
                f.arg("alpha0")
            )),
            (_, None) => {}
        }
        let last = tries.pop().unwrap_or_default();
        let mut words = format!("{e}\ntry {}, or {last}", tries.join(", "));
        if self.free == Some(Free::Unsolved) {
            words +=
                "\nwithout the joint limit no gait is found either: a looser one would not help";
        }
        if let SolveError::NotRefined {
            stationarity: Some(_),
            ..
        } = e
        {
            words += "\nthe extremals found meet the target but none is certified stationary: \
                      seen on tiny targets, whose gait is a loop so small that the terminal \
                      constraint is nearly degenerate (the paper's swimmer: x of 5e-5 m or less, \
                      theta of 1e-6 rad; 1e-4 m and 1e-5 rad solve)";
        }
        words
    }
}

/// The limit, in hundredths of a radian, just above a reach `alpha` (so that it admits it).
fn looser(alpha: f64) -> f64 {
    ((alpha * 100.0).ceil() + 1.0) / 100.0
}

/// `problem` solved without its joint limit by `options` (its phases told to `progress`): the
/// largest `|α_i|` of the gait, whose minimum the search of any limit that admits it carries
/// into that limit; [`Free::Unsolved`] if no start reaches the target or nothing refines
/// there either; `None` if every extremal found crosses the links' overlap.
fn free_reach(problem: &Problem, options: &SolveOptions, progress: &dyn Progress) -> Option<Free> {
    let free = Problem {
        alpha_max: None,
        ..*problem
    };
    match solve(&free, options, progress) {
        Ok(s) => Some(Free::Reach(s.extremals[s.best].max_abs_alpha)),
        Err(SolveError::NoneAdmissible { .. }) => None,
        Err(_) => Some(Free::Unsolved),
    }
}

/// The keyword of a warm start: `--from` on the command line, `warm=` in Python.
fn warm_arg(f: Front) -> &'static str {
    match f {
        Front::Cli => "from",
        Front::Python => "warm",
    }
}

/// Solves `prepared` from `warm` (or by the global search: without one, or when it reaches no
/// admissible extremal), its phases told to `progress`. Without a joint limit, when every
/// extremal found crosses the links' overlap, the cheapest gait within [`OVERLAP_MARGIN`] of
/// it (the problem with joint limit `π − OVERLAP_MARGIN`), if there is one.
pub fn find(
    prepared: &Prepared,
    warm: Option<&Warm>,
    progress: &dyn Progress,
) -> Result<Found, Box<Unsolved>> {
    let (problem, options) = (&prepared.problem, &prepared.options);
    let t0 = Instant::now();
    let mut notes = Vec::new();
    let result = match warm {
        None => solve(problem, options, progress),
        Some(w) => {
            let (result, failed) = continuation::solve_from(problem, w, options, progress);
            notes.extend(failed.map(Note::WarmFailed));
            result
        }
    };
    let unsolved = |error, free| {
        Box::new(Unsolved {
            error,
            problem: *problem,
            starts: options.budget(problem),
            seed: options.seed,
            free,
        })
    };
    let (solution, problem) = match result {
        Ok(s) => (s, *problem),
        Err(error @ SolveError::NoneAdmissible { .. }) if problem.alpha_max.is_none() => {
            let alpha_max = OVERLAP - OVERLAP_MARGIN;
            let margin = Problem {
                alpha_max: Some(alpha_max),
                ..*problem
            };
            match solve(&margin, options, progress) {
                Ok(solution) => {
                    notes.push(Note::OverlapMargin { error, alpha_max });
                    (solution, margin)
                }
                Err(_) => return Err(unsolved(error, None)),
            }
        }
        // Under a joint limit with no extremal past it to name a looser one by: the solve
        // without the limit names one.
        Err(e @ (SolveError::Unreachable { .. } | SolveError::NotRefined { .. }))
            if problem.alpha_max.is_some() =>
        {
            let reach = free_reach(problem, options, progress);
            return Err(unsolved(e, reach));
        }
        Err(e) => return Err(unsolved(e, None)),
    };
    Ok(Found {
        solution,
        problem,
        seconds: t0.elapsed().as_secs_f64(),
        notes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use purcell_solver::problem::Spec;

    fn unsolved(error: SolveError, alpha_max: Option<f64>) -> Unsolved {
        let spec = Spec {
            alpha_max,
            ..Spec::default()
        };
        Unsolved {
            error,
            problem: Problem::new(&spec).unwrap(),
            starts: 16,
            seed: 3,
            free: None,
        }
    }

    #[test]
    fn extremals_past_the_limit_name_a_limit_that_admits_the_nearest() {
        let u = unsolved(
            SolveError::NoneAdmissible {
                found: 2,
                best_alpha: 1.2341,
            },
            Some(1.1),
        );
        let cli = u.words(Front::Cli);
        assert!(
            cli.contains("a looser joint limit (--alpha-max 1.25, which admits"),
            "{cli}"
        );
        // Under a joint limit every seed runs the same starts: more starts, not another seed.
        assert!(
            cli.contains("try more starts (--starts 64; 16 now), a warm start"),
            "{cli}"
        );
        let python = u.words(Front::Python);
        assert!(python.contains("(alpha_max=1.25, which admits"), "{python}");
        assert!(python.contains("starts=64") && python.contains("warm=") && !python.contains("--"));
    }

    /// Issue 33: under a joint limit with nothing found past it, the solve without the limit
    /// names a looser one (just above its gait's reach); if that is not solved either, none;
    /// never another seed (every seed runs the same starts there).
    #[test]
    fn the_solve_without_the_limit_names_a_looser_one_or_none() {
        let mut u = unsolved(SolveError::Unreachable { best_residual: 0.1 }, Some(0.3));
        u.free = Some(Free::Reach(1.2961));
        let words = u.words(Front::Cli);
        assert!(
            words.contains("or a looser joint limit (--alpha-max 1.31, which admits the gait found without one; 0.3 now"),
            "{words}"
        );
        // Every seed runs the same starts under a joint limit: no other seed to try.
        assert!(!words.contains("--seed"), "{words}");
        u.free = Some(Free::Reach(0.25));
        assert!(!u.words(Front::Cli).contains("alpha-max"));
        u.free = Some(Free::Unsolved);
        u.error = SolveError::NotRefined {
            found: 2,
            best_residual: 1e-18,
            stationarity: Some(1e-6),
        };
        let words = u.words(Front::Python);
        assert!(!words.contains("alpha_max"), "{words}");
        assert!(words.contains("a looser one would not help"), "{words}");
        assert!(words.contains("none is certified stationary"), "{words}");
    }

    #[test]
    fn no_looser_limit_for_a_target_no_start_reaches() {
        let u = unsolved(SolveError::Unreachable { best_residual: 0.1 }, Some(1.1));
        assert!(!u.words(Front::Cli).contains("alpha-max"));
        let u = unsolved(
            SolveError::NoneAdmissible {
                found: 1,
                best_alpha: 3.135,
            },
            Some(3.0),
        );
        let words = u.words(Front::Cli);
        assert!(
            words.contains("a looser joint limit (--alpha-max; 3 now)"),
            "{words}"
        );
    }
}
