//! Start loops for the global search: closed shape loops through `ᾱ`, sized to the target.
//!
//! A start is a loop `α(τ) = ᾱ + E(φ₀ + 2πnτ) − E(φ₀)`, `τ = t/T`, with
//!
//! ```text
//! ellipse:       E(φ) = R(ψ)·s·(cos φ, ρ sin φ)
//! figure-eight:  E(φ) = R(ψ)·s·(sin φ, ρ/2·sin 2φ)       (φ₀ = 0)
//! ```
//!
//! and lollipops: a straight stalk of length `d` from `ᾱ` in the direction `ψ`, `n` turns
//! around a circle of radius `s` beyond its end (direction of travel the sign of `ρ`), and
//! back along the stalk, at constant speed. Cheap gaits for far targets often circle a region
//! of the shape plane away from `ᾱ` several times; an ellipse through `ᾱ` cannot reach it.
//!
//! turning number `n ∈ {1, 2, 3}`, orientation `ψ`, phase `φ₀` (where on the loop `ᾱ` sits),
//! aspect `ρ` (its sign is the direction of travel) and size `s`. Two families:
//!
//! - **scaled loops**: sizes from the problem's geometry. The net displacement of a small
//!   loop is about the curvature of the connection times the enclosed area, so the loop that
//!   moves the body as far as the target asks is found by a few rollouts of a circle of
//!   growing size ([`reference_size`]); ellipses, figure-eights and lollipops of half, once
//!   and twice that size.
//! - **box loops**: thin ellipses (`ρ = ±0.1, ±0.2`, `n = 1`) with `ᾱ` in the middle of a long
//!   side (`φ₀ = π/2, 3π/2`), in eight orientations, as long as the admissible shapes allow
//!   (reaching 75 %, 90 % and 100 % of `|α_i| ≤ 0.9π`). The cheapest admissible gaits for far
//!   targets are such loops: they enclose the strong regions of the curvature towards the
//!   corners of the shape plane on both sides of `ᾱ`, as far out as the links' overlap
//!   allows, and no loop sized from a circle reaches them. Not with a joint limit: there the
//!   cheapest gaits run along the limit, and box loops shrunk into it only repeat the scaled
//!   ones (at `α_max = 1.5` and `2.5` the search needed 50–75 % more starts with them, for the
//!   same answers).
//!
//! **Rim loops** (under a joint limit, for a loop problem): the cheapest gaits under a tight
//! limit ride its square `|α_i| ≤ α_max` several times (the paper's target at `α_max = 0.9`:
//! 16 arcs), and no loop through `ᾱ` shrunk into the limit has the turns or the reach. A rim
//! loop runs from `ᾱ` straight out to the rounded square `|x|⁴ + |y|⁴ = s⁴` about the middle
//! of the admissible shapes (`s` just inside the limit), `n` times around it and back
//! ([`rims`]); it is within the limit as it is built and is not shrunk. They come first in a
//! limited search's order: from the 96 rims (up to 6 turns) and 64 loops of the family, the
//! search returns on 33 limited problems the gait that 512 loops of the family returned.
//!
//! The list is ordered so that any prefix is diverse. The search runs the first loops of seed
//! 0's order for every seed, as many as its stopping rule runs at least (128 without a joint
//! limit; under a limit all of them, [`super::search`]), so that a basin seed 0 reaches
//! there every seed reaches: the seed orders only the loops after them ([`of_grid`]; links
//! 1, 0.7, 1.3 and target (0.25, 0.2, 0): the cheapest admissible gait's basin is reached by 3
//! of 800 loops, all figure-eights of three turns at `ψ = 3π/4`, one of them seed 0's 124th;
//! seeds 1, 3, 5 and 7 met the rule without reaching it and returned 1.1831852 against
//! 1.1766828). Within seed 0's order a first block is the same for every seed (it leads every
//! seed's order of [`family`]): the axis-aligned circles a direct transcription is usually started from and after
//! them, without a joint limit (the box loops' family), the one-turn lollipops with the whole
//! stalk at twice the reference size, one for each of the 8 directions `ψ` of the stalk and
//! each direction of travel, so that every seed reaches far out in each direction of the
//! shape plane (at drag ratio 3 and `ḡ = (0, 0.12, 0)` the cheapest admissible gait's basin
//! is reached by 20 of the 1 128 loops, all diagonal, two of them such lollipops; three seeds
//! of eight met the stopping rule at 128 starts without reaching it). Then three box loops to
//! one scaled loop until the box loops run out, each kind in an order mixed by a hash of the
//! seed. With a joint limit the lollipops stay in the mix (that family's order is unchanged;
//! the search without the limit that a limited solve runs first has the block).
//!
//! **Transitions** (an end shape `β ≠ ᾱ`): no closed loop is feasible, and neither is the
//! zero control. A start is then the straight shape path from `ᾱ` to `β` ([`straight`], the
//! constant control `(β − ᾱ)/T`, which takes the zero loop's place) with a loop of the family
//! ridden along it, `α(τ) = ᾱ + (β − ᾱ)τ + offset(τ)` ([`StartLoop::controls`]): the straight
//! path moves the body a little by itself, and the loops supply the rest, sized from the
//! displacement of a circle ridden the same way ([`reference_size`]). The box loops are
//! sized about the path's midpoint `(ᾱ + β)/2`, where an ellipse with `ᾱ` in the middle of
//! its long side reaches farthest ([`transitions`]); one that still passes the overlap fails
//! its rollout and is skipped like any start whose Newton run fails. A loop (`β = ᾱ`) runs
//! [`family`] and the zero loop exactly as before.

