//! The figures' common look: sizes, colours, axes with a frame, legends above the data,
//! arrows along a path, start and end markers, tick labels, equal-aspect ranges.
//!
//! Every size is in pixels of the SVG (a 1 500-pixel-wide canvas) and is multiplied by the
//! scale a figure is drawn at (see `render`).

use super::render::{DrawResult, FAMILY, text_width};
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Width of a one-panel figure.
pub const WIDTH: u32 = 1500;
/// Font sizes (plotters' size: the SVG font-size is this over 1.24).
pub const TITLE_FONT: f64 = 46.0;
/// Axis descriptions.
pub const LABEL_FONT: f64 = 42.0;
/// Tick labels and legend entries.
pub const TICK_FONT: f64 = 38.0;
/// Outer margin.
pub const MARGIN: f64 = 24.0;
/// Height of the title line.
pub const TITLE_HEIGHT: f64 = 56.0;
/// Height of one legend row.
pub const LEGEND_ROW: f64 = 48.0;
/// Left label area (tick labels and the rotated axis description).
pub const Y_LABELS: f64 = 150.0;
/// Bottom label area.
pub const X_LABELS: f64 = 100.0;
/// Space left of the y description, within [`Y_LABELS`].
pub const LEFT_PAD: f64 = 12.0;
/// Right margin of a plot.
pub const RIGHT: f64 = 40.0;
/// Data lines.
pub const LINE: f64 = 4.0;
/// Legend: width of a line sample, gap to its label, space between entries.
pub const LEGEND_SAMPLE: f64 = 56.0;
/// See [`LEGEND_SAMPLE`].
pub const LEGEND_GAP: f64 = 14.0;
/// See [`LEGEND_SAMPLE`].
pub const LEGEND_PAD: f64 = 40.0;

/// Okabe–Ito colours (distinguishable with any colour vision).
pub const BLUE: RGBColor = RGBColor(0, 114, 178);
/// Vermillion.
pub const VERMILLION: RGBColor = RGBColor(213, 94, 0);
/// Bluish green.
pub const GREEN: RGBColor = RGBColor(0, 158, 115);
/// Orange.
pub const ORANGE: RGBColor = RGBColor(230, 159, 0);
/// Reddish purple.
pub const PURPLE: RGBColor = RGBColor(204, 121, 167);
/// Sky blue.
pub const SKY: RGBColor = RGBColor(86, 180, 233);
/// Near black, for the frame, text and reference lines.
pub const INK: RGBColor = RGBColor(25, 25, 25);
/// Grid lines.
pub const GRID: RGBColor = RGBColor(225, 225, 225);
/// Where the links overlap (`|α_i| = π`), and other reference bounds.
pub const LIMIT: RGBColor = RGBColor(120, 120, 120);
/// A joint limit `|α_i| ≤ α_max` (dashed like [`LIMIT`], darker, so the two never look alike).
pub const JOINT_LIMIT: RGBColor = INK;

/// How the arcs (states on the joint limit) are marked in every figure: stretches of a path
/// drawn [`ON_LIMIT_LINE`] wide in [`ON_LIMIT`] in the planes, time spans shaded in
/// [`ON_LIMIT_SHADE`] over time, both labelled [`ON_LIMIT_LABEL`].
pub const ON_LIMIT: RGBColor = PURPLE;
/// See [`ON_LIMIT`].
pub const ON_LIMIT_SHADE: RGBColor = RGBColor(237, 208, 224);
/// See [`ON_LIMIT`].
pub const ON_LIMIT_LINE: f64 = 3.0 * LINE;
/// See [`ON_LIMIT`].
pub const ON_LIMIT_LABEL: &str = "on the limit";
/// Narrowest shaded span (pixels, unscaled): an arc of a few steps stays visible.
pub const ON_LIMIT_MIN_SPAN: f64 = 6.0;

/// A plotting chart in data coordinates.
pub type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// The scale a figure is drawn at, and sizes scaled by it.
#[derive(Clone, Copy, Debug)]
pub struct Scale(pub f64);

