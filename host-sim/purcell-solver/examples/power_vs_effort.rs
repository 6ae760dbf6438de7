//! The effort-optimal and the power-optimal gait of the paper's target (MODEL.md §11), each
//! from the global search and certified, with both costs of each and the power saved:
//!
//! ```text
//! cargo run --release -p purcell-solver --example power_vs_effort [ALPHA_MAX_RAD]
//! ```

use purcell_solver::problem::{Problem, Spec};
use purcell_solver::solver::cost::Cost;
use purcell_solver::solver::grid::Grid;
use purcell_solver::solver::stage::Rule;
use purcell_solver::solver::{Extremal, SolveOptions, solve};
use std::process::ExitCode;

/// The effort and the power cost of an extremal's controls on `p`'s own grid.
fn both_costs(p: &Problem, x: &Extremal) -> Option<[f64; 2]> {
    let u = &x.trajectory.controls;
    let cost = |c: Cost| {
        let grid = Grid::new(&p.with_cost(c), p.steps as usize, Rule::LEFT_POINT).ok()?;
        Some(grid.cost(u, &grid.rollout(u).ok()?))
    };
    Some([cost(Cost::Effort)?, cost(Cost::Power)?])
}

fn main() -> ExitCode {
    let alpha_max = match std::env::args().nth(1).map(|a| a.parse::<f64>()) {
        None => None,
        Some(Ok(a)) => Some(a),
        Some(Err(e)) => {
            eprintln!("error: ALPHA_MAX_RAD: {e}");
            return ExitCode::from(2);
        }
    };
    let spec = Spec {
        alpha_max,
        ..Spec::default()
    };
    let effort = match Problem::new(&spec) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    println!("paper's target, alpha-max {alpha_max:?}");
    println!(
        "| optimal for | effort J_E | power J_P | max |alpha_i| | arcs | KKT | law | certified |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let mut power_of = [0.0; 2];
    for (slot, cost) in Cost::ALL.into_iter().enumerate() {
        let p = effort.with_cost(cost);
        let Ok(s) = solve(&p, &SolveOptions::default(), &|| {}) else {
            eprintln!("error: no extremal for the {} cost", cost.name());
            return ExitCode::from(3);
        };
        let x = &s.extremals[s.best];
        let Some([je, jp]) = both_costs(&p, x) else {
            eprintln!("error: the {} gait does not roll out", cost.name());
            return ExitCode::from(3);
        };
        power_of[slot] = jp;
        let residual = |r: Option<f64>| r.map_or("–".into(), |r| format!("{r:.1e}"));
        println!(
            "| {} | {je:.9} | {jp:.9} | {:.4} | {} | {} | {} | {} |",
            cost.name(),
            x.max_abs_alpha,
            x.arcs.len(),
            residual(x.kkt_residual),
            residual(x.law_residual),
            x.uncertified().unwrap_or("yes"),
        );
    }
    let [effort_gait, power_gait] = power_of;
    println!(
        "power saved by the power-optimal gait: {:.2} %",
        100.0 * (1.0 - power_gait / effort_gait)
    );
    ExitCode::SUCCESS
}
