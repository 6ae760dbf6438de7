//! Axes with a frame and their tick labels, colour-bar ticks, and the data ranges of a plot
//! (padded, or of equal aspect).

use super::render::DrawResult;
use super::style::*;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

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

/// The tick step over `(lo, hi)` as plotters picks it: 1, 2 or 5 times a power of ten, the
/// smallest with at most [`TICKS`] multiples inside the range.
fn tick_step((lo, hi): (f64, f64)) -> f64 {
    let mut step = 10f64.powf((hi - lo).max(1e-300).log10().floor() - 2.0);
    for m in [2.0, 2.5, 2.0].iter().cycle().take(60) {
        if (hi / step).floor() - (lo / step).ceil() + 1.0 <= TICKS as f64 {
            break;
        }
        step *= m;
    }
    step
}

/// The round ticks inside `range` (multiples of plotters' tick step), for a colour bar.
pub fn round_ticks(range: (f64, f64)) -> Vec<f64> {
    let (lo, hi) = (range.0.min(range.1), range.0.max(range.1));
    let step = tick_step((lo, hi));
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|i| i as f64 * step).collect()
}

/// Tick labels with the decimals plotters' tick step over `range` needs,
/// and a true minus sign.
pub fn tick_formatter((lo, hi): (f64, f64)) -> impl Fn(f64) -> String {
    let (lo, hi) = (lo.min(hi), lo.max(hi));
    let step = tick_step((lo, hi));
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
