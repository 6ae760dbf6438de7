//! Figures in a plane whose axes share units, drawn with equal aspect: the shape loop
//! `(α1, α2)` and the swimmer in `(x, y)`. [`Overlay`] (paths with arrows, a square bound,
//! highlighted stretches, marks) is also what the field figure draws over its colours.

use super::axes::{Axes, bounds, equal_aspect};
use super::render::{DrawResult, Figure};
use super::style::*;
use super::time::Mark;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

/// A path with arrowheads showing its direction of travel.
pub struct Path {
    /// Legend label.
    pub label: String,
    /// Colour.
    pub color: RGBColor,
    /// Points in data coordinates.
    pub points: Vec<(f64, f64)>,
    /// Number of arrowheads along it.
    pub arrows: usize,
}

/// A square bound `|x|, |y| ≤ value`, dashed (a joint limit, or where the links overlap).
pub struct Square {
    /// Half its side, in data coordinates.
    pub value: f64,
    /// Legend label.
    pub label: String,
    /// Colour of the dashes.
    pub color: RGBColor,
    /// Always in view (else only the sides the data comes near).
    pub whole: bool,
}

/// Stretches of the paths drawn over them, wider and in another colour (steps on the joint
/// limit), with one legend entry.
pub struct Stretches {
    /// Legend label.
    pub label: String,
    /// Colour.
    pub color: RGBColor,
    /// Line width (unscaled pixels).
    pub width: f64,
    /// Polylines in data coordinates (a single point is drawn as a dot).
    pub lines: Vec<Vec<(f64, f64)>>,
}

/// What is drawn over the data area of a plane figure.
#[derive(Default)]
pub struct Overlay {
    /// Paths.
    pub paths: Vec<Path>,
    /// A square bound.
    pub limit: Option<Square>,
    /// Highlighted stretches of the paths (none if empty).
    pub stretches: Option<Stretches>,
    /// Marks (start, end).
    pub marks: Vec<Mark>,
}

impl Overlay {
    /// Legend entries of the overlay.
    pub fn legend(&self) -> Vec<(Key, String)> {
        let mut out: Vec<(Key, String)> = self
            .paths
            .iter()
            .map(|p| (Key::Line(p.color), p.label.clone()))
            .collect();
        if let Some(s) = self.stretches.as_ref().filter(|s| !s.lines.is_empty()) {
            out.push((Key::Wide(s.color, s.width), s.label.clone()));
        }
        if let Some(l) = &self.limit {
            out.push((Key::Dashed(l.color), l.label.clone()));
        }
        for m in &self.marks {
            if let Some(label) = &m.label {
                out.push((Key::Mark(m.marker, m.color), label.clone()));
            }
        }
        out
    }

    /// The bounding box of the paths and marks: `(x range, y range)`.
    pub fn data_bounds(&self) -> [(f64, f64); 2] {
        let xs = self.paths.iter().flat_map(|p| p.points.iter().map(|q| q.0));
        let ys = self.paths.iter().flat_map(|p| p.points.iter().map(|q| q.1));
        let mx = self.marks.iter().map(|m| m.at.0);
        let my = self.marks.iter().map(|m| m.at.1);
        [bounds(xs.chain(mx), 0.0), bounds(ys.chain(my), 0.0)]
    }

    /// Draws the limit, the paths with their arrows and the stretches on `chart` (`halo`: a
    /// white line under each path and the limit's dashes, for contrast on colours); [`Overlay::draw_marks`] draws
    /// the marks.
    pub fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        chart: &Chart<'_, DB>,
        k: Scale,
        halo: bool,
    ) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let (xr, yr) = (chart.x_range(), chart.y_range());
        if let Some(square) = &self.limit {
            // The sides of the square that fall inside the view, dashed.
            let l = square.value;
            let dash = (xr.end - xr.start).max(yr.end - yr.start) / 90.0;
            let (x0, x1) = (xr.start.max(-l), xr.end.min(l));
            let (y0, y1) = (yr.start.max(-l), yr.end.min(l));
            let mut lines = Vec::new();
            for s in [-1.0, 1.0] {
                let v = s * l;
                if xr.contains(&v) && y0 < y1 {
                    lines.push(((v, y0), (v, y1)));
                }
                if yr.contains(&v) && x0 < x1 {
                    lines.push(((x0, v), (x1, v)));
                }
            }
            for (a, b) in lines {
                if halo {
                    chart
                        .plotting_area()
                        .draw(&PathElement::new(vec![a, b], k.line(WHITE, LINE + 1.0)))?;
                }
                let len = (b.0 - a.0).hypot(b.1 - a.1);
                let n = (len / dash).ceil() as usize;
                for i in (0..n).step_by(2) {
                    let f0 = i as f64 / n as f64;
                    let f1 = ((i + 1) as f64 / n as f64).min(1.0);
                    let at = |f: f64| (a.0 + f * (b.0 - a.0), a.1 + f * (b.1 - a.1));
                    chart.plotting_area().draw(&PathElement::new(
                        vec![at(f0), at(f1)],
                        k.line(square.color, LINE - 1.0),
                    ))?;
                }
            }
        }
        for p in &self.paths {
            if halo {
                chart.plotting_area().draw(&PathElement::new(
                    p.points.clone(),
                    k.line(WHITE, 3.0 * LINE),
                ))?;
            }
            chart
                .plotting_area()
                .draw(&PathElement::new(p.points.clone(), k.line(p.color, LINE)))?;
            draw_arrows(root, chart, k, &p.points, p.arrows, p.color)?;
        }
        if let Some(s) = &self.stretches {
            for line in &s.lines {
                if let [p] = line[..] {
                    let r = k.px(s.width / 2.0);
                    root.draw(&Circle::new(chart.backend_coord(&p), r, s.color.filled()))?;
                } else {
                    chart
                        .plotting_area()
                        .draw(&PathElement::new(line.clone(), k.line(s.color, s.width)))?;
                }
            }
        }
        Ok(())
    }

    /// Draws the marks (over everything else).
    pub fn draw_marks<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        chart: &Chart<'_, DB>,
        k: Scale,
    ) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        for m in &self.marks {
            let at = chart.backend_coord(&m.at);
            draw_marker(root, k, at, m.marker, m.color, 14.0)?;
        }
        Ok(())
    }
}

