//! A limited solve's gaits walked back up the central path and down again (issue 33).
//!
//! Under a joint limit the search's cheapest gait rests on arcs of the limit found on a
//! 64-step grid, and a neighbouring basin may hold a cheaper gait that no start loop reached:
//! IPOPT started from our gait for `--alpha-max 1.5 --target -0.053,-0.226,0.53` (a random
//! probe, `peers/probe3.json` p17-5) first lifts it off its arcs with its first barrier
//! weight `μ₀ = 0.1`, and the path down ends on 7 arcs at J = 4.1770333, where we returned
//! 4.1967975 on 10. [`recentred`] does the same from each admissible extremal the refinement
//! found, the answer and the dearer ones ([`walked`]): the extremal sampled on
//! [`RECENTRE_STEPS`](super::settings::RECENTRE_STEPS) steps, just inside the limit, walked
//! along the barrier path from `τ = 0.1` ([`CENTRAL_PATHS`](super::settings::CENTRAL_PATHS)`[1]`,
//! 0.01–0.1 s). A walk that ends in another basin (farther than [`RECENTRE_SAME`] from the
//! extremal's path) and costs less there than the answer does on the problem's grid (or than
//! a cheaper extremal already reached) is refined to the problem's grid as a candidate is
//! ([`refine`](super::refine), given up once it costs more than that on a grid of
//! [`super::settings::GRADUAL_STEPS`] steps or more, [`FINE_PRUNE`](super::settings::FINE_PRUNE)),
//! and the cheapest admissible extremal reached is returned, certified as every other. On 27 limited problems
//! the walks back into the answer's basin cost 0.05 % less to 0.6 % more on their 256 steps
//! than the answer on the problem's grid, and three walks that ended elsewhere (0.33–0.96 rad
//! away) 0.18–0.42 % more (refined without the cost test: none cheaper, one back at the
//! answer after 10 s); p17-5's walk, 0.45 % less. Not only the answer's: at p17-5 the
//! refinement now also reaches 4.1912378 (8 arcs), the answer, whose walk stays in its basin,
//! while the walk of 4.1967975 reaches 4.1770333. A walk that ends in its extremal's basin,
//! or dearer, costs only the walk.
//!
//! The refinement walks so too the coarse minima whose refinement stalled on both of its
//! routes, and those that miss the target by more than 5 % on the next grid, that cost less
//! on the coarse grid than its settled gait ([`super::refinement::refine_candidates`]): from
//! the central path's far end Newton reaches on the finer grids what it does not from the
//! coarse minimum prolonged (`--alpha-max 1.2 --ratio 2.2 --target 0.087,0.28,0.14`,
//! `peers/probe4.json` p18-3: 9.3519385 from the coarse minimum 9.7390, where the refinement
//! had settled 9.9472948 and IPOPT found 9.9436241; p17-5: twenty far misses reach
//! 4.1770333, which the recentring found before).

use super::refinement::walked;
use super::settings::RECENTRE_SAME;
use super::solution::{Extremal, Solution};
use crate::problem::Problem;

/// `solution` of `problem` (under a joint limit; otherwise as it is) with the cheapest
/// extremal that the recentred walks of its admissible extremals reach, if that is admissible
/// and cheaper than its answer, returned instead ([`Solution::recentred`]; see the module
/// docs). `pulse` before each Newton iteration.
pub fn recentred(problem: &Problem, mut solution: Solution, pulse: &dyn Fn()) -> Solution {
    let Some(alpha_max) = problem.alpha_max else {
        return solution;
    };
    let mut cheapest: Option<Extremal> = None;
    for o in solution.extremals.iter().filter(|o| o.admissible) {
        let bound = cheapest
            .as_ref()
            .unwrap_or(&solution.extremals[solution.best])
            .cost;
        let u = &o.trajectory.controls;
        cheapest = walked(problem, u, (RECENTRE_SAME, bound), alpha_max, pulse).or(cheapest);
    }
    let Some(x) = cheapest else {
        return solution;
    };
    // Cheapest first: after every extremal that costs no more, the twins' indices shifted.
    let at = (solution.extremals.iter())
        .take_while(|o| o.cost <= x.cost)
        .count();
    for o in &mut solution.extremals {
        o.twin_of = o.twin_of.map(|i| i + usize::from(i >= at));
    }
    solution.extremals.insert(at, x);
    solution.best = at;
    solution.recentred = true;
    solution
}
