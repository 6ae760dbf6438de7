//! The figures of a gait: the shape loop, the swimmer time-lapse, `α(t)`, `u(t)`, `x(t)`,
//! `y(t)`, `θ(t)` and the costates `ξ^k`, `ζ^k`; the bound on the joint angles ([`bound`])
//! and the arcs on the joint limit ([`arc_spans`], [`shape_overlay`]) as every figure draws
//! them.

use super::plane::{Drawing, Overlay, Path, PlaneFigure, Square, Stretches};
use super::style::*;
use super::time::{Level, Mark, Panel, Series, Spans, TimeFigure};
use super::{PlotError, Units};
use nalgebra::{Vector2, Vector3};
use plotters::style::RGBColor;
use purcell_core::Arc;
use purcell_core::se2::ExpCoefficients;
use purcell_solver::problem::{OVERLAP, Problem};
use purcell_solver::solver::Trajectory;

/// Points kept per curve (the figures are 1 500 pixels wide).
pub const POINTS: usize = 2500;

/// The indices `0, s, 2s, …` and `last`, with `s` such that about `points` remain.
pub fn thin(last: usize, points: usize) -> Vec<usize> {
    let stride = (last / points.max(1)).max(1);
    let mut ks: Vec<usize> = (0..=last).step_by(stride).collect();
    if ks.last() != Some(&last) {
        ks.push(last);
    }
    ks
}

/// A gait with what its figures need.
pub struct GaitFigures<'a> {
    /// The problem.
    pub problem: &'a Problem,
    /// States, controls, costates `ξ`.
    pub trajectory: &'a Trajectory,
    /// Its arcs on the joint limit.
    pub arcs: &'a [Arc],
    /// Angle units of the figures.
    pub units: Units,
}