mod rims;

pub use rims::rims;

use super::grid::Grid;
use super::stage::StageState;
use crate::problem::OVERLAP;
use crate::seeded::{GOLDEN_GAMMA, splitmix64};
use nalgebra::Vector2;

/// The shape of a start loop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// An ellipse.
    Ellipse,
    /// A figure-eight (1:2 Lissajous curve).
    Eight,
    /// A stalk out of `ᾱ`, turns around a circle, and back.
    Lollipop {
        /// Length `d` of the stalk, radians.
        reach: f64,
    },
    /// A stalk out of `ᾱ` to a rounded square about `centre` (relative to `ᾱ`), turns
    /// around it, and back: a rim loop ([`rims`]).
    Rim {
        /// The square's centre, relative to `ᾱ`.
        centre: [f64; 2],
    },
}

/// One start loop (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StartLoop {
    /// Ellipse or figure-eight.
    pub shape: Shape,
    /// Size `s`, radians.
    pub size: f64,
    /// Aspect `ρ` (negative: the other direction of travel).
    pub aspect: f64,
    /// Orientation `ψ`, radians.
    pub psi: f64,
    /// Phase `φ₀`, radians.
    pub phase: f64,
    /// Turning number `n`.
    pub turns: u32,
}

impl StartLoop {
    /// `α(τ) − ᾱ` at `τ = t/T ∈ [0, 1]`.
    pub fn offset(&self, tau: f64) -> Vector2<f64> {
        let two_pi_n = 2.0 * core::f64::consts::PI * f64::from(self.turns);
        if let Shape::Rim { centre } = self.shape {
            return self.rim_offset(Vector2::from(centre), tau, two_pi_n);
        }
        let (s, c) = self.psi.sin_cos();
        let rot = |p: f64, q: f64| Vector2::new(c * p - s * q, s * p + c * q);
        let e = |phi: f64| {
            let (p, q) = match self.shape {
                // A rim loop returned above.
                Shape::Ellipse | Shape::Lollipop { .. } | Shape::Rim { .. } => {
                    (phi.cos(), self.aspect * phi.sin())
                }
                Shape::Eight => (phi.sin(), 0.5 * self.aspect * (2.0 * phi).sin()),
            };
            rot(p, q) * self.size
        };
        if let Shape::Lollipop { reach } = self.shape {
            // Stalk along ψ to the circle's nearest point, then around it (centre one radius
            // further), then back; the times are in proportion to the lengths.
            let ring = two_pi_n * self.size;
            let f = reach / (2.0 * reach + ring);
            let stalk = |x: f64| rot(reach * x, 0.0);
            return if tau <= f {
                stalk(tau / f)
            } else if tau >= 1.0 - f {
                stalk((1.0 - tau) / f)
            } else {
                let phi = core::f64::consts::PI + two_pi_n * (tau - f) / (1.0 - 2.0 * f);
                stalk(1.0) + rot(self.size, 0.0) + e(phi)
            };
        }
        let phi = self.phase + two_pi_n * tau;
        e(phi) - e(self.phase)
    }

