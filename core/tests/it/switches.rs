//! The small-angle switches of SE(2) (`SMALL_ANGLE`, `C3_SERIES_LIMIT`) in f32 and f64, on
//! both sides and for negative angles: the test kit's switch suite
//! ([`purcell_core::testkit::switch_suite`]) run over each type with its strategy
//! [`purcell_core::testkit::strategies::angle_across_switches`].
//!
//! Bounds, in units of the type's epsilon, are 10× the worst measured over 300 000 cases of
//! these strategies (both types alike unless noted): the coefficients `a, b, c₂, sin, cos`
//! 2.0 (bound 20); `c₃` 26.2 in f32, 22.1 in f64 at `|ω|` just above 0.5, where its closed
//! form `(ω − sin ω)/ω³` loses digits by design (bound 270); `exp` 2.1 (bound 25);
//! `dexp_Xᵀm` and its derivative 15.7 in f32 (at `ω = 0.01`), 5.6 in f64 (bounds 160, 60).

use crate::common;

use common::*;
use proptest::prelude::*;
use purcell_core::testkit::switch_suite::{
    coefficients, dexp_transpose, exp, momentum, twist_across_switches, within,
};

const COEFFICIENTS: [f64; 6] = [20.0, 20.0, 20.0, 270.0, 20.0, 20.0];
const EXP: f64 = 25.0;

proptest! {
    #![proptest_config(proptest_config())]

    #[test]
    fn coefficients_match_their_series_across_the_switches(w in angle_across_switches()) {
        within(coefficients::<f32>(w), COEFFICIENTS)?;
        within(coefficients::<f64>(w), COEFFICIENTS)?;
    }

    #[test]
    fn exp_matches_its_series_across_the_switches(x in twist_across_switches()) {
        prop_assert!(exp::<f32>(x) <= EXP);
        prop_assert!(exp::<f64>(x) <= EXP);
    }

    #[test]
    fn dexp_transpose_and_its_derivative_match_across_the_switches(x in twist_across_switches(), m in momentum()) {
        let (e32, e64) = (dexp_transpose::<f32>(x, m), dexp_transpose::<f64>(x, m));
        prop_assert!(e32 <= 160.0, "{e32}");
        prop_assert!(e64 <= 60.0, "{e64}");
    }
}