/// Polylines drawn over the paths, without arrows (the swimmer's links), each
/// `(points, colour)`, and the legend entries that explain them.
#[derive(Default)]
pub struct Drawing {
    /// Polylines.
    pub lines: Vec<(Vec<(f64, f64)>, RGBColor)>,
    /// Their legend entries.
    pub legend: Vec<(Key, String)>,
    /// Text beside points (a snapshot's time).
    pub labels: Vec<((f64, f64), String)>,
}

/// Size of [`Drawing::labels`]' text.
const NOTE_FONT: f64 = 28.0;

/// A plane figure with equal aspect.
pub struct PlaneFigure {
    /// Title.
    pub title: String,
    /// x description.
    pub x_desc: String,
    /// y description.
    pub y_desc: String,
    /// Drawn over the overlay.
    pub drawing: Drawing,
    /// Limit, paths and marks.
    pub overlay: Overlay,
    /// The view `(x range, y range)`; [`PlaneFigure::new`] sets it from the data.
    pub view: [(f64, f64); 2],
    /// Height of the plotting area (its width is fixed).
    plot_height: f64,
}

/// Width of a plane figure's plotting area.
const PLOT_WIDTH: f64 = WIDTH as f64 - Y_LABELS - RIGHT;

impl PlaneFigure {
    /// A figure of `drawing` and `overlay`, viewing their data padded by 6 %, and the limit
    /// square: whole if [`Square::whole`], else the sides that the data comes within a
    /// quarter of its span of.
    pub fn new(
        title: String,
        (x_desc, y_desc): (String, String),
        drawing: Drawing,
        overlay: Overlay,
    ) -> Self {
        let [mut x, mut y] = overlay.data_bounds();
        let dx = drawing.lines.iter().flat_map(|l| l.0.iter().map(|p| p.0));
        let dy = drawing.lines.iter().flat_map(|l| l.0.iter().map(|p| p.1));
        if !drawing.lines.is_empty() {
            let (bx, by) = (bounds(dx, 0.0), bounds(dy, 0.0));
            x = (x.0.min(bx.0), x.1.max(bx.1));
            y = (y.0.min(by.0), y.1.max(by.1));
        }
        if let Some(square) = &overlay.limit {
            let l = square.value;
            for r in [&mut x, &mut y] {
                let near = if square.whole {
                    f64::INFINITY
                } else {
                    0.25 * (r.1 - r.0)
                };
                if r.1 + near >= l {
                    r.1 = r.1.max(l);
                }
                if r.0 - near <= -l {
                    r.0 = r.0.min(-l);
                }
            }
        }
        let aspect = ((y.1 - y.0) / (x.1 - x.0).max(1e-12)).clamp(0.45, 1.0);
        let plot_height = (PLOT_WIDTH * aspect).round();
        let view = equal_aspect(x, y, (PLOT_WIDTH, plot_height), 0.06);
        PlaneFigure {
            title,
            x_desc,
            y_desc,
            drawing,
            overlay,
            view,
            plot_height,
        }
    }

    fn legend(&self) -> Vec<(Key, String)> {
        let mut l = self.overlay.legend();
        l.extend(self.drawing.legend.iter().cloned());
        l
    }
}

impl Figure for PlaneFigure {
    fn size(&self) -> (u32, u32) {
        let legend = legend_height(PLOT_WIDTH, &self.legend());
        let h = 2.0 * MARGIN + TITLE_HEIGHT + legend + 8.0 + self.plot_height + X_LABELS;
        (WIDTH, h.round() as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, scale: f64) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let k = Scale(scale);
        let top = draw_heading(root, k, &self.title, &self.legend(), PLOT_WIDTH)?;
        let mut axes = Axes::new(self.view[0], self.view[1], &self.x_desc, &self.y_desc);
        axes.top = top + 8.0;
        let (w, h) = self.size();
        let area = root
            .clone()
            .shrink((0, 0), (k.u(w as f64), k.u(h as f64 - MARGIN)));
        let mut chart = axes.build(&area, k)?;
        axes.decorate(&area, &mut chart, k)?;
        self.overlay.draw(root, &chart, k, false)?;
        self.overlay.draw_marks(root, &chart, k)?;
        for (points, color) in &self.drawing.lines {
            chart
                .plotting_area()
                .draw(&PathElement::new(points.clone(), k.line(*color, LINE)))?;
        }
        for (at, text) in &self.drawing.labels {
            let (x, y) = chart.backend_coord(at);
            root.draw(&Text::new(
                text.clone(),
                (x + k.px(10.0), y - k.px(10.0)),
                k.font(NOTE_FONT, HPos::Left, VPos::Bottom),
            ))?;
        }
        Ok(())
    }
}
