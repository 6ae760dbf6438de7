//! Gaits flown `m` times (issue 33): where the search finds no gait under a tight joint
//! limit, the loop that moves the body by the `m`-th root of the target, flown `m` times.
//!
//! A loop returns the shape to `ᾱ`, so `m` flights of a loop that moves the body by
//! `ḡ_m = exp(log(ḡ)/m)` (SE(2)) in `N/m` steps move it by `ḡ_m^m = ḡ` in `N`, at `m` times
//! the loop's cost. Under a tight limit a distant or turning target asks for many strokes
//! (links 1, 0.93, 0.93 to (0.144, 0.023, −0.44): 14 arcs within 1.1 rad, 20 within 1), more
//! than the coarse grid of the search resolves, while the `m`-th part asks for `m` times
//! fewer. So [`solve`] solves the part (its own search and refinement) for the periods of
//! [`PERIODS`] that divide `N`, smallest first, flies its cheapest admissible gait `m` times,
//! and refines that on the problem's grid ([`refine_patiently`], [`PERIODIC_PATIENCE`]),
//! until one reaches an extremal: the flown gait is a feasible start, not an extremal (the
//! parts' momenta need not agree), and the refinement's extremal is the problem's own,
//! certified as every other. The smallest period first: its part is the least constrained
//! (in that example `m = 2` reaches 6.0971033, `m = 5` 7.0437850, `m = 4` stalls).

use super::homotopy;
use super::progress::Progress;
use super::refinement::{extremal, refine_patiently};
use super::settings::{FINE_TAUS, PERIODIC_PATIENCE, PERIODS};
use super::solution::{Solution, SolveError};
use crate::problem::Problem;
use nalgebra::{Vector2, Vector5};
use purcell_core::se2::{Se2, exp};

/// The `m`-th part of `problem`: the target `exp(log(ḡ)/m)` in `N/m` steps (`None` if `m`
/// does not divide `N`, or for a transition, whose end shape is not its start).
pub fn part(problem: &Problem, m: usize) -> Option<Problem> {
    let steps = u32::try_from(m)
        .ok()
        .filter(|&m| m > 0 && problem.steps.is_multiple_of(m))?;
    if problem.alpha_end != problem.alpha0 {
        return None;
    }
    let t = problem.target;
    let root = exp(&(Se2::new(t.x, t.y, t.z).log() / m as f64));
    Some(Problem {
        steps: problem.steps / steps,
        target: [root.x(), root.y(), root.theta()].into(),
        ..*problem
    })
}

/// The controls `u` of a loop flown `m` times.
pub fn flown(u: &[Vector2<f64>], m: usize) -> Vec<Vector2<f64>> {
    (0..m).flat_map(|_| u.iter().copied()).collect()
}

/// The gait of `problem` (under a joint limit) refined from its part's gait flown `m` times
/// (see the module docs), for the first `m` of [`PERIODS`] that reaches an admissible one
/// (each period a part's solve and a long refinement: tens of seconds); `solve_part` solves
/// a part (the solver's search and refinement, reporting its phases to `progress`);
/// `failed`, the problem's own search's failure, is returned if none does.
pub fn solve(
    problem: &Problem,
    progress: &dyn Progress,
    solve_part: &dyn Fn(&Problem) -> Result<Solution, SolveError>,
    failed: SolveError,
) -> Result<Solution, SolveError> {
    let Some(alpha_max) = problem.alpha_max else {
        return Err(failed);
    };
    for m in PERIODS {
        let Some(p) = part(problem, m) else {
            continue;
        };
        progress.phase(&format!("flown {m} times: the part"), 1, "parts");
        let Ok(s) = solve_part(&p) else {
            continue;
        };
        progress.phase(&format!("flown {m} times: refinement"), 1, "gaits");
        // Strictly inside the limit, as the barrier path needs it.
        let u = homotopy::clip_into(
            &flown(&s.extremals[s.best].trajectory.controls, m),
            &problem.alpha0,
            (1.0 - FINE_TAUS[0]) * alpha_max,
            problem.h,
        );
        let pulse = || progress.pulse();
        let refined = refine_patiently(problem, &u, &Vector5::zeros(), PERIODIC_PATIENCE, &pulse);
        progress.tick();
        if let Ok((grid, run)) = refined {
            let x = extremal(problem, &grid, &run);
            if x.admissible {
                return Ok(Solution {
                    best: 0,
                    extremals: vec![x],
                    search: None,
                    flown: Some(m),
                });
            }
        }
    }
    Err(failed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Spec;

    /// The `m`-th part's target composed `m` times is the target (a turn and a sideways
    /// move, `m` = 2 … 5); a period that does not divide `N`, and a transition, have none.
    #[test]
    fn the_parts_target_flown_m_times_is_the_target() {
        let problem = Problem::new(&Spec {
            target: [0.144, 0.023, -0.44],
            alpha_max: Some(1.0),
            ..Spec::default()
        })
        .unwrap();
        for m in [2, 4, 5] {
            let p = part(&problem, m).unwrap();
            assert_eq!(p.steps as usize * m, problem.steps as usize);
            let t = p.target;
            let root = Se2::new(t.x, t.y, t.z);
            let whole = (1..m).fold(root, |g, _| g * root).to_xytheta();
            assert!((whole - problem.target).amax() <= 1e-14, "{m}: {whole}");
        }
        assert!(part(&problem, 3).is_none());
        let transition = Problem::new(&Spec {
            alpha_end: Some([0.2, 0.0]),
            ..Spec::default()
        })
        .unwrap();
        assert!(part(&transition, 2).is_none());
        let u = [Vector2::new(1.0, 2.0), Vector2::new(3.0, 4.0)];
        assert_eq!(flown(&u, 2), [u[0], u[1], u[0], u[1]]);
    }

    /// Within 1 rad, links 1, 0.93, 0.93 to (0.144, 0.023, −0.44) in 5 000 steps of 0.02 s,
    /// no start of the search leads to a gait (`purcell-sim solve --step 0.02 …` exited 3
    /// before, 85 s of search and refinement): the gait of the half target in 2 500 steps,
    /// flown twice and refined, reaches 6.0894163 on 20 arcs, certified. About 20 CPU-s.
    #[test]
    fn a_tight_limits_turn_is_solved_from_its_half_flown_twice() {
        let problem = Problem::new(&Spec {
            target: [0.144, 0.023, -0.44],
            links: [1.0, 0.93, 0.93],
            alpha_max: Some(1.0),
            step: 0.02,
            ..Spec::default()
        })
        .unwrap();
        let options = crate::solver::SolveOptions::default();
        let part = |p: &Problem| super::super::searched(p, &options, &|| ());
        let failed = SolveError::Unreachable {
            best_residual: f64::INFINITY,
        };
        let s = solve(&problem, &|| (), &part, failed).unwrap();
        assert_eq!(s.flown, Some(2));
        let x = &s.extremals[s.best];
        assert!((x.cost - 6.0894163).abs() <= 1e-6, "{}", x.cost);
        assert!(x.admissible && x.local_min && x.min_eta.is_some_and(|e| e > 0.0));
        assert_eq!(x.arcs.len(), 20);
        assert!(
            x.kkt_residual.is_some_and(|r| r <= 1e-9),
            "{:?}",
            x.kkt_residual
        );
    }
}
