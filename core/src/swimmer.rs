//! The swimmer's parameters and its local connection `A(α)` from resistive-force theory.
//!
//! Body frame at the centre of the middle link (length `L0`), x-axis along it. The front link
//! (`L1`) is hinged at `(+L0/2, 0)` at angle `α1`; the rear link (`L2`) at `(−L0/2, 0)` points
//! backwards at angle `α2` (MODEL.md §1). A link of length `l` with unit tangent `t`, normal
//! `n`, centre `c` feels the drag `F = −k·l·(t tᵀ + r·n nᵀ)·v_c` and the moment
//! `−r·k·l³/12·(rate of turn)`. With `τ = (t, c×t)` and `ν = (n, c×n)` the Stokes balance of
//! forces and moments about the body origin reads `W_ξ(α)·ξ + W_α(α)·α̇ = 0` with
//!
//! ```text
//! W_ξ = Σ_links l·(τ τᵀ + r·ν νᵀ + r·l²/12·e₃e₃ᵀ)           (symmetric positive definite)
//! W_α = [ r·L1²·(ν₁/2 + L1/12·e₃),  r·L2²·(−ν₂/2 + L2/12·e₃) ]
//! ```
//!
//! (the common factor `k` cancels), so that `ξ = g⁻¹ġ = −A(α)·α̇` with `A = W_ξ⁻¹ W_α` and
//! `∂A/∂αᵢ = W_ξ⁻¹ (∂W_α/∂αᵢ − ∂W_ξ/∂αᵢ · A)`: closed form, no numerical differentiation.
//! Rows of `A` are x, y, θ; columns α1, α2.

use crate::{Error, Real};
use nalgebra::{Matrix3x2, Vector2};

/// Geometry and drag of a three-link swimmer, validated on construction.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Swimmer<T> {
    lengths: [T; 3],
    drag: T,
    ratio: T,
}

/// `A(α)` with its partial derivatives `∂A/∂α1`, `∂A/∂α2` (all 3×2, rows x, y, θ).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Connection<T: Real> {
    /// The local connection: `ξ = −A(α)·α̇`.
    pub a: Matrix3x2<T>,
    /// `[∂A/∂α1, ∂A/∂α2]`.
    pub da: [Matrix3x2<T>; 2],
}

impl<T: Real> Swimmer<T> {
    /// Link lengths `(L0 middle, L1 front, L2 rear)`, drag coefficient `k`, drag ratio `r`
    /// (normal over tangential drag; 2 for slender bodies). All must be finite and positive.
    pub fn new(lengths: [T; 3], drag: T, ratio: T) -> Result<Self, Error> {
        let ok = |v: T| v.is_finite() && v > T::zero();
        if lengths.iter().all(|&l| ok(l)) && ok(drag) && ok(ratio) {
            Ok(Swimmer {
                lengths,
                drag,
                ratio,
            })
        } else {
            Err(Error::InvalidParameters)
        }
    }

    /// The paper's swimmer: unit links, `k = 1`, `r = 2`.
    pub fn purcell() -> Self {
        Swimmer {
            lengths: [T::one(); 3],
            drag: T::one(),
            ratio: T::from_f64(2.0),
        }
    }

    /// Link lengths `(L0, L1, L2)`.
    pub fn lengths(&self) -> [T; 3] {
        self.lengths
    }
    /// Drag coefficient `k` (it scales forces; the kinematics do not depend on it).
    pub fn drag(&self) -> T {
        self.drag
    }
    /// Drag ratio `r` (normal over tangential).
    pub fn ratio(&self) -> T {
        self.ratio
    }

    /// The local connection `A(α)`.
    ///
    /// Errors: [`Error::NonFinite`] for a non-finite `α`, [`Error::ShapeLimit`] for
    /// `|α_i| ≥ π`, [`Error::Singular`] if `W_ξ` is degenerate.
    pub fn connection(&self, alpha: &Vector2<T>) -> Result<Matrix3x2<T>, Error> {
        Ok(Frame::new(self, alpha)?.a().0)
    }

    /// `A(α)` and `∂A/∂α1`, `∂A/∂α2`; errors as [`Swimmer::connection`].
    pub fn connection_with_derivatives(&self, alpha: &Vector2<T>) -> Result<Connection<T>, Error> {
        let f = Frame::new(self, alpha)?;
        let a = f.a();
        let da = [f.da(&a, 0), f.da(&a, 1)];
        Ok(Connection { a: a.0, da })
    }
}