impl GaitFigures<'_> {
    fn time(&self, k: usize) -> f64 {
        self.problem.h * k as f64
    }

    /// Panels over the gait's horizon.
    fn figure(&self, title: &str, panels: Vec<Panel>) -> TimeFigure {
        TimeFigure {
            title: title.into(),
            t: (0.0, self.time(self.trajectory.controls.len())),
            panels,
        }
    }

    fn alphas(&self) -> Vec<Vector2<f64>> {
        self.trajectory.states.iter().map(|s| s.alpha).collect()
    }

    /// A curve `(t_k, f(k))` over the states `k = 0..=N` (or, with `controls`, `k < N`).
    fn series(
        &self,
        label: &str,
        color: RGBColor,
        last: usize,
        f: impl Fn(usize) -> f64,
    ) -> Series {
        Series {
            label: label.into(),
            color,
            points: thin(last, POINTS)
                .into_iter()
                .map(|k| (self.time(k), f(k)))
                .collect(),
        }
    }

    /// A panel described `y_desc` of two curves over `k ≤ last` labelled `labels`, in
    /// [`BLUE`] and [`VERMILLION`] (the first and second joint, or `x` and `y`); `f(k)` gives
    /// both values.
    fn pair(
        &self,
        y_desc: impl Into<String>,
        labels: [&str; 2],
        last: usize,
        f: impl Fn(usize) -> [f64; 2],
    ) -> Panel {
        Panel::new(
            y_desc,
            vec![
                self.series(labels[0], BLUE, last, |k| f(k)[0]),
                self.series(labels[1], VERMILLION, last, |k| f(k)[1]),
            ],
        )
    }

    /// [`Self::pair`] of `values[k]` (angles or their rates) in display units.
    fn angle_pair(&self, y_desc: String, labels: [&str; 2], values: &[Vector2<f64>]) -> Panel {
        let u = self.units;
        self.pair(y_desc, labels, values.len() - 1, |k| {
            values[k].map(|a| u.angle(a)).into()
        })
    }

    /// `(α1, α2)`, equal axes.
    pub fn shape_loop(&self) -> PlaneFigure {
        let u = self.units;
        PlaneFigure::new(
            "Shape loop".into(),
            (
                format!("α₁ ({})", u.angle_unit),
                format!("α₂ ({})", u.angle_unit),
            ),
            Drawing::default(),
            shape_overlay(self.problem, &self.alphas(), self.arcs, u, BLUE, POINTS),
        )
    }

    /// The swimmer in the plane every 5 s, links scaled down (as the paper draws it), with the
    /// path of its body, start, end and direction of travel.
    pub fn swimmer(&self) -> PlaneFigure {
        let states = &self.trajectory.states;
        let path: Vec<(f64, f64)> = thin(states.len() - 1, POINTS)
            .into_iter()
            .map(|k| (states[k].g.x(), states[k].g.y()))
            .collect();
        let [l0, l1, l2] = self.problem.swimmer.lengths();
        // Scale the links so the swimmer is about a seventh of the path's extent.
        let extent = {
            let [x, y] = Overlay {
                paths: vec![Path {
                    label: String::new(),
                    color: INK,
                    points: path.clone(),
                    arrows: 0,
                }],
                ..Overlay::default()
            }
            .data_bounds();
            (x.1 - x.0).max(y.1 - y.0).max(1e-9)
        };
        let scale = nice_ratio((l0 + l1 + l2) / (extent / 7.0));
        let (start, end) = (path[0], path[path.len() - 1]);
        let overlay = Overlay {
            paths: vec![Path {
                label: "body path".into(),
                color: LIMIT,
                points: path,
                arrows: 5,
            }],
            limit: None,
            stretches: None,
            marks: vec![
                Mark {
                    at: start,
                    marker: Marker::Circle,
                    color: ORANGE,
                    label: Some("start".into()),
                },
                Mark {
                    at: end,
                    marker: Marker::Square,
                    color: SKY,
                    label: Some("end".into()),
                },
            ],
        };
        PlaneFigure::new(
            format!(
                "Swimmer every 5 s, labelled with its time, links drawn at 1:{}",
                scale_label(scale)
            ),
            ("x (m)".into(), "y (m)".into()),
            self.snapshots(scale),
            overlay,
        )
    }

    /// The swimmer every 5 s (and at the end), its links scaled by `1/scale` about its body,
    /// each snapshot labelled with its time.
    fn snapshots(&self, scale: f64) -> Drawing {
        let states = &self.trajectory.states;
        let [l0, l1, l2] = self.problem.swimmer.lengths();
        let every = ((5.0 / self.problem.h).round() as usize).max(1);
        let mut snaps: Vec<usize> = (0..states.len()).step_by(every).collect();
        if snaps.last() != Some(&(states.len() - 1)) {
            snaps.push(states.len() - 1);
        }
        let mut lines = Vec::new();
        let mut labels = Vec::new();
        for k in snaps {
            let s = &states[k];
            labels.push((
                (s.g.x(), s.g.y()),
                format!("{} s", crate::decimal::time(k as u64, self.problem.h)),
            ));
            let (a1, a2) = (s.alpha.x, s.alpha.y);
            let at = |x: f64, y: f64| {
                let q = s.g.act(&Vector2::new(x / scale, y / scale));
                (q.x, q.y)
            };
            let (front, rear) = (at(l0 / 2.0, 0.0), at(-l0 / 2.0, 0.0));
            let front_tip = at(l0 / 2.0 + l1 * a1.cos(), l1 * a1.sin());
            let rear_tip = at(-l0 / 2.0 - l2 * a2.cos(), -l2 * a2.sin());
            lines.push((vec![rear, front], VERMILLION));
            lines.push((vec![front, front_tip], GREEN));
            lines.push((vec![rear, rear_tip], BLUE));
        }
        Drawing {
            lines,
            legend: vec![
                (Key::Line(VERMILLION), "middle link".into()),
                (Key::Line(GREEN), "front link (α₁)".into()),
                (Key::Line(BLUE), "rear link (α₂)".into()),
            ],
            labels,
        }
    }

    /// `α1(t)`, `α2(t)` with the bound ([`bound`]: a joint limit always, the overlap limit
    /// when the gait comes near it) and the arcs shaded.
    pub fn alpha(&self) -> TimeFigure {
        let (s, u) = (&self.trajectory.states, self.units);
        let desc = format!("joint angle ({})", u.angle_unit);
        let mut panel = self.angle_pair(desc, ["α₁", "α₂"], &self.alphas());
        let peak = s.iter().fold(0.0f64, |m, x| m.max(x.alpha.amax()));
        let square = bound(self.problem, u);
        if square.whole || u.angle(peak) > 0.75 * square.value {
            panel.levels = vec![
                Level {
                    y: square.value,
                    label: Some(square.label),
                    color: square.color,
                },
                Level {
                    y: -square.value,
                    label: None,
                    color: square.color,
                },
            ];
        }
        panel.spans = arc_spans(self.arcs, self.problem.h);
        self.figure("Joint angles", vec![panel])
    }

    /// `u1(t)`, `u2(t)` for `k < N` (the last CSV row's zero is padding, not a control),
    /// with the arcs shaded (`u_i = 0` there).
    pub fn controls(&self) -> TimeFigure {
        let desc = format!("u ({})", self.units.rate_unit);
        let mut panel = self.angle_pair(desc, ["u₁", "u₂"], &self.trajectory.controls);
        panel.spans = arc_spans(self.arcs, self.problem.h);
        self.figure("Controls (joint rates)", vec![panel])
    }

    /// `x(t)`, `y(t)` with the target at `T`.
    pub fn position(&self) -> TimeFigure {
        let s = &self.trajectory.states;
        let last = s.len() - 1;
        let t_end = self.time(last);
        let mut panel = self.pair("position (m)", ["x", "y"], last, |k| {
            [s[k].g.x(), s[k].g.y()]
        });
        let target = self.problem.target;
        panel.marks = vec![
            Mark {
                at: (t_end, target.x),
                marker: Marker::Square,
                color: BLUE,
                label: Some("target x".into()),
            },
            Mark {
                at: (t_end, target.y),
                marker: Marker::Diamond,
                color: VERMILLION,
                label: Some("target y".into()),
            },
        ];
        self.figure("Position of the body", vec![panel])
    }

    /// `θ(t)` with the target at `T`.
    pub fn theta(&self) -> TimeFigure {
        let (s, u) = (&self.trajectory.states, self.units);
        let last = s.len() - 1;
        let mut panel = Panel::new(
            format!("θ ({})", u.angle_unit),
            vec![self.series("θ", BLUE, last, |k| u.angle(s[k].g.theta()))],
        );
        panel.marks = vec![Mark {
            at: (self.time(last), u.angle(self.problem.target.z)),
            marker: Marker::Square,
            color: BLUE,
            label: Some("target θ".into()),
        }];
        self.figure("Orientation of the body", vec![panel])
    }

    /// The costates of the law `u_k = ξ^k − A(α_k)ᵀ ζ^k` over `k < N`: `ξ^k` (with the arcs
    /// shaded: there the joint's `ξ^k_i` takes the value `(Aᵀζ^k)_i`, MODEL.md §9) and
    /// `ζ^k = dexp_{X_k}ᵀ Ad_{g_k}ᵀ μ` (SI units whatever the angle units).
    pub fn costate(&self, mu: &Vector3<f64>) -> Result<TimeFigure, PlotError> {
        let t = self.trajectory;
        let n = t.controls.len();
        let kin = self.problem.kinematics::<f64>()?;
        let mut zeta = Vec::with_capacity(n);
        for k in 0..n {
            let s = &t.states[k];
            let a = self.problem.swimmer.connection(&s.alpha)?;
            let x = kin.twist(&a, &t.controls[k]);
            let m = s.g.adjoint_transpose_mul(mu);
            zeta.push(ExpCoefficients::new(x.z).dexp_transpose_mul(&x, &m));
        }
        let last = n - 1;
        // `xis[k]` is ξ^{k−1}: ξ^k is `xis[k + 1]`.
        let xi = |k: usize, i: usize| t.xis[k + 1][i];
        let mut xi_panel = self.pair("ξᵏ (rad/s)", ["ξ₁", "ξ₂"], last, |k| {
            [xi(k, 0), xi(k, 1)]
        });
        xi_panel.spans = arc_spans(self.arcs, self.problem.h);
        Ok(self.figure(
            "Costates of the control law u = ξ − Aᵀζ",
            vec![
                xi_panel,
                self.pair("ζᵏ (rad²/(m·s))", ["ζ (x)", "ζ (y)"], last, |k| {
                    [zeta[k].x, zeta[k].y]
                }),
                Panel::new(
                    "ζᵏ (rad/s)",
                    vec![self.series("ζ (θ)", GREEN, last, |k| zeta[k].z)],
                ),
            ],
        ))
    }
}

