//! Forward-mode dual numbers with `N` tangent components.
//!
//! A [`Dual`] is `v + Σᵢ dᵢ εᵢ` with `εᵢ εⱼ = 0`: evaluating any smooth `f` on duals seeded
//! with `dᵢ = ∂xⱼ/∂zᵢ` gives `f(x)` and its exact directional derivatives `∂f/∂zᵢ`, to
//! rounding, with no step size. The solver uses `N = 2` for the second derivatives of the
//! connection ([`crate::solver::stage`]) and `N = 7` for its independent KKT check
//! ([`crate::solver::certificate`]).
//!
//! It implements [`purcell_core::Real`], so the core's generic control law runs on it
//! unchanged: comparisons and [`Real::to_bits`] look at the value only (the core's branches
//! then follow the value path, exactly as in `f64`), and [`Real::is_finite`] checks every part.

use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};
use num_traits::{One, Zero};
use purcell_core::Real;

/// A dual number: value and `N` derivatives.
#[derive(Clone, Copy, Debug)]
pub struct Dual<const N: usize> {
    /// The value.
    pub v: f64,
    /// The derivatives with respect to the seeded unknowns.
    pub d: [f64; N],
}

impl<const N: usize> Dual<N> {
    /// A constant (zero derivatives).
    #[inline(always)]
    pub const fn constant(v: f64) -> Self {
        Dual { v, d: [0.0; N] }
    }

    /// The `i`-th unknown with value `v`: derivative 1 in component `i`, 0 elsewhere.
    /// An `i` out of range gives a constant.
    pub fn variable(v: f64, i: usize) -> Self {
        let mut d = [0.0; N];
        if let Some(slot) = d.get_mut(i) {
            *slot = 1.0;
        }
        Self { v, d }
    }

    /// `f(self)` given `f(v)` and `f′(v)` (the chain rule).
    #[inline(always)]
    fn chain(self, value: f64, slope: f64) -> Self {
        Self {
            v: value,
            d: self.d.map(|x| slope * x),
        }
    }
}

/// Equality of values only, consistent with the ordering.
impl<const N: usize> PartialEq for Dual<N> {
    fn eq(&self, other: &Self) -> bool {
        self.v == other.v
    }
}

/// Ordering of values only: the core's branches on a dual follow the value path.
impl<const N: usize> PartialOrd for Dual<N> {
    fn partial_cmp(&self, other: &Self) -> Option<core::cmp::Ordering> {
        self.v.partial_cmp(&other.v)
    }
}

#[inline(always)]
fn zip<const N: usize>(a: [f64; N], b: [f64; N], f: impl Fn(f64, f64) -> f64) -> [f64; N] {
    let mut out = [0.0; N];
    for ((o, x), y) in out.iter_mut().zip(a).zip(b) {
        *o = f(x, y);
    }
    out
}

impl<const N: usize> Add for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self {
            v: self.v + o.v,
            d: zip(self.d, o.d, |x, y| x + y),
        }
    }
}

impl<const N: usize> Sub for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self {
            v: self.v - o.v,
            d: zip(self.d, o.d, |x, y| x - y),
        }
    }
}

/// `(a + a′ε)(b + b′ε) = ab + (a′b + ab′)ε`.
impl<const N: usize> Mul for Dual<N> {
    type Output = Self;
    #[inline(always)]
    #[allow(clippy::suspicious_arithmetic_impl)] // the product rule
    fn mul(self, o: Self) -> Self {
        let (a, b) = (self.v, o.v);
        Self {
            v: a * b,
            d: zip(self.d, o.d, |x, y| x * b + a * y),
        }
    }
}

/// `(a + a′ε)/(b + b′ε) = a/b + (a′ − (a/b)·b′)/b · ε`.
impl<const N: usize> Div for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        let inv = 1.0 / o.v;
        let q = self.v * inv;
        Self {
            v: q,
            d: zip(self.d, o.d, |x, y| (x - q * y) * inv),
        }
    }
}

impl<const N: usize> Neg for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self {
            v: -self.v,
            d: self.d.map(|x| -x),
        }
    }
}

macro_rules! assign_op {
    ($tr:ident, $m:ident, $op:tt) => {
        impl<const N: usize> $tr for Dual<N> {
            #[inline(always)]
            fn $m(&mut self, o: Self) {
                *self = *self $op o;
            }
        }
    };
}
assign_op!(AddAssign, add_assign, +);
assign_op!(SubAssign, sub_assign, -);
assign_op!(MulAssign, mul_assign, *);
assign_op!(DivAssign, div_assign, /);

impl<const N: usize> Zero for Dual<N> {
    fn zero() -> Self {
        Self::constant(0.0)
    }
    fn is_zero(&self) -> bool {
        self.v == 0.0 && self.d.iter().all(|&x| x == 0.0)
    }
}

impl<const N: usize> One for Dual<N> {
    fn one() -> Self {
        Self::constant(1.0)
    }
}

impl<const N: usize> Real for Dual<N> {
    /// Same as `f64`: the derivative of the truncated fixed point is what we differentiate.
    const PASSES: purcell_core::Passes = <f64 as Real>::PASSES;

    #[inline(always)]
    fn from_f64(x: f64) -> Self {
        Self::constant(x)
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self.v
    }
    /// `d sin = cos·d`, `d cos = −sin·d`.
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = libm::sincos(self.v);
        (self.chain(s, c), self.chain(c, -s))
    }
    /// `d atan2(y, x) = (x·dy − y·dx)/(x² + y²)`.
    #[inline(always)]
    fn atan2(self, x: Self) -> Self {
        let y = self;
        let r2 = 1.0 / (x.v * x.v + y.v * y.v);
        Self {
            v: libm::atan2(y.v, x.v),
            d: zip(y.d, x.d, |dy, dx| (x.v * dy - y.v * dx) * r2),
        }
    }
    /// `d √x = d/(2√x)`.
    #[inline(always)]
    fn sqrt(self) -> Self {
        let s = libm::sqrt(self.v);
        self.chain(s, 0.5 / s)
    }
    fn is_finite(self) -> bool {
        self.v.is_finite() && self.d.iter().all(|x| x.is_finite())
    }
    fn to_bits(self) -> u64 {
        self.v.to_bits()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f<T: Real>(x: T, y: T) -> T {
        let (s, c) = (x * y).sin_cos();
        (s * s + c).sqrt() / (T::one() + x * x) + y.atan2(x) - x
    }

    #[test]
    fn derivatives_match_central_differences() {
        let (x0, y0) = (0.7, -1.3);
        let v = f(Dual::<5>::variable(x0, 0), Dual::variable(y0, 1));
        let e = 1e-6;
        let dx = (f(x0 + e, y0) - f(x0 - e, y0)) / (2.0 * e);
        let dy = (f(x0, y0 + e) - f(x0, y0 - e)) / (2.0 * e);
        assert!((v.v - f(x0, y0)).abs() < 1e-15);
        assert!((v.d[0] - dx).abs() < 1e-8, "{} vs {dx}", v.d[0]);
        assert!((v.d[1] - dy).abs() < 1e-8, "{} vs {dy}", v.d[1]);
        assert_eq!(&v.d[2..], &[0.0; 3]);
    }

    #[test]
    fn comparisons_and_bits_use_the_value_only() {
        let a = Dual::<5>::variable(1.0, 0);
        let b = Dual::<5>::constant(1.0);
        assert!(a == b && a <= b && a >= b);
        assert_eq!(a.to_bits(), 1.0f64.to_bits());
        let mut c = a;
        c.d[3] = f64::NAN;
        assert!(!c.is_finite() && c.v.is_finite());
    }
}
