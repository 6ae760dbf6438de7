//! The test vectors of MODEL.md §7: in f64 to 1e-12, in f32 to tolerances derived from the
//! conditioning of each computation (each stated next to its assertion).

use approx::assert_abs_diff_eq;
use nalgebra::{Matrix2, Matrix3x2, Vector2, Vector3};
use purcell_core::{Kinematics, OnArcs, Real, Se2, State, Swimmer, se2};

/// f32 unit roundoff scale: the spacing of f32 numbers at 1.
const EPS32: f64 = f32::EPSILON as f64;

/// `(α, A, ∂A/∂α1, ∂A/∂α2, κ)`: the vectors of §7, `κ` the 2-norm condition number of
/// `W_ξ(α)` (computed offline from the formulas of MODEL.md §2; it bounds how rounding in
/// `W_ξ` is amplified in `A = W_ξ⁻¹ W_α`).
#[allow(clippy::type_complexity)]
fn connection_vectors() -> Vec<(
    Vector2<f64>,
    Matrix3x2<f64>,
    Option<[Matrix3x2<f64>; 2]>,
    f64,
)> {
    #[rustfmt::skip]
    let v = vec![
        (
            Vector2::new(0.0, 0.0),
            Matrix3x2::new(0.0, 0.0, 1.0 / 6.0, -1.0 / 6.0, 7.0 / 27.0, 7.0 / 27.0),
            Some([
                Matrix3x2::new(-4.0 / 27.0, 2.0 / 27.0, 0.0, 0.0, 0.0, 0.0),
                Matrix3x2::new(-2.0 / 27.0, 4.0 / 27.0, 0.0, 0.0, 0.0, 0.0),
            ]),
            2.0,
        ),
        (
            Vector2::new(0.5, -0.3),
            Matrix3x2::new(-0.0524221297521321, -0.00701686926608808,
                0.159747833925603, -0.161423254304907, 0.251599627307099, 0.261512677482497),
            Some([
                Matrix3x2::new(-0.152107617787388, 0.0760042030565476,
                    -0.0305217670699354, 0.0194176398898804, -0.0372440829755903, 0.0271626047148062),
                Matrix3x2::new(-0.0753891916765094, 0.14775179529546,
                    7.14311629219022e-05, -0.00608113087579642, -0.00723135028726835, 0.02713380574958),
            ]),
            2.24,
        ),
        (
            Vector2::new(2.5, -2.9),
            Matrix3x2::new(-0.117128022444034, -0.0477262695677959,
                -0.139451363319512, 0.17511652971135, 0.340289571904178, 0.248062865707986),
            None,
            10.4,
        ),
    ];
    v
}

#[test]
fn connection_matches_model_vectors_f64() {
    let sw = Swimmer::<f64>::purcell();
    for (alpha, a, da, _) in connection_vectors() {
        let c = sw.connection_with_derivatives(&alpha).unwrap();
        // The vectors are printed to 15 significant digits (|A| < 0.35): 1e-12 is generous.
        assert_abs_diff_eq!(c.a, a, epsilon = 1e-12);
        assert_abs_diff_eq!(sw.connection(&alpha).unwrap(), a, epsilon = 1e-12);
        if let Some([d1, d2]) = da {
            assert_abs_diff_eq!(c.da[0], d1, epsilon = 1e-12);
            assert_abs_diff_eq!(c.da[1], d2, epsilon = 1e-12);
        }
    }
}

/// f32 tolerance for `A` and `∂A/∂α`: every entry of `W_ξ` and `W_α` is a sum of a few
/// products of numbers of size ≤ 1.5 built from `sin_cos` (≤ 2 ulp), so their normwise
/// relative error is ≲ 4ε; solving with `W_ξ` amplifies it by at most `κ(W_ξ)`, and
/// `∂A/∂α = W_ξ⁻¹(∂W_α − ∂W_ξ·A)` by the same factor once more through `A`. Hence
/// `|δA| ≤ 4·κ·ε·max|A|` and `|δ∂A| ≤ 8·κ·ε·max|∂A|`, plus the rounding of `α` to f32
/// (`|δα| ≤ ε/2·|α|`, times `|∂A| ≤ 0.2`). Measured: ≤ 0.25 ε at all three shapes.
#[test]
fn connection_matches_model_vectors_f32() {
    let sw = Swimmer::<f32>::purcell();
    for (alpha, a, da, kappa) in connection_vectors() {
        let c = sw
            .connection_with_derivatives(&alpha.map(|v| v as f32))
            .unwrap();
        let input = 0.5 * EPS32 * alpha.abs().max() * 0.2;
        let tol_a = 4.0 * kappa * EPS32 * a.abs().max() + input;
        assert_abs_diff_eq!(c.a.map(f64::from), a, epsilon = tol_a);
        if let Some([d1, d2]) = da {
            let tol_d = 8.0 * kappa * EPS32 * d1.abs().max().max(d2.abs().max()) + input;
            assert_abs_diff_eq!(c.da[0].map(f64::from), d1, epsilon = tol_d);
            assert_abs_diff_eq!(c.da[1].map(f64::from), d2, epsilon = tol_d);
        }
    }
}