impl Scale {
    /// A length in pixels.
    pub fn px(&self, v: f64) -> i32 {
        (v * self.0).round() as i32
    }
    /// A (positive) size in pixels.
    pub fn u(&self, v: f64) -> u32 {
        (v * self.0).round().max(1.0) as u32
    }
    /// The family at `size`, anchored at `(h, v)`.
    pub fn font(&self, size: f64, h: HPos, v: VPos) -> TextStyle<'static> {
        (FAMILY, size * self.0)
            .into_font()
            .color(&INK)
            .pos(Pos::new(h, v))
    }
    /// A line style.
    pub fn line(&self, color: RGBColor, width: f64) -> ShapeStyle {
        color.stroke_width(self.u(width))
    }
}

/// What a legend entry shows beside its label.
#[derive(Clone, Copy, Debug)]
pub enum Key {
    /// A line sample.
    Line(RGBColor),
    /// A dashed line sample.
    Dashed(RGBColor),
    /// A line sample of a given width (unscaled pixels).
    Wide(RGBColor, f64),
    /// A filled box: a shaded span.
    Band(RGBColor),
    /// A marker.
    Mark(Marker, RGBColor),
}

/// Marker shapes.
#[derive(Clone, Copy, Debug)]
pub enum Marker {
    /// Filled circle with a dark edge: a start.
    Circle,
    /// Filled square with a dark edge: an end or a target.
    Square,
    /// Filled diamond with a dark edge, fitting inside the square: a second target.
    Diamond,
    /// A cross: where something failed.
    Cross,
}

/// Draws `marker` centred at pixel `p`, of half-size `r` (unscaled).
pub fn draw_marker<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    k: Scale,
    p: (i32, i32),
    marker: Marker,
    color: RGBColor,
    r: f64,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let r = k.px(r);
    match marker {
        Marker::Circle => {
            root.draw(&Circle::new(p, r, color.filled()))?;
            root.draw(&Circle::new(p, r, k.line(INK, 2.0)))?;
        }
        Marker::Square => {
            let rect = [(p.0 - r, p.1 - r), (p.0 + r, p.1 + r)];
            root.draw(&Rectangle::new(rect, color.filled()))?;
            root.draw(&Rectangle::new(rect, k.line(INK, 2.0)))?;
        }
        Marker::Diamond => {
            let d = vec![
                (p.0, p.1 - r),
                (p.0 + r, p.1),
                (p.0, p.1 + r),
                (p.0 - r, p.1),
            ];
            root.draw(&Polygon::new(d.clone(), color.filled()))?;
            let mut outline = d.clone();
            outline.push(d[0]);
            root.draw(&PathElement::new(outline, k.line(INK, 2.0)))?;
        }
        Marker::Cross => {
            for (a, b) in [((-r, -r), (r, r)), ((-r, r), (r, -r))] {
                let seg = vec![(p.0 + a.0, p.1 + a.1), (p.0 + b.0, p.1 + b.1)];
                root.draw(&PathElement::new(seg, k.line(color, 5.0)))?;
            }
        }
    }
    Ok(())
}

/// Where [`draw_legend`] puts each entry (unscaled offsets from its top left to the entry's
/// vertical centre) within `width` unscaled pixels, and the height it takes. Laid out at
/// scale 1 so that the SVG and the PNG wrap alike.
fn legend_layout(width: f64, entries: &[(Key, String)]) -> (Vec<(f64, f64)>, f64) {
    let (mut cx, mut cy) = (0.0, LEGEND_ROW / 2.0);
    let mut at = Vec::new();
    for (_, label) in entries {
        let w = LEGEND_SAMPLE + LEGEND_GAP + text_width(label, TICK_FONT);
        if cx > 0.0 && cx + w > width {
            cx = 0.0;
            cy += LEGEND_ROW;
        }
        at.push((cx, cy));
        cx += w + LEGEND_PAD;
    }
    (
        at,
        if entries.is_empty() {
            0.0
        } else {
            cy + LEGEND_ROW / 2.0
        },
    )
}