    /// Which of the coarse barrier paths ([`super::settings::COARSE_PATHS`]) the loop runs
    /// under a joint limit: a hash of its parameters, so that a loop runs the same path
    /// whatever its place in a seed's order (by its place, seeds ran different (loop, path)
    /// pairs and their full budgets reached different minima).
    pub fn path(&self) -> usize {
        let (kind, reach) = match self.shape {
            Shape::Ellipse => (0, 0),
            Shape::Eight => (1, 0),
            Shape::Lollipop { reach } => (2, reach.to_bits()),
            Shape::Rim { centre } => (3, centre[0].to_bits() ^ centre[1].to_bits().rotate_left(32)),
        };
        let words = [
            kind,
            reach,
            self.size.to_bits(),
            self.aspect.to_bits(),
            self.psi.to_bits(),
            self.phase.to_bits(),
            u64::from(self.turns),
        ];
        let h = words
            .iter()
            .fold(0u64, |h, &w| splitmix64(h.wrapping_add(GOLDEN_GAMMA) ^ w));
        (h & 1) as usize
    }

    /// The controls that run the loop on `grid` (the shape path, differenced); for a
    /// transition, ridden along the straight path to the end shape (see the module docs).
    pub fn controls(&self, grid: &Grid) -> Vec<Vector2<f64>> {
        let n = grid.steps;
        let h = grid.h();
        let mut prev = Vector2::zeros();
        let u = (1..=n).map(|k| {
            let next = if k == n {
                Vector2::zeros()
            } else {
                self.offset(k as f64 / n as f64)
            };
            let u = (next - prev) / h;
            prev = next;
            u
        });
        match drift(grid) {
            Some(v) => u.map(|x| x + v).collect(),
            None => u.collect(),
        }
    }
}

/// The circle size whose net displacement best matches the target's size (see the module
/// docs), between 0.01 and 1.6 rad. Distances weigh a turn of the body by the middle link's
/// length.
pub fn reference_size(grid: &Grid) -> f64 {
    let want = moved(grid, &grid.terminal.target, &grid.start);
    let mut best = (f64::INFINITY, 0.5);
    let mut s = 0.01;
    while s <= 1.6 {
        let circle = StartLoop {
            shape: Shape::Ellipse,
            size: s,
            aspect: 1.0,
            psi: 0.0,
            phase: 0.0,
            turns: 1,
        };
        if let Ok(states) = grid.rollout(&circle.controls(grid))
            && let Some(end) = states.last()
        {
            let got = moved(grid, end, &grid.start);
            // Floored so that the logarithm stays finite for a zero target.
            let miss = (got.max(TINY) / want.max(TINY)).ln().abs();
            if miss < best.0 {
                best = (miss, s);
            }
        }
        s *= 1.25;
    }
    best.1
}

/// How far the body is from `t` at `s`: the distance, a turn weighed by the middle link's
/// length.
fn moved(grid: &Grid, s: &StageState, t: &StageState) -> f64 {
    let scale = grid.model.kin.swimmer().lengths()[0];
    ((s[2] - t[2]).powi(2) + (s[3] - t[3]).powi(2) + (scale * (s[4] - t[4])).powi(2)).sqrt()
}

/// The constant control `(β − ᾱ)/T` of the straight shape path from the start shape to the
/// end shape of `grid`; `None` for a loop (`β = ᾱ`).
pub fn drift(grid: &Grid) -> Option<Vector2<f64>> {
    let (s, t) = (&grid.start, &grid.terminal.target);
    let d = Vector2::new(t[0] - s[0], t[1] - s[1]);
    (d != Vector2::zeros()).then(|| d / (grid.h() * grid.steps as f64))
}

/// The first start of a search on `grid`: the straight shape path to the end shape (the zero
/// control for a loop: the zero loop).
pub fn straight(grid: &Grid) -> Vec<Vector2<f64>> {
    vec![drift(grid).unwrap_or_else(Vector2::zeros); grid.steps]
}