/// `(X, exp(X) as (x, y, θ))` from §7.
fn exp_vectors() -> [(Vector3<f64>, Vector3<f64>); 2] {
    [
        (
            Vector3::new(1.0, 2.0, 0.7),
            Vector3::new(0.24843151686666864, 2.176561695986991, 0.7),
        ),
        (
            Vector3::new(0.3, -0.2, 1e-6),
            Vector3::new(0.30000009999995, -0.19999984999996667, 1e-6),
        ),
    ]
}

#[test]
fn exp_matches_model_vectors_f64() {
    for (x, g) in exp_vectors() {
        assert_abs_diff_eq!(se2::exp(&x).to_xytheta(), g, epsilon = 1e-12);
    }
    // At ω = 1e-6 the naive (1 − cos ω)/ω would keep only ~4 digits: check to 1e-15.
    let (x, g) = exp_vectors()[1];
    assert_abs_diff_eq!(se2::exp(&x).to_xytheta(), g, epsilon = 1e-15);
}

/// f32 tolerance for `exp`: the translation is `V(ω)·v` with `|a|, |b| ≤ 1` each accurate to
/// ≈ 2 ε (half-angle or series forms, no cancellation), so `|δp| ≤ 4ε·(|vx| + |vy|)` (the
/// inputs' own rounding is inside that); the angle goes through `sin_cos` (≤ 2 ulp) and
/// `atan2f`, so `|δθ| ≤ 4ε·|ω|` relative. Measured: ≤ 0.9 ε.
#[test]
fn exp_matches_model_vectors_f32() {
    for (x, g) in exp_vectors() {
        let got = se2::exp(&x.map(|v| v as f32)).to_xytheta().map(f64::from);
        let tol_p = 4.0 * EPS32 * (x.x.abs() + x.y.abs());
        assert_abs_diff_eq!(got.xy(), g.xy(), epsilon = tol_p);
        assert_abs_diff_eq!(got.z, g.z, epsilon = 4.0 * EPS32 * x.z.abs());
    }
}

/// The one-step vector of §7: inputs and expected outputs.
struct StepVector {
    alpha: Vector2<f64>,
    g: Vector3<f64>,
    xi: Vector2<f64>,
    mu: Vector3<f64>,
    u: Vector2<f64>,
    alpha_next: Vector2<f64>,
    g_next: Vector3<f64>,
    xi_next: Vector2<f64>,
}

fn step_vector() -> StepVector {
    StepVector {
        alpha: Vector2::new(0.3, -0.4),
        g: Vector3::new(0.05, -0.02, 0.2),
        xi: Vector2::new(0.01, -0.03),
        mu: Vector3::new(1.5, 13.2, 0.6),
        u: Vector2::new(-1.9485070881797708, 2.204985349281734),
        alpha_next: Vector2::new(0.2805149291182023, -0.37795014650718267),
        g_next: Vector3::new(
            0.04918563550870081,
            -0.013271901098288786,
            0.19942863681122489,
        ),
        xi_next: Vector2::new(0.03179965609005496, -0.019447012540811347),
    }
}

