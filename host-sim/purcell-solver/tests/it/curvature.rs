//! The curvature of the connection against the core's exact kinematics: the net motion of a
//! small shape loop, divided by the area it encloses, tends to `F` at its centre.

use nalgebra::{Vector2, Vector3};
use purcell_core::{Kinematics, State, Swimmer};
use purcell_solver::curvature::{Field, curvature};
use std::f64::consts::PI;

/// Relative tolerance of motion/area against `F` for loops of radius 1e-3 (measured: at most
/// 1.4e-3, near `α1 = 2.8` where `F` varies fastest; 8 000 steps per loop).
const TOL: f64 = 5e-3;

/// `log(g_end)` after the circle of radius `eps` around `centre`, run as `steps` steps of
/// the exact kinematics (counter-clockwise if `ccw`), starting at `centre + (eps, 0)`.
fn loop_motion(swimmer: Swimmer<f64>, centre: Vector2<f64>, eps: f64, ccw: bool) -> Vector3<f64> {
    let steps = 8000;
    let kin = Kinematics::new(swimmer, 1.0).unwrap();
    let sign = if ccw { 1.0 } else { -1.0 };
    let at = |j: usize| {
        let phi = sign * 2.0 * PI * j as f64 / steps as f64;
        centre + eps * Vector2::new(phi.cos(), phi.sin())
    };
    let mut state = State::at_origin(at(0));
    for j in 0..steps {
        state = kin.step(&state, &(at(j + 1) - at(j))).unwrap();
    }
    state.g.log()
}

#[test]
fn small_loops_move_the_body_by_curvature_times_area() {
    let swimmers = [
        Swimmer::purcell(),
        Swimmer::new([1.0, 0.6, 1.4], 1.0, 3.0).unwrap(),
    ];
    let centres = [
        (0.0, 0.0),
        (0.5, -0.3),
        (1.2, 0.9),
        (-2.0, 2.5),
        (2.8, -1.0),
    ];
    for swimmer in swimmers {
        for &(c1, c2) in &centres {
            let centre = Vector2::new(c1, c2);
            let f = curvature(&swimmer, &centre).unwrap();
            let scale = f.amax();
            assert!(scale > 1e-3, "F({centre:?}) too small to test: {f:?}");
            // Both orientations, two radii: motion / signed area → F. Averaging the two
            // orientations cancels the O(1/steps) error of the discrete loop and leaves the
            // O(eps) one, which must shrink with eps.
            let mut averaged = Vec::new();
            for eps in [1e-3, 5e-4] {
                let area = PI * eps * eps;
                let ccw = loop_motion(swimmer, centre, eps, true) / area;
                let cw = loop_motion(swimmer, centre, eps, false) / -area;
                for d in [ccw, cw] {
                    let err = (d - f).amax() / scale;
                    assert!(
                        err < TOL,
                        "centre {centre:?}, eps {eps}: motion/area {d:?}, F {f:?}"
                    );
                }
                averaged.push(((ccw + cw) / 2.0 - f).amax() / scale);
            }
            assert!(
                averaged[1] < 0.7 * averaged[0] || averaged[1] < 1e-6,
                "{averaged:?}"
            );
            // The bracket term is far above that error: with its sign flipped, F would miss.
            let a = swimmer.connection(&centre).unwrap();
            let bracket = purcell_core::se2::ad(&a.column(0).into_owned()) * a.column(1);
            assert!(
                2.0 * bracket.amax() > 10.0 * TOL * scale,
                "{bracket:?} {f:?}"
            );
        }
    }
}