/// Height of the legend [`draw_legend`] draws in `width` pixels (unscaled).
pub fn legend_height(width: f64, entries: &[(Key, String)]) -> f64 {
    legend_layout(width, entries).1
}

/// Draws a legend as rows of entries from `(x, y)` (top left), wrapping at `width` (all
/// unscaled pixels).
pub fn draw_legend<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    k: Scale,
    (x, y): (f64, f64),
    width: f64,
    entries: &[(Key, String)],
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let style = k.font(TICK_FONT, HPos::Left, VPos::Center);
    let (sample, gap) = (k.px(LEGEND_SAMPLE), k.px(LEGEND_GAP));
    let (at, _) = legend_layout(width, entries);
    for ((key, label), (dx, dy)) in entries.iter().zip(at) {
        let (cx, cy) = (k.px(x + dx), k.px(y + dy));
        match *key {
            Key::Line(c) => {
                let seg = vec![(cx, cy), (cx + sample, cy)];
                root.draw(&PathElement::new(seg, k.line(c, LINE + 1.0)))?;
            }
            Key::Dashed(c) => {
                let dash = sample / 5;
                for i in [0, 2, 4] {
                    let seg = vec![(cx + i * dash, cy), (cx + (i + 1) * dash, cy)];
                    root.draw(&PathElement::new(seg, k.line(c, LINE - 1.0)))?;
                }
            }
            Key::Wide(c, width) => {
                let seg = vec![(cx, cy), (cx + sample, cy)];
                root.draw(&PathElement::new(seg, k.line(c, width)))?;
            }
            Key::Band(c) => {
                let h = k.px(14.0);
                let rect = [(cx, cy - h), (cx + sample, cy + h)];
                root.draw(&Rectangle::new(rect, c.filled()))?;
            }
            Key::Mark(m, c) => draw_marker(root, k, (cx + sample / 2, cy), m, c, 12.0)?,
        }
        root.draw(&Text::new(
            label.clone(),
            (cx + sample + gap, cy),
            style.clone(),
        ))?;
    }
    Ok(())
}

/// Clears `root`, draws the title at its top left and `legend` (if any) under it, from the
/// left of the plots and `width` wide; returns where the content below starts (unscaled).
pub fn draw_heading<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    k: Scale,
    title: &str,
    legend: &[(Key, String)],
    width: f64,
) -> Result<f64, Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let style = k.font(TITLE_FONT, HPos::Left, VPos::Top);
    root.draw(&Text::new(
        title.to_string(),
        (k.px(MARGIN), k.px(MARGIN)),
        style,
    ))?;
    let top = MARGIN + TITLE_HEIGHT;
    draw_legend(root, k, (Y_LABELS, top), width, legend)?;
    Ok(top + legend_height(width, legend))
}

/// Axes of a plot: where the plotting area sits in its drawing area and what it shows.
pub struct Axes<'a> {
    /// x range.
    pub x: (f64, f64),
    /// y range.
    pub y: (f64, f64),
    /// x description.
    pub x_desc: &'a str,
    /// y description.
    pub y_desc: &'a str,
    /// Tick label of a y value (`None`: plain numbers).
    pub y_ticks: Option<&'a dyn Fn(f64) -> String>,
    /// Pixels above the plotting area (title, legend), unscaled.
    pub top: f64,
    /// Pixels right of it, unscaled.
    pub right: f64,
    /// Left label area, unscaled.
    pub left: f64,
    /// Bottom label area, unscaled.
    pub bottom: f64,
    /// Grid lines at the ticks.
    pub grid: bool,
}