/// Checks `α` against the link-overlap limit `|α_i| < π`.
pub fn check_shape<T: Real>(alpha: &Vector2<T>) -> Result<(), Error> {
    let (a1, a2) = (alpha.x, alpha.y);
    if !(a1.is_finite() && a2.is_finite()) {
        return Err(Error::NonFinite);
    }
    let pi = T::pi();
    if a1.abs() >= pi || a2.abs() >= pi {
        return Err(Error::ShapeLimit);
    }
    Ok(())
}

/// A symmetric 3×3 matrix by its upper triangle `[xx, xy, xz, yy, yz, zz]`.
type Sym3<T> = [T; 6];

/// `w += s·(a bᵀ + b aᵀ)/2`, or `s·a aᵀ` when `a = b`, on a symmetric matrix.
#[inline(always)]
fn add_sym_outer<T: Real>(w: &mut Sym3<T>, a: &[T; 3], b: &[T; 3], s: T) {
    let h = T::half() * s;
    w[0] += s * a[0] * b[0];
    w[1] += h * (a[0] * b[1] + a[1] * b[0]);
    w[2] += h * (a[0] * b[2] + a[2] * b[0]);
    w[3] += s * a[1] * b[1];
    w[4] += h * (a[1] * b[2] + a[2] * b[1]);
    w[5] += s * a[2] * b[2];
}

/// `S·M` for symmetric `S` and a 3×2 `M` given by rows.
#[inline(always)]
fn sym_mul<T: Real>(s: &Sym3<T>, m: &[[T; 2]; 3]) -> [[T; 2]; 3] {
    let row = |a: T, b: T, c: T| {
        [
            a * m[0][0] + b * m[1][0] + c * m[2][0],
            a * m[0][1] + b * m[1][1] + c * m[2][1],
        ]
    };
    [
        row(s[0], s[1], s[2]),
        row(s[1], s[3], s[4]),
        row(s[2], s[4], s[5]),
    ]
}

fn to_matrix<T: Real>(m: &[[T; 2]; 3]) -> Matrix3x2<T> {
    Matrix3x2::new(m[0][0], m[0][1], m[1][0], m[1][1], m[2][0], m[2][1])
}

/// The per-shape quantities shared by `A` and its derivatives.
struct Frame<T> {
    l: [T; 3],
    r: T,
    /// `τ, ν` of the front (index 0) and rear (index 1) link, and their `α`-derivatives.
    tau: [[T; 3]; 2],
    nu: [[T; 3]; 2],
    dtau: [[T; 3]; 2],
    dnu: [[T; 3]; 2],
    /// `W_ξ⁻¹` (symmetric) and `W_α` (by rows).
    w_inv: Sym3<T>,
    w_alpha: [[T; 2]; 3],
}

/// `A` by rows, as computed once per shape.
struct ARows<T>(Matrix3x2<T>, [[T; 2]; 3]);