#[test]
fn model_test_vectors() {
    // At α = 0 from MODEL.md §7: ∂A₂/∂α1 − ∂A₁/∂α2 = (4/27, 0, 0), [A₁, A₂] = (7/81, 0, 0).
    let swimmer = Swimmer::purcell();
    let f = curvature(&swimmer, &Vector2::zeros()).unwrap();
    assert!(
        (f - Vector3::new(-5.0 / 81.0, 0.0, 0.0)).amax() < 1e-15,
        "{f:?}"
    );
    // At α = (0.5, −0.3) (MODEL.md §8's regression vector), from an independent
    // implementation: CasADi's graph of the connection in peers/casadi_m4f/gen_step.py,
    // ∂A/∂α by CasADi's AD, F = [A₁, A₂] − (∂A₂/∂α1 − ∂A₁/∂α2) (CasADi 3.8.2); it gives
    // (−5/81, 0, 0) at α = 0 too.
    let f = curvature(&swimmer, &Vector2::new(0.5, -0.3)).unwrap();
    let want = Vector3::new(
        -0.06900328033932962,
        -0.0074025989083540255,
        -0.03439395500207451,
    );
    assert!((f - want).amax() < 1e-15, "{f:?}");
}

#[test]
fn field_matches_pointwise_curvature_and_is_symmetric() {
    let swimmer = Swimmer::purcell();
    let field = Field::sample(&swimmer, 12).unwrap();
    assert_eq!(field.values.len(), 144);
    let n = field.centres.len();
    for j in 0..n {
        for i in 0..n {
            let a = Vector2::new(field.centres[i], field.centres[j]);
            assert_eq!(field.at(i, j), curvature(&swimmer, &a).unwrap());
            // Mirror images of a swimmer with equal outer links. Across the body's y axis
            // (front and rear swap): (α1, α2) → (−α2, −α1), loops reverse, (vx, vy, ω) →
            // (−vx, vy, −ω), so F_x and F_θ keep and F_y flips. Across its x axis: α → −α,
            // loops keep their sense, (vx, vy, ω) → (vx, −vy, −ω).
            let f = field.at(i, j);
            let front_rear = field.at(n - 1 - j, n - 1 - i);
            let up_down = field.at(n - 1 - i, n - 1 - j);
            let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
            assert!(
                close(front_rear.x, f.x) && close(front_rear.y, -f.y) && close(front_rear.z, f.z)
            );
            assert!(close(up_down.x, f.x) && close(up_down.y, -f.y) && close(up_down.z, -f.z));
        }
    }
    let csv = field.to_csv();
    assert_eq!(csv.lines().count(), 145);
    assert_eq!(
        csv.lines().next(),
        Some("alpha1,alpha2,curvature_x,curvature_y,curvature_theta")
    );
}

#[test]
fn integral_over_a_loop_weights_by_winding_number() {
    let swimmer = Swimmer::purcell();
    let field = Field::sample(&swimmer, 180).unwrap();
    let (centre, r) = (Vector2::new(0.4, -0.7), 0.6);
    let circle = |turns: f64| -> Vec<Vector2<f64>> {
        (0..2000)
            .map(|j| {
                let phi = turns * 2.0 * PI * j as f64 / 2000.0;
                centre + r * Vector2::new(phi.cos(), phi.sin())
            })
            .collect()
    };
    // ∬ F over the disc by polar quadrature (midpoint in r and φ), independent of the grid.
    let mut disc = Vector3::zeros();
    let (nr, nphi) = (60, 240);
    for i in 0..nr {
        let rho = r * (i as f64 + 0.5) / nr as f64;
        for j in 0..nphi {
            let phi = 2.0 * PI * (j as f64 + 0.5) / nphi as f64;
            let a = centre + rho * Vector2::new(phi.cos(), phi.sin());
            disc +=
                curvature(&swimmer, &a).unwrap() * rho * (r / nr as f64) * (2.0 * PI / nphi as f64);
        }
    }
    let ccw = field.integral_over(&circle(1.0));
    let cw = field.integral_over(&circle(-1.0));
    let twice = field.integral_over(&circle(2.0));
    let scale = disc.amax();
    // Cells of 2° cut the disc's edge: a few parts in a thousand.
    assert!(
        (ccw - disc).amax() < 5e-3 * scale,
        "{ccw:?} against {disc:?}"
    );
    assert_eq!(cw, -ccw);
    assert!((twice - 2.0 * ccw).amax() < 1e-12 * scale);
}
