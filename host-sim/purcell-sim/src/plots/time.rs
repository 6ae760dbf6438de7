//! Quantities over time: one or more panels stacked over a shared time axis, each with its
//! legend above it, reference levels (joint limits, targets), shaded time spans (steps on the
//! joint limit) and marks.

use super::axes::{Axes, bounds, power_of_ten};
use super::render::{DrawResult, Figure};
use super::style::*;
use plotters::coord::Shift;
use plotters::prelude::*;

/// One curve.
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Colour.
    pub color: RGBColor,
    /// `(t, value)` points.
    pub points: Vec<(f64, f64)>,
}

/// A horizontal reference line (a joint limit, a target value).
pub struct Level {
    /// Its value.
    pub y: f64,
    /// Legend label (`None`: drawn without an entry, e.g. the second of a ± pair).
    pub label: Option<String>,
    /// Colour.
    pub color: RGBColor,
}

/// A single marked point.
pub struct Mark {
    /// Where.
    pub at: (f64, f64),
    /// Shape.
    pub marker: Marker,
    /// Fill colour.
    pub color: RGBColor,
    /// Legend label (`None`: no entry).
    pub label: Option<String>,
}

/// Time spans shaded behind the curves, with one legend entry.
pub struct Spans {
    /// `(t0, t1)` of each span, seconds; each drawn at least [`ARC_MIN_SPAN`] wide.
    pub spans: Vec<(f64, f64)>,
    /// Fill colour.
    pub color: RGBColor,
    /// Legend label.
    pub label: String,
}

/// One panel.
pub struct Panel {
    /// y-axis description, with units.
    pub y_desc: String,
    /// Curves.
    pub series: Vec<Series>,
    /// Reference lines.
    pub levels: Vec<Level>,
    /// Marked points.
    pub marks: Vec<Mark>,
    /// Shaded time spans (none if empty).
    pub spans: Option<Spans>,
    /// Values are `log10` of the quantity (ticks labelled `10ⁿ`).
    pub log10: bool,
}

impl Panel {
    /// A linear panel with curves only.
    pub fn new(y_desc: impl Into<String>, series: Vec<Series>) -> Self {
        Panel {
            y_desc: y_desc.into(),
            series,
            levels: Vec::new(),
            marks: Vec::new(),
            spans: None,
            log10: false,
        }
    }

    fn legend(&self) -> Vec<(Key, String)> {
        let mut out: Vec<(Key, String)> = self
            .series
            .iter()
            .map(|s| (Key::Line(s.color), s.label.clone()))
            .collect();
        for l in &self.levels {
            if let Some(label) = &l.label {
                out.push((Key::Dashed(l.color), label.clone()));
            }
        }
        if let Some(s) = self.spans.as_ref().filter(|s| !s.spans.is_empty()) {
            out.push((Key::Band(s.color), s.label.clone()));
        }
        for m in &self.marks {
            if let Some(label) = &m.label {
                out.push((Key::Mark(m.marker, m.color), label.clone()));
            }
        }
        out
    }

    /// The y range: the data, the levels and the marks, padded.
    fn y_range(&self) -> (f64, f64) {
        let values = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p.1))
            .chain(self.levels.iter().map(|l| l.y))
            .chain(self.marks.iter().map(|m| m.at.1));
        let (lo, hi) = bounds(values, 0.05);
        if self.log10 {
            (lo.floor(), hi.ceil())
        } else {
            (lo, hi)
        }
    }
}

/// Panels over a shared time axis.
pub struct TimeFigure {
    /// Title.
    pub title: String,
    /// Time range, seconds.
    pub t: (f64, f64),
    /// Panels, top to bottom.
    pub panels: Vec<Panel>,
}

/// Height of each panel's plotting area.
const PLOT_HEIGHT: f64 = 560.0;
/// Space between a legend and its plot.
const LEGEND_SPACE: f64 = 8.0;

impl TimeFigure {
    fn legend_width() -> f64 {
        WIDTH as f64 - Y_LABELS - RIGHT
    }

    /// Unscaled height of panel `i` (legend, plot, labels).
    fn panel_height(&self, i: usize) -> f64 {
        let p = &self.panels[i];
        legend_height(Self::legend_width(), &p.legend()) + LEGEND_SPACE + PLOT_HEIGHT + X_LABELS
    }
}

impl Figure for TimeFigure {
    fn size(&self) -> (u32, u32) {
        let panels: f64 = (0..self.panels.len()).map(|i| self.panel_height(i)).sum();
        (WIDTH, (2.0 * MARGIN + TITLE_HEIGHT + panels).round() as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, scale: f64) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let k = Scale(scale);
        let mut top = draw_heading(root, k, &self.title, &[], Self::legend_width())?;
        for (i, p) in self.panels.iter().enumerate() {
            let legend = p.legend();
            let lh = legend_height(Self::legend_width(), &legend);
            draw_legend(root, k, (Y_LABELS, top), Self::legend_width(), &legend)?;
            let height = self.panel_height(i);
            let area = root
                .clone()
                .shrink((0, k.px(top)), (k.u(WIDTH as f64), k.u(height)));
            let power = |v: f64| power_of_ten(v);
            let mut axes = Axes::new(self.t, p.y_range(), "t (s)", &p.y_desc);
            axes.top = lh + LEGEND_SPACE;
            if p.log10 {
                axes.y_ticks = Some(&power);
            }
            let mut chart = axes.build(&area, k)?;
            if let Some(s) = &p.spans {
                // Behind the grid and the curves.
                let (y0, y1) = axes.y;
                let left = chart.backend_coord(&(self.t.0, y1)).0;
                let right = chart.backend_coord(&(self.t.1, y1)).0;
                for &(t0, t1) in &s.spans {
                    let (a, b) = (
                        chart.backend_coord(&(t0, y1)),
                        chart.backend_coord(&(t1, y0)),
                    );
                    let widen = (k.px(ARC_MIN_SPAN) - (b.0 - a.0)).max(0);
                    let x0 = (a.0 - widen / 2).max(left);
                    let x1 = (b.0 + widen - widen / 2).min(right);
                    root.draw(&Rectangle::new([(x0, a.1), (x1, b.1)], s.color.filled()))?;
                }
            }
            axes.decorate(&area, &mut chart, k)?;
            for l in &p.levels {
                let (t0, t1) = self.t;
                let mut t = t0;
                let dash = (t1 - t0) / 80.0;
                while t < t1 {
                    let seg = vec![(t, l.y), ((t + dash).min(t1), l.y)];
                    chart
                        .plotting_area()
                        .draw(&PathElement::new(seg, k.line(l.color, LINE - 1.0)))?;
                    t += 2.0 * dash;
                }
            }
            for s in &p.series {
                chart
                    .plotting_area()
                    .draw(&PathElement::new(s.points.clone(), k.line(s.color, LINE)))?;
            }
            for m in &p.marks {
                let at = chart.backend_coord(&m.at);
                draw_marker(root, k, at, m.marker, m.color, 12.0)?;
            }
            top += height;
        }
        Ok(())
    }
}