/// The first `count` start loops of the problem on `grid` (loop size `size`, box loops
/// without a joint limit `limit`): [`family`] through its start shape for a loop (after the
/// rim loops under a limit), [`transitions`] for a transition. The first `common` are seed
/// 0's for every seed; `seed` orders the rest (see the module docs).
pub fn of_grid(
    grid: &Grid,
    size: f64,
    seed: u64,
    common: usize,
    count: usize,
    limit: Option<f64>,
) -> Vec<StartLoop> {
    let ordered = |seed: u64, count: usize| {
        let alpha0 = Vector2::new(grid.start[0], grid.start[1]);
        let alpha_end = Vector2::new(grid.terminal.target[0], grid.terminal.target[1]);
        let boxes = limit.is_none();
        if alpha_end == alpha0 {
            let mut out = limit.map_or_else(Vec::new, |a| rims(grid, a));
            out.truncate(count);
            let rest = count - out.len();
            out.extend(family(size, &alpha0, seed, rest, boxes));
            out
        } else {
            transitions(size, &alpha0, &alpha_end, seed, count, boxes)
        }
    };
    if seed == 0 || common >= count {
        return ordered(0, count);
    }
    let mut out = ordered(0, common);
    let own: Vec<StartLoop> = (ordered(seed, usize::MAX).into_iter())
        .filter(|s| !out.contains(s))
        .collect();
    out.extend(own);
    out.truncate(count);
    out
}

/// The start loops of a transition from `alpha0` to `alpha_end` (see the module docs): those
/// of [`family`] with the box loops sized about the midpoint of the straight path.
pub fn transitions(
    size: f64,
    alpha0: &Vector2<f64>,
    alpha_end: &Vector2<f64>,
    seed: u64,
    count: usize,
    boxes: bool,
) -> Vec<StartLoop> {
    family(size, &((alpha0 + alpha_end) / 2.0), seed, count, boxes)
}

/// The smallest displacement [`reference_size`] compares (a floor, not a tolerance).
const TINY: f64 = 1e-300;
/// Box loops reach at most this `|α_i|` (radians): 90 % of the links' overlap.
const BOX: f64 = 0.9 * OVERLAP;
/// Box loops per scaled loop in the mixed part of the family.
const BOX_SHARE: usize = 3;

/// The box loops for the start shape `alpha0` (see the module docs).
fn box_loops(alpha0: &Vector2<f64>) -> Vec<StartLoop> {
    let pi = core::f64::consts::PI;
    let mut out = Vec::new();
    for k in 0..8 {
        let psi = pi * f64::from(k) / 8.0;
        for aspect in [0.1, -0.1, 0.2, -0.2] {
            for phase in [0.5 * pi, 1.5 * pi] {
                let unit = StartLoop {
                    shape: Shape::Ellipse,
                    size: 1.0,
                    aspect,
                    psi,
                    phase,
                    turns: 1,
                };
                // The largest size with |ᾱ_i + s·o_i| ≤ BOX at 64 points o of the unit loop.
                let mut room = f64::INFINITY;
                for j in 0..64 {
                    let o = unit.offset(f64::from(j) / 64.0);
                    for i in 0..2 {
                        if o[i] != 0.0 {
                            room = room.min((BOX - alpha0[i] * o[i].signum()) / o[i].abs());
                        }
                    }
                }
                if !(room.is_finite() && room > 0.0) {
                    continue;
                }
                for fill in [0.75, 0.9, 1.0] {
                    out.push(StartLoop {
                        size: fill * room,
                        ..unit
                    });
                }
            }
        }
    }
    out
}

/// The first `count` start loops for a problem whose [`reference_size`] is `size` and whose
/// start shape is `alpha0`, ordered by `seed`, with the box loops if `boxes` (see the module
/// docs).
pub fn family(
    size: f64,
    alpha0: &Vector2<f64>,
    seed: u64,
    count: usize,
    boxes: bool,
) -> Vec<StartLoop> {
    let (first, rest) = shapes(size, boxes);
    // A deterministic mix (splitmix64 of the seed and the index) of everything but the
    // axis-aligned ellipses.
    let mix = |i: u64| {
        splitmix64(
            seed.wrapping_add(i.wrapping_mul(GOLDEN_GAMMA))
                .wrapping_add(GOLDEN_GAMMA),
        )
    };
    let mixed = |list: Vec<StartLoop>, salt: u64| {
        let mut keyed: Vec<(u64, StartLoop)> = list
            .into_iter()
            .enumerate()
            .map(|(i, s)| (mix((i as u64) ^ salt), s))
            .collect();
        keyed.sort_by_key(|(k, _)| *k);
        keyed.into_iter().map(|(_, s)| s)
    };
    let mut boxes = mixed(if boxes { box_loops(alpha0) } else { Vec::new() }, 1 << 40);
    let mut scaled = mixed(rest, 0);
    let mut out = first;
    while out.len() < count {
        let before = out.len();
        out.extend(boxes.by_ref().take(BOX_SHARE));
        out.extend(scaled.next());
        if out.len() == before {
            break;
        }
    }
    out.truncate(count);
    out
}

