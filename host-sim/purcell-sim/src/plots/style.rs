//! The figures' common look: sizes, colours and colour maps, legends above the data, arrows
//! along a path, start and end markers (axes and their ticks: [`super::axes`]).
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
/// Colour bar (the field's and the sweep's maps): gap from the plot, width, room for its
/// labels.
pub const BAR_GAP: f64 = 24.0;
/// See [`BAR_GAP`].
pub const BAR_WIDTH: f64 = 36.0;
/// See [`BAR_GAP`].
pub const BAR_LABELS: f64 = 150.0;
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
/// drawn [`ARC_LINE`] wide in [`ARC`] in the planes, time spans shaded in
/// [`ARC_SHADE`] over time, both labelled [`ARC_LABEL`].
pub const ARC: RGBColor = PURPLE;
/// See [`ARC`].
pub const ARC_SHADE: RGBColor = RGBColor(237, 208, 224);
/// See [`ARC`].
pub const ARC_LINE: f64 = 3.0 * LINE;
/// See [`ARC`].
pub const ARC_LABEL: &str = "on the limit";
/// Narrowest shaded span (pixels, unscaled): an arc of a few steps stays visible.
pub const ARC_MIN_SPAN: f64 = 6.0;

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
    const STOPS: [u32; 11] = [
        0x053061, 0x2166ac, 0x4393c3, 0x92c5de, 0xd1e5f0, 0xf7f7f7, 0xfddbc7, 0xf4a582, 0xd6604d,
        0xb2182b, 0x67001f,
    ];
    piecewise(&STOPS, (t.clamp(-1.0, 1.0) + 1.0) * 5.0)
}

/// The viridis colour map at `f ∈ [0, 1]` (piecewise linear through five of its colours):
/// sequential and readable by colour-blind viewers.
pub fn viridis(f: f64) -> RGBColor {
    const STOPS: [u32; 5] = [0x440154, 0x3b528b, 0x21918c, 0x5ec962, 0xfde725];
    piecewise(&STOPS, f.clamp(0.0, 1.0) * 4.0)
}

/// The colour at `x ∈ [0, n − 1]` on the polyline through the `n` colours `stops`
/// (`0xRRGGBB`; each channel linear between neighbours, rounded).
fn piecewise(stops: &[u32], x: f64) -> RGBColor {
    let i = (x.floor() as usize).min(stops.len() - 2);
    let t = x - i as f64;
    let mix = |shift: u32| {
        let [p, q] = [stops[i], stops[i + 1]].map(|c| f64::from((c >> shift) & 0xff));
        (p + (q - p) * t).round() as u8
    };
    RGBColor(mix(16), mix(8), mix(0))
}
