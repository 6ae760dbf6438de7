//! Gaits flown `m` times (issue 33): where the search finds no gait under a tight joint
//! limit, the loop that moves the body by the `m`-th root of the target, flown `m` times.
//!
//! A loop returns the shape to `ᾱ`, so `m` flights of a loop that moves the body by
//! `ḡ_m = exp(log(ḡ)/m)` (SE(2)) in `N/m` steps move it by `ḡ_m^m = ḡ` in `N`, at `m` times
//! the loop's cost. Under a tight limit a distant or turning target asks for many strokes
//! (links 1, 0.93, 0.93 to (0.144, 0.023, −0.44): 14 arcs within 1.1 rad, 20 within 1), more
//! than the coarse grid of the search resolves, while the `m`-th part asks for `m` times
//! fewer. So [`solve`] solves the part (its own search and refinement) for each period of
//! [`PERIODS`] that divides `N`, flies its cheapest admissible gait `m` times, and refines
//! that on the problem's grid ([`refine_patiently`], [`PERIODIC_PATIENCE`]; if that stalls,
//! from the flown gait sampled on a coarse grid), and returns the cheapest extremal reached:
//! the flown gait is a feasible start, not an extremal (the parts' momenta need not agree),
//! and the refinement's extremal is the problem's own, certified as every other. No period
//! is always the best (in that example `m = 2` reaches 6.0971033, `m = 5` 7.0437850, `m = 4`
//! stalls; in another `m = 4` and 5 reach 16.4368808 and 13.3076662).

use super::grid;
use super::homotopy;
use super::progress::Progress;
use super::refinement::{extremal, refine_patiently};
use super::settings::{FINE_TAUS, FLOWN_SAMPLE, PERIODIC_PATIENCE, PERIODS};
use super::solution::{Extremal, Solution, SolveError};
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

/// The cheapest gait of `problem` (under a joint limit) refined from a part's gait flown `m`
/// times (see the module docs), over the `m` of [`PERIODS`] that reach an admissible one
/// (each period a part's solve and a long refinement: tens of seconds to minutes; the first
/// that refines is not always the cheapest: `--alpha-max 1.2 --ratio 2.2 --links
/// 1.0,1.02,0.78 --target 0.210,0.288,0.34` 16.4368808 from `m` = 4, 13.3076662 from 5);
/// `solve_part` solves a part (the solver's search and refinement, reporting its phases to
/// `progress`); `None` if none does.
pub fn solve(
    problem: &Problem,
    progress: &dyn Progress,
    solve_part: &dyn Fn(&Problem) -> Result<Solution, SolveError>,
) -> Option<Solution> {
    let alpha_max = problem.alpha_max?;
    let mut best: Option<(Extremal, usize)> = None;
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
        let x = starts(problem, u).find_map(|start| refined(problem, &start, &pulse));
        progress.tick();
        if let Some(x) = x.filter(|x| best.as_ref().is_none_or(|(b, _)| x.cost < b.cost)) {
            best = Some((x, m));
        }
    }
    let (x, m) = best?;
    Some(Solution {
        best: 0,
        extremals: vec![x],
        search: None,
        flown: Some(m),
        recentred: false,
    })
}

/// The starts of the refinement of a flown gait `u` (on the problem's grid), in turn: `u`
/// itself, and `u` sampled on [`FLOWN_SAMPLE`] steps, from where the refinement walks the
/// barrier paths of the gradual grids ([`refine_patiently`]). On `--alpha-max 1.2 --ratio
/// 2.2 --links 1.0,1.02,0.78 --target 0.210,0.288,0.34` the first stalls for every period
/// (the flown gaits of `m` = 2, 4, 5 cost 22.27, 23.50, 27.18), the second reaches 16.4368808
/// from `m` = 4 and 13.3076662 from `m` = 5 (not from 2): on the problem's grid the barrier
/// path creeps from a start far from its central path, on 1 024 steps it walks.
fn starts(problem: &Problem, u: Vec<Vector2<f64>>) -> impl Iterator<Item = Vec<Vector2<f64>>> {
    let sampled = (problem.steps as usize > FLOWN_SAMPLE).then(|| grid::prolong(&u, FLOWN_SAMPLE));
    core::iter::once(u).chain(sampled)
}

/// The admissible extremal of `problem` refined from `start` ([`refine_patiently`] with
/// [`PERIODIC_PATIENCE`]), if it reaches one.
fn refined(problem: &Problem, start: &[Vector2<f64>], pulse: &dyn Fn()) -> Option<Extremal> {
    let zero = Vector5::zeros();
    let (grid, run) = refine_patiently(problem, start, &zero, PERIODIC_PATIENCE, pulse).ok()?;
    let x = extremal(problem, &grid, &run);
    x.admissible.then_some(x)
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
    /// flown twice and refined, reaches 6.0894163 on 20 arcs, certified. From the second
    /// start, the flown gait sampled on 256 steps, the refinement reaches an extremal of the
    /// same cost to 1e-6 (6.0894175: an arc's end a step away). About 50 CPU-s.
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
        let searched = |p: &Problem| super::super::searched(p, &options, &|| ());
        let s = solve(&problem, &|| (), &searched).unwrap();
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
        let alpha_max = problem.alpha_max.unwrap();
        let half = searched(&part(&problem, 2).unwrap()).unwrap();
        let u = flown(&half.extremals[half.best].trajectory.controls, 2);
        let u = homotopy::clip_into(
            &u,
            &problem.alpha0,
            (1.0 - FINE_TAUS[0]) * alpha_max,
            problem.h,
        );
        let [whole, sampled] = &starts(&problem, u).collect::<Vec<_>>()[..] else {
            panic!("two starts")
        };
        assert_eq!((whole.len(), sampled.len()), (5000, FLOWN_SAMPLE));
        let y = refined(&problem, sampled, &|| ()).expect("an admissible extremal");
        assert!(
            (y.cost - x.cost).abs() <= 1e-6 * x.cost,
            "{} {}",
            y.cost,
            x.cost
        );
        assert!(y.local_min && y.kkt_residual.is_some_and(|r| r <= 1e-9));
    }
}