impl Axes<'_> {
    /// Axes with the default label areas and margins.
    pub fn new<'a>(x: (f64, f64), y: (f64, f64), x_desc: &'a str, y_desc: &'a str) -> Axes<'a> {
        Axes {
            x,
            y,
            x_desc,
            y_desc,
            y_ticks: None,
            top: MARGIN,
            right: RIGHT,
            left: Y_LABELS,
            bottom: X_LABELS,
            grid: true,
        }
    }

    /// [`Axes::build`], then [`Axes::decorate`].
    pub fn draw<'b, DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        k: Scale,
    ) -> Result<Chart<'b, DB>, Box<dyn std::error::Error>>
    where
        DB::ErrorType: 'static,
    {
        let mut chart = self.build(area, k)?;
        self.decorate(area, &mut chart, k)?;
        Ok(chart)
    }

    /// The chart on `area`, nothing drawn yet.
    pub fn build<'b, DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        k: Scale,
    ) -> Result<Chart<'b, DB>, Box<dyn std::error::Error>>
    where
        DB::ErrorType: 'static,
    {
        Ok(ChartBuilder::on(area)
            .margin_top(k.u(self.top))
            .margin_right(k.u(self.right))
            // The rotated y description starts a little in from the edge.
            .margin_left(k.u(LEFT_PAD))
            .margin_bottom(0)
            .x_label_area_size(k.u(self.bottom))
            .y_label_area_size(k.u(self.left - LEFT_PAD))
            .build_cartesian_2d(self.x.0..self.x.1, self.y.0..self.y.1)?)
    }

    /// Draws the grid (if [`Axes::grid`]), ticks, labels and a full frame on the chart built
    /// on `area`.
    pub fn decorate<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        chart: &mut Chart<'_, DB>,
        k: Scale,
    ) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let x_fmt = tick_formatter(self.x);
        let y_fmt = tick_formatter(self.y);
        let y_custom = self.y_ticks;
        let y_label = move |v: &f64| match y_custom {
            Some(f) => f(*v),
            None => y_fmt(*v),
        };
        let x_label = move |v: &f64| x_fmt(*v);
        let grid = if self.grid {
            k.line(GRID, 2.0)
        } else {
            TRANSPARENT.into()
        };
        chart
            .configure_mesh()
            .light_line_style(TRANSPARENT)
            .bold_line_style(grid)
            .axis_style(k.line(INK, 2.0))
            .set_all_tick_mark_size(k.u(10.0))
            .x_labels(TICKS)
            .y_labels(TICKS)
            .label_style(k.font(TICK_FONT, HPos::Center, VPos::Top))
            .axis_desc_style(k.font(LABEL_FONT, HPos::Center, VPos::Top))
            .x_desc(self.x_desc)
            .y_desc(self.y_desc)
            .x_label_formatter(&x_label)
            .y_label_formatter(&y_label)
            .draw()?;
        // The frame in pixels of `area`: drawn on the plotting area it would be clipped.
        let base = area.get_base_pixel();
        let at = |p: (f64, f64)| {
            let (x, y) = chart.backend_coord(&p);
            (x - base.0, y - base.1)
        };
        let (x, y) = (self.x, self.y);
        area.draw(&Rectangle::new(
            [at((x.0, y.1)), at((x.1, y.0))],
            k.line(INK, 2.0),
        ))?;
        Ok(())
    }
}

/// One tick of a colour bar whose right edge is at `x`: a mark at height `y` and its label.
pub fn colour_bar_tick<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    k: Scale,
    x: i32,
    y: i32,
    label: String,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    root.draw(&PathElement::new(
        vec![(x, y), (x + k.px(10.0), y)],
        k.line(INK, 2.0),
    ))?;
    root.draw(&Text::new(
        label,
        (x + k.px(16.0), y),
        k.font(TICK_FONT, HPos::Left, VPos::Center),
    ))?;
    Ok(())
}

/// Labels per axis (at most).
pub const TICKS: usize = 7;

