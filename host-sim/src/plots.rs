//! SVG figures of a solution (plotters, SVG backend only): the shape loop, `α(t)`, `u(t)`,
//! `x(t), y(t)`, `θ(t)`, and the swimmer drawn in the plane every 5 s.

use crate::problem::Problem;
use crate::solver::Trajectory;
use crate::solver::continuation::{Lattice, SweepPoint};
use plotters::prelude::*;

type Series<'a> = (&'a str, Vec<(f64, f64)>, RGBColor);

fn range(v: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let lo = v.clone().fold(f64::INFINITY, f64::min);
    let hi = v.fold(f64::NEG_INFINITY, f64::max);
    let pad = 0.05 * (hi - lo).max(1e-9);
    (lo - pad, hi + pad)
}

fn line_plot(
    title: &str,
    xlabel: &str,
    ylabel: &str,
    series: &[Series<'_>],
    equal: bool,
) -> Result<String, String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (720, 480)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let (mut x0, mut x1) = range(series.iter().flat_map(|s| s.1.iter().map(|p| p.0)));
        let (mut y0, mut y1) = range(series.iter().flat_map(|s| s.1.iter().map(|p| p.1)));
        if equal {
            let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
            let half = 0.5 * (x1 - x0).max((y1 - y0) * 1.5);
            x0 = cx - half;
            x1 = cx + half;
            y0 = cy - half / 1.5;
            y1 = cy + half / 1.5;
        }
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 20))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc(xlabel)
            .y_desc(ylabel)
            .draw()
            .map_err(|e| e.to_string())?;
        for (name, pts, color) in series {
            let c = *color;
            let drawn = chart
                .draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))
                .map_err(|e| e.to_string())?;
            // Unnamed series (the swimmer's intermediate snapshots) stay out of the legend.
            if !name.is_empty() {
                drawn
                    .label(*name)
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c));
            }
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

/// Every figure as `(file name, SVG text)`.
pub fn figures(problem: &Problem, t: &Trajectory) -> Result<Vec<(String, String)>, String> {
    let h = problem.h;
    let time = |k: usize| h * k as f64;
    let stride = (t.states.len() / 2000).max(1);
    let pick = |f: &dyn Fn(usize) -> f64| -> Vec<(f64, f64)> {
        (0..t.states.len())
            .step_by(stride)
            .map(|k| (time(k), f(k)))
            .collect()
    };
    let mut out = Vec::new();
    let shape: Vec<(f64, f64)> = t
        .states
        .iter()
        .step_by(stride)
        .map(|s| (s.alpha.x, s.alpha.y))
        .collect();
    out.push((
        "shape_loop.svg".into(),
        line_plot(
            "Shape loop",
            "alpha1 (rad)",
            "alpha2 (rad)",
            &[("(alpha1, alpha2)", shape, BLUE)],
            false,
        )?,
    ));
    out.push((
        "alpha.svg".into(),
        line_plot(
            "Joint angles",
            "t (s)",
            "alpha (rad)",
            &[
                ("alpha1", pick(&|k| t.states[k].alpha.x), BLUE),
                ("alpha2", pick(&|k| t.states[k].alpha.y), RED),
            ],
            false,
        )?,
    ));
    let u = |k: usize, i: usize| t.controls.get(k).map_or(0.0, |u| u[i]);
    out.push((
        "controls.svg".into(),
        line_plot(
            "Controls",
            "t (s)",
            "u (rad/s)",
            &[
                ("u1", pick(&|k| u(k, 0)), BLUE),
                ("u2", pick(&|k| u(k, 1)), RED),
            ],
            false,
        )?,
    ));
    out.push((
        "position.svg".into(),
        line_plot(
            "Position",
            "t (s)",
            "m",
            &[
                ("x", pick(&|k| t.states[k].g.x()), BLUE),
                ("y", pick(&|k| t.states[k].g.y()), RED),
            ],
            false,
        )?,
    ));
    out.push((
        "theta.svg".into(),
        line_plot(
            "Orientation",
            "t (s)",
            "theta (rad)",
            &[("theta", pick(&|k| t.states[k].g.theta()), BLUE)],
            false,
        )?,
    ));
    // The swimmer every 5 s: three segments per snapshot, colour from early (blue) to late (red).
    let [l0, l1, l2] = problem.swimmer.lengths();
    let every = ((5.0 / h).round() as usize).max(1);
    let mut series = Vec::new();
    let snaps: Vec<usize> = (0..t.states.len()).step_by(every).collect();
    let n = snaps.len().max(2) - 1;
    for (i, &k) in snaps.iter().enumerate() {
        let s = &t.states[k];
        let (a1, a2) = (s.alpha.x, s.alpha.y);
        let body = |p: (f64, f64)| {
            let q = s.g.act(&nalgebra::Vector2::new(p.0, p.1));
            (q.x, q.y)
        };
        let front_tip = (l0 / 2.0 + l1 * a1.cos(), l1 * a1.sin());
        let rear_tip = (-l0 / 2.0 - l2 * a2.cos(), -l2 * a2.sin());
        let pts = vec![
            body(front_tip),
            body((l0 / 2.0, 0.0)),
            body((-l0 / 2.0, 0.0)),
            body(rear_tip),
        ];
        let f = i as f64 / n as f64;
        let color = RGBColor((255.0 * f) as u8, 60, (255.0 * (1.0 - f)) as u8);
        let name = match i {
            0 => "start (t = 0)",
            _ if i == n => "end (t = T)",
            _ => "",
        };
        series.push((name, pts, color));
    }
    let path: Vec<(f64, f64)> = t
        .states
        .iter()
        .step_by(stride)
        .map(|s| (s.g.x(), s.g.y()))
        .collect();
    series.push(("centre path", path, BLACK));
    out.push((
        "swimmer.svg".into(),
        line_plot(
            "Swimmer every 5 s (blue: start, red: end)",
            "x (m)",
            "y (m)",
            &series,
            true,
        )?,
    ));
    Ok(out)
}