/// The start loops of [`family`] for a loop size `size`, before the mix: the round ellipses
/// of the given size at `ψ = 0` and after them, with `directions`, the one-turn lollipops with
/// the whole stalk at twice that size (first, the same block for every seed), and every other
/// ellipse, figure-eight and lollipop.
fn shapes(size: f64, directions: bool) -> (Vec<StartLoop>, Vec<StartLoop>) {
    let pi = core::f64::consts::PI;
    let mut first = Vec::new();
    let mut far = Vec::new();
    let mut rest = Vec::new();
    for turns in [1u32, 2, 3] {
        for scale in [1.0, 0.5, 2.0] {
            for aspect in [1.0, -1.0, 0.6, -0.6] {
                for psi in [0.0, 0.25 * pi, 0.5 * pi, 0.75 * pi] {
                    for phase in [0.0, 0.5 * pi, pi, 1.5 * pi] {
                        let e = StartLoop {
                            shape: Shape::Ellipse,
                            size: (size * scale).clamp(0.01, 1.6),
                            aspect,
                            psi,
                            phase,
                            turns,
                        };
                        if psi == 0.0 && aspect.abs() == 1.0 && scale == 1.0 {
                            first.push(e);
                        } else {
                            rest.push(e);
                        }
                    }
                }
                if aspect.abs() == 1.0 {
                    for psi in [0.0, 0.25 * pi, 0.5 * pi, 0.75 * pi] {
                        rest.push(StartLoop {
                            shape: Shape::Eight,
                            size: (size * scale).clamp(0.01, 1.6),
                            aspect,
                            psi,
                            phase: 0.0,
                            turns,
                        });
                    }
                    for k in 0..8 {
                        for reach in [0.5, 1.0] {
                            let l = StartLoop {
                                shape: Shape::Lollipop {
                                    reach: reach * (size * scale).clamp(0.01, 1.6),
                                },
                                size: (0.7 * size * scale).clamp(0.01, 1.2),
                                aspect,
                                psi: 0.25 * pi * f64::from(k),
                                phase: 0.0,
                                turns,
                            };
                            // One turn, the whole stalk, twice the reference size: each
                            // a direction of the shape plane, far out.
                            if directions && turns == 1 && scale == 2.0 && reach == 1.0 {
                                far.push(l);
                            } else {
                                rest.push(l);
                            }
                        }
                    }
                }
            }
        }
    }
    first.append(&mut far);
    (first, rest)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Problem;
    use crate::solver::stage::Rule;

    /// Asserts that start loop `s` on `grid` closes (its controls sum to zero); its largest
    /// `|α_i|` from `alpha0` over `samples + 1` points of its offset.
    pub(super) fn closed_reach(
        s: &StartLoop,
        grid: &Grid,
        alpha0: &Vector2<f64>,
        samples: u32,
    ) -> f64 {
        let u = s.controls(grid);
        let closure: Vector2<f64> = u.iter().sum::<Vector2<f64>>() * grid.h();
        assert!(closure.amax() < 1e-12, "{s:?}");
        (0..=samples)
            .map(|j| (alpha0 + s.offset(f64::from(j) / f64::from(samples))).amax())
            .fold(0.0, f64::max)
    }

    #[test]
    fn every_start_is_a_closed_loop_through_alpha0() {
        let p = Problem::paper();
        let grid = Grid::new(&p, 64, Rule::LEFT_POINT).unwrap();
        for s in family(0.5, &Vector2::new(0.3, -0.2), 3, 500, true) {
            let u = s.controls(&grid);
            assert_eq!(u.len(), 64);
            let closure: Vector2<f64> = u.iter().sum::<Vector2<f64>>() * grid.h();
            assert!(closure.amax() < 1e-12, "{s:?}");
            assert!(s.offset(0.0).amax() == 0.0);
        }
    }

    /// Box loops: closed, through `ᾱ`, within `|α_i| ≤ 0.9π` and reaching it, for a bent
    /// start too; three of every four loops after the first block (the same for every seed),
    /// until they run out.
    #[test]
    fn box_loops_span_the_admissible_shapes() {
        let p = Problem::paper();
        let grid = Grid::new(&p, 64, Rule::LEFT_POINT).unwrap();
        for alpha0 in [Vector2::zeros(), Vector2::new(0.8, -1.1)] {
            let loops = box_loops(&alpha0);
            assert_eq!(loops.len(), 192);
            let mut widest = 0.0f64;
            for s in &loops {
                let reach = closed_reach(s, &grid, &alpha0, 256);
                assert!(reach <= BOX * (1.0 + 1e-3), "{s:?}: {reach}");
                widest = widest.max(reach);
            }
            assert!(widest >= 0.99 * BOX, "{widest}");
        }
        assert_eq!(family(0.5, &Vector2::zeros(), 0, 4096, false).len(), 936);
        let f = family(0.5, &Vector2::zeros(), 0, 4096, true);
        assert_eq!(f.len(), 1128);
        let block = shapes(0.5, true).0.len();
        assert_eq!(block, 40);
        assert_eq!(shapes(0.5, false).0.len(), 24);
        assert_eq!(
            f[..block],
            family(0.5, &Vector2::zeros(), 7, block, true)[..]
        );
        let thin = |s: &StartLoop| s.shape == Shape::Ellipse && s.aspect.abs() <= 0.2;
        let early = &f[block..block + 128];
        assert_eq!(early.iter().filter(|s| thin(s)).count(), 96);
    }

    #[test]
    fn the_family_is_deterministic_in_the_seed_and_diverse_early() {
        let a = Vector2::zeros();
        assert_eq!(family(0.5, &a, 1, 40, true), family(0.5, &a, 1, 40, true));
        assert_ne!(family(0.5, &a, 1, 64, true), family(0.5, &a, 2, 64, true));
        let f = family(0.5, &a, 0, 80, true);
        assert!(f.iter().any(|s| s.turns == 3) && f.iter().any(|s| s.shape == Shape::Eight));
        assert!(f.iter().any(|s| s.aspect < 0.0) && f.iter().any(|s| s.aspect > 0.0));
    }

    /// The first `common` loops are seed 0's for every seed, the rest the seed's own order
    /// without them; with `common` the whole count (under a joint limit), seed 0's order.
    #[test]
    fn the_first_common_loops_are_seed_0s_for_every_seed() {
        let grid = Grid::new(&Problem::paper(), 64, Rule::LEFT_POINT).unwrap();
        let zero = of_grid(&grid, 0.5, 0, 0, 300, None);
        let other = of_grid(&grid, 0.5, 5, 128, 300, None);
        assert_eq!(other[..128], zero[..128]);
        assert_ne!(other[128..], zero[128..]);
        let own: Vec<StartLoop> = (of_grid(&grid, 0.5, 5, 0, 4096, None).into_iter())
            .filter(|s| !zero[..128].contains(s))
            .take(300 - 128)
            .collect();
        assert_eq!(other[128..], own[..]);
        assert_eq!(
            of_grid(&grid, 0.5, 5, 100, 100, Some(1.5)),
            of_grid(&grid, 0.5, 0, 0, 100, Some(1.5))
        );
    }

    /// A loop's barrier path is its own, whatever the seed's order; both paths are used.
    #[test]
    fn the_barrier_path_is_the_loops_own() {
        let a = Vector2::zeros();
        let first = family(0.5, &a, 0, 4096, false);
        let other = family(0.5, &a, 5, 4096, false);
        assert_ne!(first, other);
        for s in &other {
            let same = first.iter().find(|t| *t == s).expect("the same loops");
            assert_eq!(same.path(), s.path());
        }
        let ones = first.iter().filter(|s| s.path() == 1).count();
        assert!((400..=536).contains(&ones), "{ones} of {}", first.len());
    }

    #[test]
    fn reference_size_grows_with_the_target() {
        let size = |x: f64| {
            let spec = crate::problem::Spec {
                target: [x, 0.0, 0.0],
                ..Default::default()
            };
            let p = Problem::new(&spec).unwrap();
            reference_size(&Grid::new(&p, 64, Rule::LEFT_POINT).unwrap())
        };
        let (a, b) = (size(0.001), size(0.1));
        assert!(a < b && a < 0.2, "{a} {b}");
    }
}
