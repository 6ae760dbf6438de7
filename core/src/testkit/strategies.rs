//! [`proptest`](https://docs.rs/proptest) strategies for the core's types, for property tests
//! here and downstream (as nalgebra exports its own behind a feature).
//!
//! In the manif discipline: the identity and tiny perturbations of it as often as random
//! elements, angles near `±π`, and angles on both sides of every small-angle switch of
//! [`crate::se2`].

use crate::se2::{C3_SERIES_LIMIT, SMALL_ANGLE};
use crate::{Se2, Tangent};
use nalgebra::Vector2;
use proptest::prelude::*;

/// A twist `(vx, vy, ω)`: the zero twist, a tiny one (components ≤ 1e-8), or a random one
/// with `|ω| < π` (so that `log(exp(X)) = X`).
pub fn tangent() -> impl Strategy<Value = Tangent<f64>> {
    prop_oneof![
        1 => Just(Tangent::zeros()),
        2 => (-1e-8..1e-8f64, -1e-8..1e-8f64, -1e-8..1e-8f64)
            .prop_map(|(a, b, c)| Tangent::new(a, b, c)),
        2 => (-1.0..1.0f64, -1.0..1.0f64, -1e-4..1e-4f64)
            .prop_map(|(a, b, c)| Tangent::new(a, b, c)),
        6 => (-5.0..5.0f64, -5.0..5.0f64, -3.1..3.1f64)
            .prop_map(|(a, b, c)| Tangent::new(a, b, c)),
    ]
}

/// A twist with `|ω|` within `1e-9 … 1e-3` of `π`, either sign.
pub fn tangent_near_pi() -> impl Strategy<Value = Tangent<f64>> {
    (-5.0..5.0f64, -5.0..5.0f64, -9.0..-3.0f64, any::<bool>()).prop_map(|(a, b, e, neg)| {
        let w = core::f64::consts::PI - 10f64.powf(e);
        Tangent::new(a, b, if neg { -w } else { w })
    })
}

/// A group element: identity, a tiny perturbation of it, or random (any angle, including ±π).
pub fn se2() -> impl Strategy<Value = Se2<f64>> {
    prop_oneof![
        1 => Just(Se2::identity()),
        2 => (-1e-8..1e-8f64, -1e-8..1e-8f64, -1e-8..1e-8f64)
            .prop_map(|(a, b, c)| Se2::new(a, b, c)),
        1 => (-5.0..5.0f64, -5.0..5.0f64, any::<bool>()).prop_map(|(a, b, neg)| {
            Se2::new(a, b, if neg { -core::f64::consts::PI } else { core::f64::consts::PI })
        }),
        6 => (-5.0..5.0f64, -5.0..5.0f64, -4.0..4.0f64).prop_map(|(a, b, c)| Se2::new(a, b, c)),
    ]
}

/// An admissible shape, `|α_i| ≤ 3` (the overlap limit is π).
pub fn alpha() -> impl Strategy<Value = Vector2<f64>> {
    (-3.0..3.0f64, -3.0..3.0f64).prop_map(|(a, b)| Vector2::new(a, b))
}

/// An angle `ω` of either sign on either side of a small-angle switch ([`SMALL_ANGLE`],
/// [`C3_SERIES_LIMIT`]), from the switch itself to 10 % off it (relative offsets
/// `10^−15 … 10^−1`), or anywhere in `1e-9 ≤ |ω| ≤ 1` (log-uniform).
pub fn angle_across_switches() -> impl Strategy<Value = f64> {
    let near = (
        prop::sample::select(&[SMALL_ANGLE, C3_SERIES_LIMIT][..]),
        -15.0..-1.0f64,
        any::<bool>(),
        any::<bool>(),
    )
        .prop_map(|(switch, e, above, neg)| {
            let w = switch * (1.0 + if above { 1.0 } else { -1.0 } * 10f64.powf(e));
            if neg { -w } else { w }
        });
    let anywhere = (-9.0..0.0f64, any::<bool>()).prop_map(|(e, neg)| {
        let w = 10f64.powf(e);
        if neg { -w } else { w }
    });
    prop_oneof![
        3 => near,
        1 => Just(SMALL_ANGLE),
        1 => Just(-SMALL_ANGLE),
        1 => Just(C3_SERIES_LIMIT),
        1 => Just(-C3_SERIES_LIMIT),
        3 => anywhere,
    ]
}

/// proptest's default 256 cases (`PROPTEST_CASES` overrides), and no regression files written
/// into the source tree (a failure prints its minimal input; add it as an explicit test case
/// instead).
pub fn proptest_config() -> ProptestConfig {
    ProptestConfig {
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}
