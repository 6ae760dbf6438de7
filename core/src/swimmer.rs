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
    /// With parameters of wildly different scales (say a link of `10⁻²⁷⁴` beside one of
    /// `1`), `W_ξ` can be numerically degenerate although positive definite; a result that
    /// is not finite is then [`Error::Singular`], never an `Ok` holding NaN.
    pub fn connection(&self, alpha: &Vector2<T>) -> Result<Matrix3x2<T>, Error> {
        check_shape(alpha)?;
        let a = Frame::new(self, alpha)?.a().0;
        finite_or_singular(&a)?;
        Ok(a)
    }

    /// `A(α)` and `∂A/∂α1`, `∂A/∂α2`; errors as [`Swimmer::connection`].
    pub fn connection_with_derivatives(&self, alpha: &Vector2<T>) -> Result<Connection<T>, Error> {
        check_shape(alpha)?;
        let c = self.connection_unchecked(alpha)?;
        finite_or_singular(&c.a)?;
        finite_or_singular(&c.da[0])?;
        finite_or_singular(&c.da[1])?;
        Ok(c)
    }

    /// [`Swimmer::connection_with_derivatives`] for a shape already checked by [`check_shape`].
    #[inline(always)]
    pub(crate) fn connection_unchecked(&self, alpha: &Vector2<T>) -> Result<Connection<T>, Error> {
        let f = Frame::new(self, alpha)?;
        let a = f.a();
        let da = f.da(&a);
        Ok(Connection { a: a.0, da })
    }
}

/// `Err(Singular)` unless every entry is finite.
#[inline(always)]
fn finite_or_singular<T: Real>(m: &Matrix3x2<T>) -> Result<(), Error> {
    if T::all_finite([m.m11, m.m12, m.m21, m.m22, m.m31, m.m32]) {
        Ok(())
    } else {
        Err(Error::Singular)
    }
}

/// Checks `α` against the link-overlap limit `|α_i| < π`.
pub fn check_shape<T: Real>(alpha: &Vector2<T>) -> Result<(), Error> {
    let (a1, a2) = (alpha.x, alpha.y);
    if !T::all_finite([a1, a2]) {
        return Err(Error::NonFinite);
    }
    within_limit(a1, a2)
}

/// `Ok` unless `|α1| ≥ π` or `|α2| ≥ π` (for finite angles).
#[inline(always)]
pub(crate) fn within_limit<T: Real>(a1: T, a2: T) -> Result<(), Error> {
    let pi = T::pi();
    if a1.abs() < pi && a2.abs() < pi {
        Ok(())
    } else {
        Err(Error::ShapeLimit)
    }
}

/// A symmetric 3×3 matrix by its upper triangle `[xx, xy, xz, yy, yz, zz]`.
type Sym3<T> = [T; 6];

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

/// One outer link (front or rear) at its current angle.
///
/// `τ = (cos α, sin α, τ_z)`, `ν = (−sin α, cos α, ν_z)`. Both links satisfy
/// `∂τ/∂α = ν + σ·(l/2)·e₃` and `∂ν/∂α = −τ`, with `σ = −1` (front) or `+1` (rear), so
///
/// ```text
/// ∂W_ξ/∂α = l·(1 − r)·(ν τᵀ + τ νᵀ) + σ·l²/2·(e₃τᵀ + τ e₃ᵀ),    ∂W_α/∂α (own column) = σ·r·l²/2·τ
/// ```
struct Link<T> {
    l: T,
    sigma: T,
    tau: [T; 3],
    nu: [T; 3],
}

impl<T: Real> Link<T> {
    /// `w += l·(τ τᵀ + r·ν νᵀ)`, using `cos² + sin² = 1`.
    #[inline(always)]
    fn add_drag(&self, w: &mut Sym3<T>, r: T) {
        let [c, s, tz] = self.tau;
        let nz = self.nu[2];
        let l = self.l;
        let rl = r * l;
        let kl = rl - l; // (r − 1)·l
        let (ss, cc, cs) = (s * s, c * c, c * s);
        w[0] += l + kl * ss;
        w[1] -= kl * cs;
        w[2] += l * c * tz - rl * s * nz;
        w[3] += l + kl * cc;
        w[4] += l * s * tz + rl * c * nz;
        w[5] += l * tz * tz + rl * nz * nz;
    }

    /// `E = ∂W_α/∂α − ∂W_ξ/∂α · A` for this link's angle, by rows; `own` selects this
    /// link's column of `W_α` (0 front, 1 rear).
    #[inline(always)]
    fn de(&self, a: &[[T; 2]; 3], r: T, own: Own) -> [[T; 2]; 3] {
        let [t0, t1, t2] = self.tau;
        let [n0, n1, n2] = self.nu;
        let [a0, a1, a2] = a;
        // τᵀA and νᵀA (1×2 each).
        let ta = [
            t0 * a0[0] + t1 * a1[0] + t2 * a2[0],
            t0 * a0[1] + t1 * a1[1] + t2 * a2[1],
        ];
        let na = [
            n0 * a0[0] + n1 * a1[0] + n2 * a2[0],
            n0 * a0[1] + n1 * a1[1] + n2 * a2[1],
        ];
        let l = self.l;
        let kl = l - r * l; // (1 − r)·l
        let hl2 = self.sigma * T::half() * l * l; // σ·l²/2
        // E = −(ν⊗p + τ⊗q + e₃⊗s), with ∂W_α/∂α folded into q.
        let p = [kl * ta[0], kl * ta[1]];
        let mut q = [kl * na[0] + hl2 * a2[0], kl * na[1] + hl2 * a2[1]];
        match own {
            Own::Front => q[0] -= r * hl2,
            Own::Rear => q[1] -= r * hl2,
        }
        let s = [hl2 * ta[0], hl2 * ta[1]];
        let row = |n: T, t: T| [-(n * p[0] + t * q[0]), -(n * p[1] + t * q[1])];
        let [e0, e1, mut e2] = [row(n0, t0), row(n1, t1), row(n2, t2)];
        e2[0] -= s[0];
        e2[1] -= s[1];
        [e0, e1, e2]
    }
}