/// Tick labels with the decimals plotters' tick step over `range` needs (it steps by 1, 2
/// or 5 times a power of ten, at most [`TICKS`] labels), and a true minus sign.
pub fn tick_formatter((lo, hi): (f64, f64)) -> impl Fn(f64) -> String {
    let (lo, hi) = (lo.min(hi), lo.max(hi));
    let mut step = 10f64.powf((hi - lo).max(1e-300).log10().floor() - 2.0);
    for m in [2.0, 2.5, 2.0].iter().cycle().take(60) {
        // The smallest step whose multiples inside the range are few enough.
        if (hi / step).floor() - (lo / step).ceil() + 1.0 <= TICKS as f64 {
            break;
        }
        step *= m;
    }
    let decimals = (-(step.log10() + 1e-9).floor()).max(0.0) as usize;
    move |v| {
        minus(&format!(
            "{:.*}",
            decimals,
            if v.abs() < 1e-9 * step { 0.0 } else { v }
        ))
    }
}

/// `s` with `-` written as the minus sign `−`.
pub fn minus(s: &str) -> String {
    s.replace('-', "−")
}

/// `10ⁿ` for a whole `n`, nothing otherwise (tick labels of a log10 axis).
pub fn power_of_ten(v: f64) -> String {
    let n = v.round();
    if (v - n).abs() > 1e-9 {
        return String::new();
    }
    const SUP: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let digits: String = (n.abs() as i64)
        .to_string()
        .chars()
        .map(|c| SUP[c.to_digit(10).unwrap_or(0) as usize])
        .collect();
    format!("10{}{digits}", if n < 0.0 { "⁻" } else { "" })
}

/// Data ranges around `(x, y)` (each `(lo, hi)`, padded by `pad` of the larger span) whose
/// units per pixel are equal on a `w × h`-pixel plotting area: the smaller span is widened.
pub fn equal_aspect(x: (f64, f64), y: (f64, f64), (w, h): (f64, f64), pad: f64) -> [(f64, f64); 2] {
    let (cx, cy) = (0.5 * (x.0 + x.1), 0.5 * (y.0 + y.1));
    let span = (x.1 - x.0).max(1e-12).max((y.1 - y.0) * w / h);
    let per_px = span * (1.0 + 2.0 * pad) / w;
    let (hw, hh) = (0.5 * per_px * w, 0.5 * per_px * h);
    [(cx - hw, cx + hw), (cy - hh, cy + hh)]
}

/// `(lo, hi)` of some values, padded by `pad` of the span on each side.
pub fn bounds(values: impl Iterator<Item = f64>, pad: f64) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if !lo.is_finite() || !hi.is_finite() {
        return (-1.0, 1.0);
    }
    let span = (hi - lo).max(1e-9 * hi.abs().max(1.0));
    (lo - pad * span, hi + pad * span)
}

/// Draws `count` filled arrowheads along a polyline (data coordinates), evenly spaced in
/// pixel arc length and pointing along it.
pub fn draw_arrows<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &Chart<'_, DB>,
    k: Scale,
    path: &[(f64, f64)],
    count: usize,
    color: RGBColor,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let px: Vec<(f64, f64)> = path
        .iter()
        .map(|p| {
            let (x, y) = chart.backend_coord(p);
            (x as f64, y as f64)
        })
        .collect();
    let mut lengths = vec![0.0];
    for w in px.windows(2) {
        let d = ((w[1].0 - w[0].0).powi(2) + (w[1].1 - w[0].1).powi(2)).sqrt();
        lengths.push(lengths.last().copied().unwrap_or(0.0) + d);
    }
    let total = lengths.last().copied().unwrap_or(0.0);
    if total <= 0.0 || count == 0 {
        return Ok(());
    }
    let (len, half) = (k.0 * 30.0, k.0 * 13.0);
    let mut i = 0;
    for a in 0..count {
        let s = total * (a as f64 + 0.5) / count as f64;
        while i + 1 < lengths.len() && lengths[i + 1] < s {
            i += 1;
        }
        // Direction from a chord a little either side, so pixel noise does not tilt it.
        let before = px[lengths
            .iter()
            .position(|&l| l >= s - len)
            .unwrap_or(0)
            .min(i)];
        let after = px[lengths
            .iter()
            .position(|&l| l >= s + len)
            .unwrap_or(px.len() - 1)];
        let (dx, dy) = (after.0 - before.0, after.1 - before.1);
        let n = (dx * dx + dy * dy).sqrt();
        if n == 0.0 {
            continue;
        }
        let (ux, uy) = (dx / n, dy / n);
        let t = (s - lengths[i]) / (lengths[(i + 1).min(lengths.len() - 1)] - lengths[i]).max(1e-9);
        let j = (i + 1).min(px.len() - 1);
        let c = (
            px[i].0 + t * (px[j].0 - px[i].0),
            px[i].1 + t * (px[j].1 - px[i].1),
        );
        let tip = (c.0 + 0.5 * len * ux, c.1 + 0.5 * len * uy);
        let base = (c.0 - 0.5 * len * ux, c.1 - 0.5 * len * uy);
        let tri = vec![
            (tip.0 as i32, tip.1 as i32),
            ((base.0 - half * uy) as i32, (base.1 + half * ux) as i32),
            ((base.0 + half * uy) as i32, (base.1 - half * ux) as i32),
        ];
        root.draw(&Polygon::new(tri, color.filled()))?;
    }
    Ok(())
}