/// The bound on the joint angles in display units: the problem's joint limit `±α_max`
/// (dashed in [`JOINT_LIMIT`], always shown), or else where the links overlap (`|α_i| = π`,
/// dashed in [`LIMIT`], shown where the gait comes near it).
pub fn bound(problem: &Problem, units: Units) -> Square {
    match problem.alpha_max {
        Some(a) => Square {
            value: units.angle(a),
            label: format!("joint limit ±{}", units.format_angle(a)),
            color: JOINT_LIMIT,
            whole: true,
        },
        None => Square {
            value: units.angle(OVERLAP),
            label: format!("links overlap, |αᵢ| = {}", units.format_angle(OVERLAP)),
            color: LIMIT,
            whole: false,
        },
    }
}

/// The arcs as time spans `[t_first, t_last]` (the states on the limit; the controls
/// `u_first … u_{last−1}` of that joint are zero), shaded in [`ARC_SHADE`]; `None`
/// without arcs.
pub fn arc_spans(arcs: &[Arc], h: f64) -> Option<Spans> {
    (!arcs.is_empty()).then(|| Spans {
        label: ARC_LABEL.into(),
        color: ARC_SHADE,
        spans: arcs
            .iter()
            .map(|a| (h * f64::from(a.first), h * f64::from(a.last)))
            .collect(),
    })
}