#[test]
fn law_step_matches_model_vector_f64() {
    let v = step_vector();
    let kin = Kinematics::new(Swimmer::<f64>::purcell(), 0.01).unwrap();
    let state = State {
        alpha: v.alpha,
        g: Se2::new(v.g.x, v.g.y, v.g.z),
    };
    let s = kin
        .law_step(&state, &v.xi, &v.mu, OnArcs::NONE, f64::PASSES)
        .unwrap();
    assert_abs_diff_eq!(s.u, v.u, epsilon = 1e-12);
    assert_abs_diff_eq!(s.next.alpha, v.alpha_next, epsilon = 1e-12);
    assert_abs_diff_eq!(s.next.g.to_xytheta(), v.g_next, epsilon = 1e-12);
    assert_abs_diff_eq!(s.xi, v.xi_next, epsilon = 1e-12);
    // The kinematics alone, under that control, reach the same state.
    let next = kin.step(&state, &v.u).unwrap();
    assert_abs_diff_eq!(next.alpha, v.alpha_next, epsilon = 1e-12);
    assert_abs_diff_eq!(next.g.to_xytheta(), v.g_next, epsilon = 1e-12);
}

/// f32 tolerance for the one-step vector, from the terms each output is computed from:
/// - `u = (I − hB)⁻¹(ξ − Aᵀζ)`: `A` carries ≲ 4κε relative error (κ ≈ 2.2 here, see
///   `connection_matches_model_vectors_f32`), `ζ ≈ Ad_gᵀμ` ≈ 2ε (rounded μ, g and the
///   products), the subtraction ε: so `|δu| ≤ (4κ + 4)·ε·T` with
///   `T = max_i |ξ_i| + Σ_j |A_ji||m_j|` (≈ 3.6 here, while |u| ≈ 2: mild cancellation);
///   `(I − hB)⁻¹` is within 3% of I and does not change that.
/// - `α' = α + hu`: `ε|α'| + h·|δu|`.
/// - `g' = g·exp(X)`: f32 `g` (2 ulp of sin_cos) composed with a step of size `h|Au| ≈ 5e-3`:
///   `4ε·max(1, |g|)`; `θ'` likewise through `atan2f`.
/// - `ξ' = ξ + hBu`: `ε|ξ'| + h·(|B|·|δu| + |u|·|δB|)` with `|δB| ≤ 8κε·|ζ|·max|∂A|`.
///
/// Measured: `u` 1.7 ε, everything else ≤ 0.3 ε.
#[test]
fn law_step_matches_model_vector_f32() {
    let v = step_vector();
    let h = 0.01;
    let kin = Kinematics::new(Swimmer::<f32>::purcell(), h as f32).unwrap();
    let state = State {
        alpha: v.alpha.map(|x| x as f32),
        g: Se2::new(v.g.x as f32, v.g.y as f32, v.g.z as f32),
    };
    let s = kin
        .law_step(
            &state,
            &v.xi.map(|x| x as f32),
            &v.mu.map(|x| x as f32),
            OnArcs::NONE,
            f32::PASSES,
        )
        .unwrap();

    // Sizes of the terms, from the f64 computation.
    let sw = Swimmer::<f64>::purcell();
    let c = sw.connection_with_derivatives(&v.alpha).unwrap();
    let m = Se2::new(v.g.x, v.g.y, v.g.z).adjoint_transpose_mul(&v.mu);
    let terms = v.xi.abs().max() + (c.a.abs().transpose() * m.abs()).max();
    let kappa = 2.2;
    let tol_u = (4.0 * kappa + 4.0) * EPS32 * terms;
    let b = Matrix2::from_fn(|i, j| m.dot(&c.da[i].column(j)));
    let max_da = c.da[0].abs().max().max(c.da[1].abs().max());
    let tol_b = 8.0 * kappa * EPS32 * m.abs().sum() * max_da;
    let tol_alpha = EPS32 * v.alpha_next.abs().max() + h * tol_u;
    let tol_g = 4.0 * EPS32;
    let tol_xi =
        EPS32 * v.xi_next.abs().max() + h * (b.abs().max() * 2.0 * tol_u + v.u.abs().sum() * tol_b);

    assert_abs_diff_eq!(s.u.map(f64::from), v.u, epsilon = tol_u);
    assert_abs_diff_eq!(
        s.next.alpha.map(f64::from),
        v.alpha_next,
        epsilon = tol_alpha
    );
    let g = s.next.g.to_xytheta().map(f64::from);
    assert_abs_diff_eq!(g, v.g_next, epsilon = tol_g);
    assert_abs_diff_eq!(s.xi.map(f64::from), v.xi_next, epsilon = tol_xi);
    // The tolerances are tight enough to see a lost digit: none exceeds 20 ε·|value|.
    assert!(tol_u < 20.0 * EPS32 * v.u.abs().max() && tol_xi < 20.0 * EPS32);
}