/// A diverging colour (blue, white, red after ColorBrewer's RdBu) for `t ∈ [−1, 1]`.
pub fn diverging(t: f64) -> RGBColor {
    const STOPS: [(u8, u8, u8); 11] = [
        (5, 48, 97),
        (33, 102, 172),
        (67, 147, 195),
        (146, 197, 222),
        (209, 229, 240),
        (247, 247, 247),
        (253, 219, 199),
        (244, 165, 130),
        (214, 96, 77),
        (178, 24, 43),
        (103, 0, 31),
    ];
    let x = (t.clamp(-1.0, 1.0) + 1.0) * 5.0;
    let i = (x.floor() as usize).min(9);
    let f = x - i as f64;
    let mix = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_aspect_gives_equal_units_per_pixel() {
        for (x, y, wh) in [
            ((0.0, 1.0), (0.0, 3.0), (800.0, 600.0)),
            ((-5.0, 5.0), (1.0, 1.5), (1200.0, 400.0)),
        ] {
            let [rx, ry] = equal_aspect(x, y, wh, 0.05);
            let (ux, uy) = ((rx.1 - rx.0) / wh.0, (ry.1 - ry.0) / wh.1);
            assert!((ux / uy - 1.0).abs() < 1e-12);
            assert!(rx.0 <= x.0 && rx.1 >= x.1 && ry.0 <= y.0 && ry.1 >= y.1);
        }
    }

    #[test]
    fn axes_put_the_plotting_area_where_the_layouts_assume() {
        // Figures size their canvas from these sums (equal aspect depends on it).
        let mut svg = String::new();
        let (w, h) = (1500u32, 900u32);
        let area = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
        let mut axes = Axes::new((0.0, 1.0), (0.0, 1.0), "x", "y");
        axes.top = 70.0;
        for scale in [1.0, 3.0] {
            let chart = axes.build(&area, Scale(scale)).unwrap();
            let k = Scale(scale);
            let want = (
                w as i32 - k.px(axes.left) - k.px(axes.right),
                h as i32 - k.px(axes.top) - k.px(axes.bottom),
            );
            let (pw, ph) = chart.plotting_area().dim_in_pixel();
            assert_eq!((pw as i32, ph as i32), want, "scale {scale}");
        }
    }

    #[test]
    fn tick_labels() {
        let f = tick_formatter((-0.1, 0.35));
        assert_eq!(f(-0.1), "−0.1");
        assert_eq!(tick_formatter((0.1, 3.3))(0.5), "0.5");
        assert_eq!(tick_formatter((0.0, 0.6))(0.2), "0.2");
        assert_eq!(tick_formatter((0.0, 100.0))(40.0), "40");
        assert_eq!(power_of_ten(-8.0), "10⁻⁸");
        assert_eq!(power_of_ten(2.0), "10²");
        assert_eq!(power_of_ten(-7.5), "");
    }
}
