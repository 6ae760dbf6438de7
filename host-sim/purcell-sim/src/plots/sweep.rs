//! The gait atlas of a sweep: the cost of the cheapest admissible gait over the plane of two
//! axes of the target lattice (`sweep`), one cell per target, grey where none was found.

use super::axes::{Axes, colour_bar_tick, minus, round_ticks, tick_formatter};
use super::render::{DrawResult, Figure};
use super::style::*;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};
use purcell_solver::solver::continuation::{Lattice, SweepPoint};

/// Plotting-area side.
const PANEL: f64 = 1000.0;
/// Room above the bar for its label.
const BAR_TITLE: f64 = 60.0;
/// Colour steps of the bar.
const BAR_STEPS: usize = 64;
/// Cells with no admissible gait.
const MISSING: RGBColor = RGBColor(200, 200, 200);

/// The atlas.
pub struct SweepFigure<'a> {
    /// The lattice.
    pub lattice: &'a Lattice,
    /// Its results, in the lattice's order.
    pub points: &'a [SweepPoint],
    /// The horizon `T` of every target's problem, seconds.
    pub horizon: f64,
}

impl SweepFigure<'_> {
    /// The two axes drawn: the first two that vary (`x`, `y` if none or one varies).
    fn axes(&self) -> (usize, usize) {
        let varying: Vec<usize> = (0..3).filter(|&i| self.lattice.axes[i].len() > 1).collect();
        match varying.as_slice() {
            [a, b, ..] => (*a, *b),
            [a] if *a == 0 => (0, 1),
            [a] => (0, *a),
            [] => (0, 1),
        }
    }

    fn cost(p: &SweepPoint) -> Option<f64> {
        p.result
            .as_ref()
            .ok()
            .filter(|x| x.admissible)
            .map(|x| x.cost)
    }

    fn range(&self) -> (f64, f64) {
        let (lo, hi) = self
            .points
            .iter()
            .filter_map(Self::cost)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), c| {
                (l.min(c), h.max(c))
            });
        if lo.is_finite() && hi > lo {
            (lo, hi)
        } else if lo.is_finite() {
            (lo - 0.5, lo + 0.5)
        } else {
            (0.0, 1.0)
        }
    }

    /// A cell's half width along an axis (half the spacing; 0.05 for a single value).
    fn half(values: &[f64]) -> f64 {
        match values {
            [a, b, ..] => 0.5 * (b - a).abs(),
            _ => 0.05,
        }
    }
}

const NAMES: [&str; 3] = ["target x (m)", "target y (m)", "target θ (rad)"];

impl Figure for SweepFigure<'_> {
    fn size(&self) -> (u32, u32) {
        let w = Y_LABELS + PANEL + RIGHT + BAR_GAP + BAR_WIDTH + BAR_LABELS + MARGIN;
        let h = 2.0 * MARGIN + TITLE_HEIGHT + PANEL + X_LABELS;
        (w.round() as u32, h.round() as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, scale: f64) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let k = Scale(scale);
        let (a, b) = self.axes();
        // The lattice's third axis, held at its (first) value, and the horizon.
        let held = (0..3).find(|&i| i != a && i != b).unwrap_or(2);
        let unit = if held == 2 { "rad" } else { "m" };
        let value = self.lattice.axes[held].first().copied().unwrap_or(0.0);
        let title = format!(
            "Cost J of the cheapest admissible gait, per target ({} = {} {unit}, T = {} s)",
            ["x", "y", "θ"][held],
            minus(&format!("{value}")),
            self.horizon
        );
        let top = draw_heading(root, k, &title, &[], PANEL)?;
        let (va, vb) = (&self.lattice.axes[a], &self.lattice.axes[b]);
        let (ha, hb) = (Self::half(va), Self::half(vb));
        let span = |v: &[f64], h: f64| {
            let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (lo - h, hi + h)
        };
        let area = root.clone().shrink(
            (0, k.px(top)),
            (k.u(Y_LABELS + PANEL + RIGHT), k.u(PANEL + X_LABELS)),
        );
        let mut axes = Axes::new(span(va, ha), span(vb, hb), NAMES[a], NAMES[b]);
        axes.top = 0.0;
        axes.grid = false;
        let mut chart = axes.build(&area, k)?;
        let (lo, hi) = self.range();
        let colour = |c: Option<f64>| c.map_or(MISSING, |c| viridis((c - lo) / (hi - lo)));
        for p in self.points {
            let (u, v) = (p.target[a], p.target[b]);
            let p0 = chart.backend_coord(&(u - ha, v + hb));
            let p1 = chart.backend_coord(&(u + ha, v - hb));
            root.draw(&Rectangle::new(
                [p0, (p1.0 + k.px(1.0), p1.1 + k.px(1.0))],
                colour(Self::cost(p)).filled(),
            ))?;
        }
        axes.decorate(&area, &mut chart, k)?;
        // Colour bar beside the plot, J increasing upwards.
        let (_, right) = span(va, ha);
        let (bottom, upper) = span(vb, hb);
        let (px, top) = chart.backend_coord(&(right, upper));
        // Room above the bar for its label.
        let py0 = top + k.px(BAR_TITLE);
        let (_, py1) = chart.backend_coord(&(right, bottom));
        let bx = px + k.px(BAR_GAP);
        let bw = k.px(BAR_WIDTH);
        let height = (py1 - py0) as f64;
        for s in 0..BAR_STEPS {
            let f = (s as f64 + 0.5) / BAR_STEPS as f64;
            let t = py0 + (height * (BAR_STEPS - 1 - s) as f64 / BAR_STEPS as f64).round() as i32;
            let u = py0 + (height * (BAR_STEPS - s) as f64 / BAR_STEPS as f64).round() as i32;
            root.draw(&Rectangle::new(
                [(bx, t), (bx + bw, u)],
                viridis(f).filled(),
            ))?;
        }
        root.draw(&Rectangle::new(
            [(bx, py0), (bx + bw, py1)],
            k.line(INK, 2.0),
        ))?;
        let fmt = tick_formatter((lo, hi));
        for v in round_ticks((lo, hi)) {
            let y = py0 + ((hi - v) / (hi - lo) * height).round() as i32;
            colour_bar_tick(root, k, bx + bw, y, fmt(v))?;
        }
        root.draw(&Text::new(
            "J (rad²/s)",
            (bx, top),
            k.font(TICK_FONT, HPos::Left, VPos::Top),
        ))?;
        Ok(())
    }
}
