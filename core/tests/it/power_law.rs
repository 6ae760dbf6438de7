//! The power cost's law (MODEL.md §11) in the core: the step's `u_k` and `ξ^k` solve the
//! power's stationarity and adjoint, checked against a metric `G` built here from each link's
//! dissipation (not from the core's closed forms), in `f64` and `f32`, free and on an arc; and
//! how fast the passes converge (`-- --nocapture` prints the table MODEL.md §11 quotes).

use nalgebra::{Matrix2, Vector2, Vector3};
use purcell_core::{Cost, Kinematics, LawStep, OnArcs, Passes, Real, Se2, State, Swimmer, se2};

/// `uᵀG(α)u`: the power the three links dissipate with the body moving as the connection says
/// (`ξ = −A(α)u`), each link's drag from its own centre's velocity (MODEL.md §2).
fn dissipated(sw: &Swimmer<f64>, alpha: &Vector2<f64>, u: &Vector2<f64>) -> f64 {
    let [l0, l1, l2] = sw.lengths();
    let (k, r) = (sw.drag(), sw.ratio());
    let xi = -(sw.connection(alpha).unwrap() * u);
    let (vx, vy, w) = (xi.x, xi.y, xi.z);
    let ((s1, c1), (s2, c2)) = (alpha.x.sin_cos(), alpha.y.sin_cos());
    // (length, centre, ∂centre/∂α_j·u_j, direction, own turning rate)
    let links = [
        (l0, (0.0, 0.0), (0.0, 0.0), (1.0, 0.0), 0.0),
        (
            l1,
            (l0 / 2.0 + l1 / 2.0 * c1, l1 / 2.0 * s1),
            (-l1 / 2.0 * s1 * u.x, l1 / 2.0 * c1 * u.x),
            (c1, s1),
            u.x,
        ),
        (
            l2,
            (-l0 / 2.0 - l2 / 2.0 * c2, -l2 / 2.0 * s2),
            (l2 / 2.0 * s2 * u.y, -l2 / 2.0 * c2 * u.y),
            (c2, s2),
            u.y,
        ),
    ];
    links
        .iter()
        .map(|&(l, (cx, cy), (dx, dy), (tx, ty), turn)| {
            let (px, py) = (vx - w * cy + dx, vy + w * cx + dy);
            let (par, perp) = (px * tx + py * ty, py * tx - px * ty);
            let rate = w + turn;
            k * l * par * par + r * k * l * perp * perp + r * k * l * l * l / 12.0 * rate * rate
        })
        .sum()
}

/// `G(α)` by polarisation of [`dissipated`].
fn metric(sw: &Swimmer<f64>, alpha: &Vector2<f64>) -> Matrix2<f64> {
    let p = |u: Vector2<f64>| dissipated(sw, alpha, &u);
    let (e1, e2) = (Vector2::x(), Vector2::y());
    let g12 = (p(e1 + e2) - p(e1) - p(e2)) / 2.0;
    Matrix2::new(p(e1), g12, g12, p(e2))
}

/// `c_i = uᵀ∂G/∂α_i u` by a central difference of [`metric`].
fn shape_gradient(sw: &Swimmer<f64>, alpha: &Vector2<f64>, u: &Vector2<f64>) -> Vector2<f64> {
    let e = 1e-5;
    Vector2::from_fn(|i, _| {
        let mut d = Vector2::zeros();
        d[i] = e;
        let dg = (metric(sw, &(alpha + d)) - metric(sw, &(alpha - d))) / (2.0 * e);
        u.dot(&(dg * u))
    })
}

/// The residual of the power law at one step, relative to `|Gu|`: the stationarity
/// `Gu − ξ^k + Aᵀζ` (rows of the joints not on an arc) and, for a joint on an arc, `u_i = 0`
/// and `ξ^k_i = (Gu)_i + (Aᵀζ)_i`; with `ξ^k = ξ^{k−1} + hBu + (h/2)c` off the arc.
fn law_residual(
    kin: &Kinematics<f64>,
    s: &State<f64>,
    xi_prev: &Vector2<f64>,
    mu: &Vector3<f64>,
    step: &LawStep<f64>,
    on: OnArcs,
) -> f64 {
    let (sw, h, u, xi) = (kin.swimmer(), kin.h(), &step.u, &step.xi);
    let c = sw.connection_with_derivatives(&s.alpha).unwrap();
    let zeta = se2::dexp(&(c.a * u * -h)).transpose() * s.g.adjoint_transpose_mul(mu);
    let bu = Vector2::new(zeta.dot(&(c.da[0] * u)), zeta.dot(&(c.da[1] * u)));
    let xi_k = xi_prev + bu * h + shape_gradient(sw, &s.alpha, u) * (0.5 * h);
    let gu = metric(sw, &s.alpha) * u;
    let stationary = gu + c.a.transpose() * zeta;
    let mut worst = 0.0f64;
    for i in 0..2 {
        worst = worst.max(if on.0[i] {
            u[i].abs().max((xi[i] - stationary[i]).abs())
        } else {
            (stationary[i] - xi_k[i]).abs().max((xi[i] - xi_k[i]).abs())
        });
    }
    worst / gu.amax()
}

