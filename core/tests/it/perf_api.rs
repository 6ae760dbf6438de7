//! The `Real` methods added for the MCU step's speed: `all_finite` (one multiply-add per value
//! and one comparison in `f32`/`f64`) and `abs` (the sign bit in `f32`/`f64`) must answer
//! exactly what the plain definitions answer.

use proptest::prelude::*;
use purcell_core::Real;

/// The definition `all_finite` must agree with.
fn plain_all_finite<T: Real, const N: usize>(xs: [T; N]) -> bool {
    xs.iter().all(|x| x.is_finite())
}

fn specials_f64() -> [f64; 12] {
    [
        0.0,
        -0.0,
        1.0,
        -2.5,
        f64::MAX,
        f64::MIN,
        f64::MIN_POSITIVE,
        5e-324,
        -5e-324,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ]
}

fn specials_f32() -> [f32; 12] {
    [
        0.0,
        -0.0,
        1.0,
        -2.5,
        f32::MAX,
        f32::MIN,
        f32::MIN_POSITIVE,
        1e-45,
        -1e-45,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
    ]
}

/// `Real::all_finite` answers [`plain_all_finite`] on every single, pair and triple of `xs`.
fn assert_all_finite_is_the_definition<T: Real>(xs: &[T]) {
    for &a in xs {
        assert_eq!(T::all_finite([a]), a.is_finite(), "{a:?}");
        for &b in xs {
            assert_eq!(T::all_finite([a, b]), plain_all_finite([a, b]));
            for &c in xs {
                assert_eq!(T::all_finite([a, b, c]), plain_all_finite([a, b, c]));
            }
        }
    }
}

#[test]
fn all_finite_matches_the_definition_on_every_pair_and_triple_of_specials() {
    assert_all_finite_is_the_definition(&specials_f64());
    assert_all_finite_is_the_definition(&specials_f32());
    // Nothing to check is vacuously finite; a NaN anywhere in a long list is found.
    assert!(f32::all_finite::<0>([]));
    let mut ten = [1.0f32; 10];
    assert!(f32::all_finite(ten));
    ten[9] = f32::NAN;
    assert!(!f32::all_finite(ten));
    ten[9] = f32::MAX;
    ten[0] = f32::NEG_INFINITY;
    assert!(!f32::all_finite(ten));
}

#[test]
fn abs_is_the_magnitude() {
    assert_abs_is_the_magnitude(specials_f64());
    assert_abs_is_the_magnitude(specials_f32());
}

/// `Real::abs(x)` is `x` or `−x`, whichever is not negative, and NaN for NaN.
fn assert_abs_is_the_magnitude<T: Real>(xs: impl IntoIterator<Item = T>) {
    for x in xs {
        let a = x.abs();
        #[allow(clippy::eq_op)] // x ≠ x: NaN
        if x != x {
            assert!(a != a, "{x:?}");
        } else {
            assert_eq!(a, if x < T::zero() { -x } else { x });
            assert!(a >= T::zero());
        }
    }
}

/// Any bit pattern: normal, subnormal, zero, infinite or NaN.
fn any_f32() -> impl Strategy<Value = f32> {
    any::<u32>().prop_map(f32::from_bits)
}

fn any_f64() -> impl Strategy<Value = f64> {
    any::<u64>().prop_map(f64::from_bits)
}

proptest! {
    #[test]
    fn all_finite_matches_the_definition_on_any_bits_f32(xs in prop::array::uniform10(any_f32())) {
        prop_assert_eq!(f32::all_finite(xs), plain_all_finite(xs));
    }

    #[test]
    fn all_finite_matches_the_definition_on_any_bits_f64(xs in prop::array::uniform6(any_f64())) {
        prop_assert_eq!(f64::all_finite(xs), plain_all_finite(xs));
    }
}
