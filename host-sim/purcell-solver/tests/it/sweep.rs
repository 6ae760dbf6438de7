//! The atlas (`sweep`) against `solve`: at every target it is at least as cheap as the global
//! search there, a small lattice agrees with a large one where they share targets, and no
//! neighbour's gait, carried to a target, improves on it.

use nalgebra::Vector3;
use purcell_solver::problem::{Problem, Spec};
use purcell_solver::solver::continuation::{Lattice, SweepPoint, Warm, continue_to, sweep};
use purcell_solver::solver::{SolveOptions, solve};

fn atlas(x: (f64, f64, usize), y: (f64, f64, usize)) -> Vec<SweepPoint> {
    let lattice = Lattice {
        axes: [
            Lattice::spaced(x.0, x.1, x.2),
            Lattice::spaced(y.0, y.1, y.2),
            vec![0.0],
        ],
    };
    sweep(&Spec::default(), &lattice, &SolveOptions::default(), &|| {}).unwrap()
}

fn cost_at(points: &[SweepPoint], t: Vector3<f64>) -> f64 {
    let p = points
        .iter()
        .find(|p| (p.target - t).amax() <= 1e-9)
        .unwrap_or_else(|| panic!("no cell at {t}"));
    p.result.as_ref().expect("solved").cost
}

fn solve_cost(t: Vector3<f64>) -> f64 {
    let spec = Spec {
        target: [t.x, t.y, t.z],
        ..Spec::default()
    };
    let s = solve(
        &Problem::new(&spec).unwrap(),
        &SolveOptions::default(),
        &|| {},
    )
    .unwrap();
    s.extremals[s.best].cost
}

/// The default lattice (13 × 13 over ±0.3 m), the small one of 3 × 3 over [0, 0.2]²: the
/// small one's cells equal the large one's, and each is no dearer than `solve` (the paper's
/// target among them); so is the large one at (0.3, 0.1).
#[test]
fn the_atlas_is_no_dearer_than_solve_and_does_not_depend_on_the_lattice() {
    let large = atlas((-0.3, 0.3, 13), (-0.3, 0.3, 13));
    let small = atlas((0.0, 0.2, 3), (0.0, 0.2, 3));
    for p in &small {
        let x = p.result.as_ref().expect("solved");
        assert_eq!(x.uncertified(), None, "{}", p.target);
        // The check the sweep's `status` comes from rejects what it should.
        let mut bad = x.clone();
        bad.kkt_residual = Some(1e-6);
        assert_eq!(bad.uncertified(), Some("KKT residual above 1e-8"));
        bad.local_min = false;
        assert_eq!(bad.uncertified(), Some("not a strict local minimum"));
        bad.admissible = false;
        assert_eq!(bad.uncertified(), Some("not admissible"));
        let here = x.cost;
        let there = cost_at(&large, p.target);
        assert!(
            (here - there).abs() <= 1e-6 * here.max(1e-12),
            "{}: small lattice {here}, large {there}",
            p.target
        );
        let alone = solve_cost(p.target);
        assert!(
            here <= alone * (1.0 + 1e-6) + 1e-12,
            "{}: atlas {here}, solve {alone}",
            p.target
        );
    }
    let far = Vector3::new(0.3, 0.1, 0.0);
    let (here, alone) = (cost_at(&large, far), solve_cost(far));
    assert!(
        here <= alone * (1.0 + 1e-6),
        "{far}: atlas {here}, solve {alone}"
    );
    assert!((cost_at(&large, Vector3::new(0.1, 0.1, 0.0)) - 0.6817478081948872).abs() <= 1e-6);
}

/// Every cell of a small lattice, re-solved from each neighbour's gait (`solve --from`), gets
/// nothing cheaper than the atlas has.
#[test]
fn no_neighbour_gait_improves_a_cell() {
    let points = atlas((0.1, 0.3, 3), (0.1, 0.3, 3));
    for p in &points {
        let here = p.result.as_ref().expect("solved");
        let spec = Spec {
            target: [p.target.x, p.target.y, p.target.z],
            ..Spec::default()
        };
        let problem = Problem::new(&spec).unwrap();
        for q in &points {
            let d = (q.target - p.target).abs();
            let moved = d.iter().filter(|v| **v > 1e-12).count();
            if moved != 1 || d.max() > 0.1 + 1e-9 {
                continue; // neighbours only
            }
            let there = q.result.as_ref().expect("solved");
            let warm =
                Warm::from_trajectory(&there.trajectory, &there.mu, problem.horizon()).unwrap();
            if let Ok(x) = continue_to(&problem, &warm)
                && x.admissible
            {
                assert!(
                    x.cost >= here.cost * (1.0 - 1e-6),
                    "{} from {}: {} below the atlas's {}",
                    p.target,
                    q.target,
                    x.cost,
                    here.cost
                );
            }
        }
    }
}
