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

#[test]
fn all_finite_matches_the_definition_on_every_pair_and_triple_of_specials() {
    let (s64, s32) = (specials_f64(), specials_f32());
    for &a in &s64 {
        assert_eq!(f64::all_finite([a]), a.is_finite(), "{a}");
        for &b in &s64 {
            assert_eq!(f64::all_finite([a, b]), plain_all_finite([a, b]));
            for &c in &s64 {
                assert_eq!(f64::all_finite([a, b, c]), plain_all_finite([a, b, c]));
            }
        }
    }
    for &a in &s32 {
        assert_eq!(f32::all_finite([a]), a.is_finite(), "{a}");
        for &b in &s32 {
            assert_eq!(f32::all_finite([a, b]), plain_all_finite([a, b]));
            for &c in &s32 {
                assert_eq!(f32::all_finite([a, b, c]), plain_all_finite([a, b, c]));
            }
        }
    }
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
    for x in specials_f64() {
        let a = <f64 as Real>::abs(x);
        if x.is_nan() {
            assert!(a.is_nan());
        } else {
            assert_eq!(a, if x < 0.0 { -x } else { x });
            assert!(a >= 0.0);
        }
    }
    for x in specials_f32() {
        let a = <f32 as Real>::abs(x);
        if x.is_nan() {
            assert!(a.is_nan());
        } else {
            assert_eq!(a, if x < 0.0 { -x } else { x });
            assert!(a >= 0.0);
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