impl<T: Real> Frame<T> {
    fn new(sw: &Swimmer<T>, alpha: &Vector2<T>) -> Result<Self, Error> {
        check_shape(alpha)?;
        let [l0, l1, l2] = sw.lengths;
        let r = sw.ratio;
        let half = T::half();
        let (s1, c1) = alpha.x.sin_cos();
        let (s2, c2) = alpha.y.sin_cos();
        let h0 = half * l0;
        // Front link: t = (c1, s1), n = (−s1, c1), centre (L0/2 + L1/2·c1, L1/2·s1).
        let tau1 = [c1, s1, h0 * s1];
        let nu1 = [-s1, c1, h0 * c1 + half * l1];
        let dtau1 = [-s1, c1, h0 * c1];
        let dnu1 = [-c1, -s1, -(h0 * s1)];
        // Rear link: t = (c2, s2), n = (−s2, c2), centre (−L0/2 − L2/2·c2, −L2/2·s2).
        let tau2 = [c2, s2, -(h0 * s2)];
        let nu2 = [-s2, c2, -(h0 * c2) - half * l2];
        let dtau2 = [-s2, c2, -(h0 * c2)];
        let dnu2 = [-c2, -s2, h0 * s2];

        let twelfth = T::from_f64(1.0 / 12.0);
        let z = T::zero();
        // Middle link: τ = e1, ν = e2.
        let mut w: Sym3<T> = [
            l0,
            z,
            z,
            r * l0,
            z,
            r * twelfth * (l0 * l0 * l0 + l1 * l1 * l1 + l2 * l2 * l2),
        ];
        add_sym_outer(&mut w, &tau1, &tau1, l1);
        add_sym_outer(&mut w, &nu1, &nu1, r * l1);
        add_sym_outer(&mut w, &tau2, &tau2, l2);
        add_sym_outer(&mut w, &nu2, &nu2, r * l2);

        // Inverse by cofactors: one division.
        let [xx, xy, xz, yy, yz, zz] = w;
        let cof = [
            yy * zz - yz * yz,
            xz * yz - xy * zz,
            xy * yz - xz * yy,
            xx * zz - xz * xz,
            xy * xz - xx * yz,
            xx * yy - xy * xy,
        ];
        let det = xx * cof[0] + xy * cof[1] + xz * cof[2];
        // W_ξ is positive definite for positive parameters; refuse anything else.
        let scale = xx * yy * zz;
        if !(det.is_finite() && det > T::from_f64(1e-12) * scale) {
            return Err(Error::Singular);
        }
        let inv_det = T::one() / det;
        let w_inv = cof.map(|v| v * inv_det);

        let a1 = r * l1 * l1;
        let a2 = r * l2 * l2;
        let w_alpha = [
            [a1 * half * nu1[0], -(a2 * half * nu2[0])],
            [a1 * half * nu1[1], -(a2 * half * nu2[1])],
            [
                a1 * (half * nu1[2] + twelfth * l1),
                a2 * (twelfth * l2 - half * nu2[2]),
            ],
        ];
        Ok(Frame {
            l: [l0, l1, l2],
            r,
            tau: [tau1, tau2],
            nu: [nu1, nu2],
            dtau: [dtau1, dtau2],
            dnu: [dnu1, dnu2],
            w_inv,
            w_alpha,
        })
    }

    fn a(&self) -> ARows<T> {
        let rows = sym_mul(&self.w_inv, &self.w_alpha);
        ARows(to_matrix(&rows), rows)
    }

    /// `∂A/∂α_i = W_ξ⁻¹ (∂W_α/∂α_i − ∂W_ξ/∂α_i · A)`, `i` = 0 (front) or 1 (rear).
    fn da(&self, a: &ARows<T>, i: usize) -> Matrix3x2<T> {
        let (tau, nu, dtau, dnu) = match i {
            0 => (&self.tau[0], &self.nu[0], &self.dtau[0], &self.dnu[0]),
            _ => (&self.tau[1], &self.nu[1], &self.dtau[1], &self.dnu[1]),
        };
        let l = if i == 0 { self.l[1] } else { self.l[2] };
        let two = T::from_f64(2.0);
        let mut dw: Sym3<T> = [T::zero(); 6];
        add_sym_outer(&mut dw, dtau, tau, two * l);
        add_sym_outer(&mut dw, dnu, nu, two * self.r * l);
        let dwa = sym_mul(&dw, &a.1);
        // ∂W_α/∂α_i has one non-zero column: ±r·l²/2·∂ν.
        let col = self.r * l * l * T::half();
        let mut e = [[T::zero(); 2]; 3];
        for ((erow, d), &dnu_r) in e.iter_mut().zip(dwa.iter()).zip(dnu.iter()) {
            if i == 0 {
                erow[0] = col * dnu_r - d[0];
                erow[1] = -d[1];
            } else {
                erow[0] = -d[0];
                erow[1] = -(col * dnu_r) - d[1];
            }
        }
        to_matrix(&sym_mul(&self.w_inv, &e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn connection_at_straight_shape_matches_model_test_vector() {
        let sw = Swimmer::<f64>::purcell();
        let c = sw
            .connection_with_derivatives(&Vector2::new(0.0, 0.0))
            .unwrap();
        let a = Matrix3x2::new(0.0, 0.0, 1.0 / 6.0, -1.0 / 6.0, 7.0 / 27.0, 7.0 / 27.0);
        assert_relative_eq!(c.a, a, epsilon = 1e-14);
        let d1 = Matrix3x2::new(-4.0 / 27.0, 2.0 / 27.0, 0.0, 0.0, 0.0, 0.0);
        let d2 = Matrix3x2::new(-2.0 / 27.0, 4.0 / 27.0, 0.0, 0.0, 0.0, 0.0);
        assert_relative_eq!(c.da[0], d1, epsilon = 1e-14);
        assert_relative_eq!(c.da[1], d2, epsilon = 1e-14);
    }
}