/// Steps of MODEL.md §7's size: (α, g, ξ^{k−1}, μ) with `|u|` from about 0.5 to 3 rad/s.
fn cases() -> [(State<f64>, Vector2<f64>, Vector3<f64>); 3] {
    let at = |a: (f64, f64), g: (f64, f64, f64)| State {
        alpha: Vector2::new(a.0, a.1),
        g: Se2::new(g.0, g.1, g.2),
    };
    [
        (
            at((0.3, -0.4), (0.05, -0.02, 0.2)),
            Vector2::new(0.01, -0.03),
            Vector3::new(1.5, 13.2, 0.6),
        ),
        (
            at((1.2, 0.7), (0.1, 0.08, -0.5)),
            Vector2::new(0.2, -0.1),
            Vector3::new(-2.0, 4.0, 0.3),
        ),
        (
            at((-2.1, 2.6), (-0.3, 0.2, 2.0)),
            Vector2::new(-0.05, 0.12),
            Vector3::new(0.4, -3.0, -1.1),
        ),
    ]
}

#[test]
fn the_test_metric_is_model_s() {
    let sw = Swimmer::purcell();
    let g = metric(&sw, &Vector2::zeros());
    let want = Matrix2::new(16.0, -11.0, -11.0, 16.0) / 81.0;
    assert!((g - want).amax() < 1e-15, "{g}");
    let g = metric(&sw, &Vector2::new(0.5, -0.3));
    assert!((g.m11 - 0.2232094378997902).abs() < 1e-14);
    assert!((g.m12 + 0.1507931009899087).abs() < 1e-14);
}

#[test]
fn a_power_step_solves_the_power_law_free_and_on_arcs() {
    let h = 0.01;
    for sw in [
        Swimmer::purcell(),
        Swimmer::new([1.0, 0.7, 1.3], 2.5, 3.0).unwrap(),
    ] {
        let kin = Kinematics::new(sw, h).unwrap();
        let kin32 = Kinematics::new(
            Swimmer::new(
                sw.lengths().map(|l| l as f32),
                sw.drag() as f32,
                sw.ratio() as f32,
            )
            .unwrap(),
            h as f32,
        )
        .unwrap();
        for (s, xi, mu) in cases() {
            for on in [OnArcs::NONE, OnArcs([true, false]), OnArcs([false, true])] {
                let step = kin
                    .law_step_for(&s, &xi, &mu, Cost::Power, on, f64::POWER_PASSES)
                    .unwrap();
                let r = law_residual(&kin, &s, &xi, &mu, &step, on);
                assert!(r < 1e-9, "f64 {on:?}: residual {r:.1e}");
                // On an arc the joint rests exactly.
                for i in 0..2 {
                    assert!(!on.0[i] || step.u[i] == 0.0);
                }
                // f32: the same step to f32's rounding of its terms.
                let s32 = State {
                    alpha: s.alpha.cast::<f32>(),
                    g: Se2::new(s.g.x() as f32, s.g.y() as f32, s.g.theta() as f32),
                };
                let step32 = kin32
                    .law_step_for(
                        &s32,
                        &xi.cast(),
                        &mu.cast(),
                        Cost::Power,
                        on,
                        f32::POWER_PASSES,
                    )
                    .unwrap();
                let du = (step32.u.cast::<f64>() - step.u).amax() / step.u.amax();
                assert!(du < 2e-5, "f32 {on:?}: |δu|/|u| = {du:.1e}");
                // The power's law differs from the effort's.
                let effort = kin.law_step(&s, &xi, &mu, on, f64::PASSES).unwrap();
                assert!((effort.u - step.u).amax() > 1e-2 * step.u.amax());
            }
        }
    }
}

#[test]
fn both_joints_on_arcs_rest_with_the_costate_of_the_stationarity() {
    let kin = Kinematics::new(Swimmer::purcell(), 0.01).unwrap();
    let (s, xi, mu) = cases()[1];
    let step = kin
        .law_step_for(
            &s,
            &xi,
            &mu,
            Cost::Power,
            OnArcs([true, true]),
            f64::POWER_PASSES,
        )
        .unwrap();
    assert_eq!(step.u, Vector2::zeros());
    // u = 0: ζ = m, ξ^k = Aᵀm.
    let a = kin.swimmer().connection(&s.alpha).unwrap();
    let want = a.transpose() * s.g.adjoint_transpose_mul(&mu);
    assert!((step.xi - want).amax() < 1e-14);
}

#[test]
fn passes_converge_to_the_root_of_the_power_law() {
    let kin = Kinematics::new(Swimmer::purcell(), 0.01).unwrap();
    println!("power law, |u - u(Newton 10)| / |u| after the first iterate and passes:");
    for (s, xi, mu) in cases()
        .into_iter()
        .flat_map(|(s, xi, mu)| [0.03, 0.3, 1.0].map(|f| (s, xi * f, mu * f)))
    {
        let u = |p: Passes| {
            kin.law_step_for(&s, &xi, &mu, Cost::Power, OnArcs::NONE, p)
                .unwrap()
                .u
        };
        let root = u(Passes::newton(10));
        let rel = |p| (u(p) - root).amax() / root.amax();
        let (first, plain, newton, newton2) = (
            rel(Passes::plain(0)),
            rel(Passes::plain(1)),
            rel(Passes::newton(1)),
            rel(Passes::newton(2)),
        );
        println!(
            "|u| {:.2}: first {first:.1e}, plain 1 {plain:.1e}, newton 1 {newton:.1e}, \
             newton 2 {newton2:.1e}",
            root.amax()
        );
        // Each pass gains: the first iterate's error squared by Newton, cut by the plain pass.
        assert!(first < 2e-3 && plain < 1e-2 * first && newton2 < 1e-13);
        assert!(newton < 1e-4 * first.max(1e-11) || newton < 1e-15);
    }
}