/// The sweep's figure as `(file name, SVG text)`: `sweep.svg`, the cost over the plane of the
/// first two axes of the lattice that vary (colour; grey where no admissible gait was found),
/// or the cost along the one that varies.
pub fn sweep_figures(
    lattice: &Lattice,
    points: &[SweepPoint],
) -> Result<Vec<(String, String)>, String> {
    let names = ["x (m)", "y (m)", "theta (rad)"];
    let varying: Vec<usize> = (0..3).filter(|&i| lattice.axes[i].len() > 1).collect();
    let cost = |p: &SweepPoint| {
        p.result
            .as_ref()
            .ok()
            .filter(|x| x.admissible)
            .map(|x| x.cost)
    };
    let coord = |p: &SweepPoint, axis: usize| p.target[axis];
    let mut svg = String::new();
    match varying.as_slice() {
        [] | [_] => {
            let axis = varying.first().copied().unwrap_or(0);
            let pts: Vec<(f64, f64)> = points
                .iter()
                .filter_map(|p| Some((coord(p, axis), cost(p)?)))
                .collect();
            svg = line_plot(
                "Cost of the cheapest gait",
                names[axis],
                "J",
                &[("J", pts, BLUE)],
                false,
            )?;
        }
        [a, b, ..] => {
            let (a, b) = (*a, *b);
            let (xa, xb) = (&lattice.axes[a], &lattice.axes[b]);
            let step = |v: &[f64]| (v[v.len() - 1] - v[0]) / (v.len() - 1) as f64;
            let (da, db) = (step(xa), step(xb));
            let (lo, hi) = points
                .iter()
                .filter_map(cost)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), c| {
                    (l.min(c), h.max(c))
                });
            {
                let root = SVGBackend::with_string(&mut svg, (760, 640)).into_drawing_area();
                root.fill(&WHITE).map_err(|e| e.to_string())?;
                let (main, bar) = root.split_horizontally(660);
                let x0 = xa[0] - 0.5 * da;
                let x1 = xa[xa.len() - 1] + 0.5 * da;
                let y0 = xb[0] - 0.5 * db;
                let y1 = xb[xb.len() - 1] + 0.5 * db;
                let mut chart = ChartBuilder::on(&main)
                    .caption("Cost J of the cheapest admissible gait", ("sans-serif", 20))
                    .margin(10)
                    .x_label_area_size(40)
                    .y_label_area_size(60)
                    .build_cartesian_2d(x0..x1, y0..y1)
                    .map_err(|e| e.to_string())?;
                chart
                    .configure_mesh()
                    .disable_mesh()
                    .x_desc(names[a])
                    .y_desc(names[b])
                    .draw()
                    .map_err(|e| e.to_string())?;
                let colour = |c: Option<f64>| match c {
                    Some(c) if hi > lo => viridis((c - lo) / (hi - lo)),
                    Some(_) => viridis(0.5),
                    None => RGBColor(200, 200, 200),
                };
                chart
                    .draw_series(points.iter().map(|p| {
                        let (u, v) = (coord(p, a), coord(p, b));
                        Rectangle::new(
                            [(u - 0.5 * da, v - 0.5 * db), (u + 0.5 * da, v + 0.5 * db)],
                            colour(cost(p)).filled(),
                        )
                    }))
                    .map_err(|e| e.to_string())?;
                // Colour bar.
                let mut scale = ChartBuilder::on(&bar)
                    .margin_top(40)
                    .margin_bottom(50)
                    .y_label_area_size(50)
                    .build_cartesian_2d(0.0..1.0, lo.min(hi)..hi.max(lo + 1e-12))
                    .map_err(|e| e.to_string())?;
                scale
                    .configure_mesh()
                    .disable_mesh()
                    .disable_x_axis()
                    .y_desc("J")
                    .draw()
                    .map_err(|e| e.to_string())?;
                let n = 64;
                scale
                    .draw_series((0..n).map(|i| {
                        let f0 = i as f64 / n as f64;
                        let f1 = (i + 1) as f64 / n as f64;
                        Rectangle::new(
                            [(0.0, lo + f0 * (hi - lo)), (1.0, lo + f1 * (hi - lo))],
                            viridis(f0).filled(),
                        )
                    }))
                    .map_err(|e| e.to_string())?;
                root.present().map_err(|e| e.to_string())?;
            }
        }
    }
    Ok(vec![("sweep.svg".into(), svg)])
}

/// The viridis colour map at `f ∈ [0, 1]` (piecewise linear through five of its colours).
fn viridis(f: f64) -> RGBColor {
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let x = f.clamp(0.0, 1.0) * 4.0;
    let i = (x.floor() as usize).min(3);
    let t = x - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let mix = |p: f64, q: f64| (p + (q - p) * t).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}
