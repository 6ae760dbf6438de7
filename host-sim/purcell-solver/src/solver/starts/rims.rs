//! Rim loops: start loops that ride a joint limit's square (see [`super`]'s docs).

use super::{Shape, StartLoop};
use crate::solver::grid::Grid;
use crate::solver::settings::{RIM_TURNS, SHRINK};
use nalgebra::Vector2;

impl StartLoop {
    /// A rim loop's `α(τ) − ᾱ` (see [`rims`]): the stalk from `ᾱ` to the square's point in
    /// the direction `ψ` from `centre`, `n` turns around the square (direction of travel the
    /// sign of `ρ`), and back, at constant speed along the stalk and in angle on the square.
    pub(super) fn rim_offset(&self, centre: Vector2<f64>, tau: f64, two_pi_n: f64) -> Vector2<f64> {
        // The rounded square |x|⁴ + |y|⁴ = s⁴ at polar angle φ.
        let square = |phi: f64| {
            let (s, c) = phi.sin_cos();
            let r = (c.powi(4) + s.powi(4)).powf(0.25);
            Vector2::new(c, s) * (self.size / r)
        };
        let entry = centre + square(self.psi);
        let stalk = entry.norm();
        // The square's perimeter is about 1.1 times its inscribed circle's.
        let f = stalk / (2.0 * stalk + 1.1 * two_pi_n * self.size);
        if tau <= f {
            entry * (tau / f)
        } else if tau >= 1.0 - f {
            entry * ((1.0 - tau) / f)
        } else {
            let turned = self.aspect.signum() * two_pi_n * (tau - f) / (1.0 - 2.0 * f);
            centre + square(self.psi + turned)
        }
    }

    /// Whether it is a rim loop ([`rims`]): within the limit as it is built.
    pub fn is_rim(&self) -> bool {
        matches!(self.shape, Shape::Rim { .. })
    }
}

/// The rim loops of a loop problem under the joint limit `alpha_max` (see [`super`]'s docs):
/// rounded squares `|x|⁴ + |y|⁴ = s⁴` about the middle of the admissible shapes (`α = 0`),
/// `s = ` [`SHRINK`]` · α_max`, entered from `ᾱ` in the 8 directions `ψ = kπ/4` from the
/// centre, each way round, `n = 1 …` [`RIM_TURNS`] turns; by `n`, then `ψ`, then the way.
pub fn rims(grid: &Grid, alpha_max: f64) -> Vec<StartLoop> {
    (1..=RIM_TURNS)
        .flat_map(|turns| (0..8).flat_map(move |k| [1.0, -1.0].map(|way| (turns, k, way))))
        .map(|(turns, k, way)| rim(grid, alpha_max, turns, k, way))
        .collect()
}

/// The rim loop of `turns` turns entered in the direction `ψ = kπ/4`, the way round `way`.
fn rim(grid: &Grid, alpha_max: f64, turns: u32, k: u32, way: f64) -> StartLoop {
    StartLoop {
        shape: Shape::Rim {
            centre: [-grid.start[0], -grid.start[1]],
        },
        size: SHRINK * alpha_max,
        aspect: way,
        psi: 0.25 * core::f64::consts::PI * f64::from(k),
        phase: 0.0,
        turns,
    }
}

#[cfg(test)]
mod tests {
    use super::super::of_grid;
    use super::super::tests::closed_reach;
    use super::*;
    use crate::problem::Problem;
    use crate::solver::stage::Rule;

    /// Rim loops: closed, through `ᾱ` (bent too), within the limit and riding it, every
    /// turning number up to [`RIM_TURNS`] in 16 directions and ways; first in a limited loop
    /// problem's order, absent from a free one's.
    #[test]
    fn rim_loops_ride_the_limit_from_alpha0() {
        for (alpha0, alpha_max) in [([0.0, 0.0], 0.9), ([0.4, -0.4], 1.6)] {
            let p = Problem::new(&crate::problem::Spec {
                alpha0,
                alpha_max: Some(alpha_max),
                ..Default::default()
            })
            .unwrap();
            let grid = Grid::new(&p, 256, Rule::LEFT_POINT).unwrap();
            let loops = rims(&grid, alpha_max);
            assert_eq!(loops.len(), 16 * RIM_TURNS as usize);
            assert!((1..=RIM_TURNS).all(|n| loops.iter().any(|s| s.turns == n)));
            let start = Vector2::from(alpha0);
            let bound = SHRINK * alpha_max;
            for s in &loops {
                assert!(s.is_rim() && s.offset(0.0) == Vector2::zeros(), "{s:?}");
                let reach = closed_reach(s, &grid, &start, 1024);
                assert!(reach <= bound * (1.0 + 1e-12), "{s:?}: {reach}");
                assert!(reach >= 0.99 * bound, "{s:?}: {reach}");
            }
            let limited = of_grid(&grid, 0.5, 3, 0, 100, Some(alpha_max));
            assert_eq!(limited[..loops.len()], loops[..]);
            assert!(
                !of_grid(&grid, 0.5, 3, 0, 100, None)
                    .iter()
                    .any(StartLoop::is_rim)
            );
        }
    }
}