/// A gait over the shape plane: the loop `alphas` (states `k = 0..=N`, drawn with about
/// `points` of them) with arrows, its `arcs` on the joint limit drawn over it
/// ([`ARC`]), the bound ([`bound`]), the start.
pub fn shape_overlay(
    problem: &Problem,
    alphas: &[Vector2<f64>],
    arcs: &[Arc],
    units: Units,
    color: RGBColor,
    points: usize,
) -> Overlay {
    let at = |a: &Vector2<f64>| (units.angle(a.x), units.angle(a.y));
    let path = thin(alphas.len().saturating_sub(1), points)
        .into_iter()
        .filter_map(|k| alphas.get(k))
        .map(at)
        .collect();
    let lines: Vec<Vec<(f64, f64)>> = arcs
        .iter()
        .map(|a| {
            let len = a.last.saturating_sub(a.first) as usize;
            thin(len, points)
                .into_iter()
                .filter_map(|i| alphas.get(a.first as usize + i))
                .map(at)
                .collect()
        })
        .collect();
    let a0 = problem.alpha0;
    Overlay {
        paths: vec![Path {
            label: "gait".into(),
            color,
            points: path,
            arrows: 6,
        }],
        limit: Some(bound(problem, units)),
        stretches: (!lines.is_empty()).then(|| Stretches {
            label: ARC_LABEL.into(),
            color: ARC,
            width: ARC_LINE,
            lines,
        }),
        marks: vec![Mark {
            at: (units.angle(a0.x), units.angle(a0.y)),
            marker: Marker::Circle,
            color: ORANGE,
            label: Some("start = end, ᾱ".into()),
        }],
    }
}

/// The ratio 1, 2, 5 × 10ⁿ nearest above `r` (at least 1).
fn nice_ratio(r: f64) -> f64 {
    if r <= 1.0 {
        return 1.0;
    }
    let base = 10f64.powf(r.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * base)
        .find(|&v| v >= r)
        .unwrap_or(10.0 * base)
}

fn scale_label(s: f64) -> String {
    format!("{}", s.round() as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thinning_keeps_both_ends() {
        assert_eq!(thin(3, POINTS), vec![0, 1, 2, 3]);
        let t = thin(10_000, POINTS);
        assert_eq!((t[0], *t.last().unwrap()), (0, 10_000));
        assert!(t.len() <= POINTS + 2);
        let t = thin(10_001, 100);
        assert_eq!(*t.last().unwrap(), 10_001);
    }

    #[test]
    fn ratios() {
        assert_eq!(nice_ratio(42.0), 50.0);
        assert_eq!(nice_ratio(0.3), 1.0);
        assert_eq!(nice_ratio(120.0), 200.0);
    }
}