/// Which column of `W_α` belongs to a link.
#[derive(Clone, Copy)]
enum Own {
    Front,
    Rear,
}

/// The per-shape quantities shared by `A` and its derivatives.
struct Frame<T> {
    r: T,
    links: [Link<T>; 2],
    /// `W_ξ⁻¹` (symmetric) and `W_α` (by rows).
    w_inv: Sym3<T>,
    w_alpha: [[T; 2]; 3],
}

/// `A` as a matrix and by rows.
struct ARows<T>(Matrix3x2<T>, [[T; 2]; 3]);

impl<T: Real> Frame<T> {
    /// Assumes `α` was checked by [`check_shape`].
    #[inline(always)]
    fn new(sw: &Swimmer<T>, alpha: &Vector2<T>) -> Result<Self, Error> {
        let [l0, l1, l2] = sw.lengths;
        let r = sw.ratio;
        let half = T::half();
        let (s1, c1) = alpha.x.sin_cos();
        let (s2, c2) = alpha.y.sin_cos();
        let h0 = half * l0;
        // Front link: centre (L0/2 + L1/2·c1, L1/2·s1); rear: (−L0/2 − L2/2·c2, −L2/2·s2).
        let front = Link {
            l: l1,
            sigma: -T::one(),
            tau: [c1, s1, h0 * s1],
            nu: [-s1, c1, h0 * c1 + half * l1],
        };
        let rear = Link {
            l: l2,
            sigma: T::one(),
            tau: [c2, s2, -(h0 * s2)],
            nu: [-s2, c2, -(h0 * c2) - half * l2],
        };

        let twelfth = T::from_f64(1.0 / 12.0);
        let z = T::zero();
        // Middle link: τ = e1, ν = e2; every link's own rotation adds r·l³/12 to W_zz.
        let mut w: Sym3<T> = [
            l0,
            z,
            z,
            r * l0,
            z,
            r * twelfth * (l0 * l0 * l0 + l1 * l1 * l1 + l2 * l2 * l2),
        ];
        front.add_drag(&mut w, r);
        rear.add_drag(&mut w, r);

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
        if !(det.is_finite() && det > T::from_f64(1e-12) * (xx * yy * zz)) {
            return Err(Error::Singular);
        }
        let inv_det = T::one() / det;
        let w_inv = cof.map(|v| v * inv_det);

        let (a1, a2) = (r * l1 * l1, r * l2 * l2);
        let (n1, n2) = (&front.nu, &rear.nu);
        let w_alpha = [
            [a1 * half * n1[0], -(a2 * half * n2[0])],
            [a1 * half * n1[1], -(a2 * half * n2[1])],
            [
                a1 * (half * n1[2] + twelfth * l1),
                a2 * (twelfth * l2 - half * n2[2]),
            ],
        ];
        Ok(Frame {
            r,
            links: [front, rear],
            w_inv,
            w_alpha,
        })
    }

    #[inline(always)]
    fn a(&self) -> ARows<T> {
        let rows = sym_mul(&self.w_inv, &self.w_alpha);
        ARows(to_matrix(&rows), rows)
    }

    /// `∂A/∂α_i = W_ξ⁻¹ (∂W_α/∂α_i − ∂W_ξ/∂α_i · A)`.
    #[inline(always)]
    fn da(&self, a: &ARows<T>) -> [Matrix3x2<T>; 2] {
        let [front, rear] = &self.links;
        [
            to_matrix(&sym_mul(&self.w_inv, &front.de(&a.1, self.r, Own::Front))),
            to_matrix(&sym_mul(&self.w_inv, &rear.de(&a.1, self.r, Own::Rear))),
        ]
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

    #[test]
    fn connection_at_bent_shapes_matches_model_test_vectors() {
        let sw = Swimmer::<f64>::purcell();
        let c = sw
            .connection_with_derivatives(&Vector2::new(0.5, -0.3))
            .unwrap();
        #[rustfmt::skip]
        let (a, d1, d2) = (
            Matrix3x2::new(-0.0524221297521321, -0.00701686926608808,
                0.159747833925603, -0.161423254304907, 0.251599627307099, 0.261512677482497),
            Matrix3x2::new(-0.152107617787388, 0.0760042030565476,
                -0.0305217670699354, 0.0194176398898804, -0.0372440829755903, 0.0271626047148062),
            Matrix3x2::new(-0.0753891916765094, 0.14775179529546,
                7.14311629219022e-05, -0.00608113087579642, -0.00723135028726835, 0.02713380574958),
        );
        assert_relative_eq!(c.a, a, epsilon = 1e-13);
        assert_relative_eq!(c.da[0], d1, epsilon = 1e-13);
        assert_relative_eq!(c.da[1], d2, epsilon = 1e-13);
        #[rustfmt::skip]
        let a = Matrix3x2::new(-0.117128022444034, -0.0477262695677959,
            -0.139451363319512, 0.17511652971135, 0.340289571904178, 0.248062865707986);
        assert_relative_eq!(
            sw.connection(&Vector2::new(2.5, -2.9)).unwrap(),
            a,
            epsilon = 1e-13
        );
    }
}
