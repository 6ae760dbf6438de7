//! The curvature of the connection over the shape plane ([`purcell_solver::curvature`]): one colour
//! field per chosen body direction, with a colour bar, and a gait drawn on top.

use super::Units;
use super::axes::{Axes, colour_bar_tick, minus, tick_formatter};
use super::plane::Overlay;
use super::render::{DrawResult, Figure};
use super::style::*;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};
use purcell_solver::curvature::Field;

/// A row of `F`: a body direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Component {
    /// Forward, along the middle link (m/rad²).
    X,
    /// Sideways (m/rad²).
    Y,
    /// Turning (1/rad).
    Theta,
}

impl Component {
    /// All three, in order.
    pub const ALL: [Component; 3] = [Component::X, Component::Y, Component::Theta];

    fn index(self) -> usize {
        match self {
            Component::X => 0,
            Component::Y => 1,
            Component::Theta => 2,
        }
    }

    fn caption(self) -> &'static str {
        match self {
            Component::X => "x row (m/rad²)",
            Component::Y => "y row (m/rad²)",
            Component::Theta => "θ row (1/rad)",
        }
    }

    /// A motion in this direction, as text (`θ` in the angle units).
    fn motion(self, v: f64, units: Units) -> String {
        let (value, decimals, unit) = match self {
            Component::Theta if units.per_radian == 1.0 => (v, 4, " rad"),
            Component::Theta => (units.angle(v), 2, "°"),
            _ => (v, 3, " m"),
        };
        let text = format!("{value:.decimals$}");
        // No "−0.000": a value that rounds to zero is written without a sign.
        let text = if text
            .trim_start_matches('-')
            .trim_matches(['0', '.'])
            .is_empty()
        {
            text.trim_start_matches('-').to_string()
        } else {
            minus(&text)
        };
        format!("{text}{unit}")
    }
}

/// Colour bands of the field: an even number, so that zero is the edge between the palest
/// blue and the palest red and the sign changes show as a contour.
const BANDS: usize = 20;
/// Plotting-area side of each panel when there are several, and of a single one.
const PANEL: f64 = 640.0;
/// See [`PANEL`].
const SINGLE_PANEL: f64 = 920.0;
/// Height of a line of a panel's caption.
const CAPTION_LINE: f64 = 52.0;

/// The field figure.
pub struct FieldFigure<'a> {
    /// Title.
    pub title: String,
    /// The sampled field.
    pub field: &'a Field,
    /// Panels.
    pub components: Vec<Component>,
    /// The gait, joint limit and start, in display units.
    pub overlay: Overlay,
    /// For a gait: per row of `F`, the integral of `F` over the area it encloses and the
    /// motion it makes (`log(g_0⁻¹ g_N)`), SI.
    pub motion: Option<[(f64, f64); 3]>,
    /// Angle units of the axes.
    pub units: Units,
}

impl FieldFigure<'_> {
    fn panel(&self) -> f64 {
        if self.components.len() == 1 {
            SINGLE_PANEL
        } else {
            PANEL
        }
    }

    fn panel_width(&self) -> f64 {
        Y_LABELS + self.panel() + BAR_GAP + BAR_WIDTH + BAR_LABELS
    }

    fn width(&self) -> f64 {
        self.components.len() as f64 * self.panel_width() + MARGIN
    }

    fn caption_height(&self) -> f64 {
        CAPTION_LINE * if self.motion.is_some() { 2.5 } else { 1.25 }
    }

    fn legend_width(&self) -> f64 {
        self.width() - Y_LABELS - MARGIN
    }

    /// The largest `|F|` of a component: the ends of its colour bar.
    fn limit(&self, c: Component) -> f64 {
        let l = self
            .field
            .values
            .iter()
            .fold(0.0f64, |m, v| m.max(v[c.index()].abs()));
        if l > 0.0 { l } else { 1.0 }
    }

    fn band(t: f64) -> usize {
        (((t.clamp(-1.0, 1.0) + 1.0) / 2.0 * BANDS as f64) as usize).min(BANDS - 1)
    }

    fn band_color(b: usize) -> RGBColor {
        diverging(((b as f64 + 0.5) / BANDS as f64) * 2.0 - 1.0)
    }

    /// Panel `c` with its top left at `(left, top)`: caption, the field (with the gait on top),
    /// axes and colour bar.
    fn draw_panel<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        k: Scale,
        c: Component,
        (left, top): (f64, f64),
    ) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        for (i, line) in self.caption(c).into_iter().enumerate() {
            let size = if i == 0 { LABEL_FONT } else { TICK_FONT };
            root.draw(&Text::new(
                line,
                (
                    k.px(left + Y_LABELS),
                    k.px(top + (i as f64 + 0.5) * CAPTION_LINE),
                ),
                k.font(size, HPos::Left, VPos::Center),
            ))?;
        }
        let area = root.clone().shrink(
            (k.px(left), k.px(top + self.caption_height())),
            (
                k.u(Y_LABELS + self.panel() + RIGHT),
                k.u(self.panel() + X_LABELS),
            ),
        );
        let half = self.units.angle(std::f64::consts::PI);
        let x_desc = format!("α₁ ({})", self.units.angle_unit);
        let y_desc = format!("α₂ ({})", self.units.angle_unit);
        let mut axes = Axes::new((-half, half), (-half, half), &x_desc, &y_desc);
        axes.top = 0.0;
        axes.grid = false;
        let mut chart = axes.build(&area, k)?;
        let lim = self.limit(c);
        self.draw_cells(root, &chart, k, c, lim)?;
        axes.decorate(&area, &mut chart, k)?;
        self.overlay.draw(root, &chart, k, true)?;
        self.overlay.draw_marks(root, &chart, k)?;
        let (right, top) = chart.backend_coord(&(half, half));
        let bottom = chart.backend_coord(&(half, -half)).1;
        Self::draw_colour_bar(root, k, right, (top, bottom), lim)
    }

    /// The caption of panel `c` above its plot, a line each: the row of `F`, and with a gait
    /// the integral of `F` over the area it encloses beside the motion it makes.
    fn caption(&self, c: Component) -> Vec<String> {
        let mut lines = vec![format!("F, {}", c.caption())];
        if let Some(m) = self.motion {
            let (estimate, actual) = m[c.index()];
            lines.push(format!(
                "over the gait: {}; it moves {}",
                c.motion(estimate, self.units),
                c.motion(actual, self.units)
            ));
        }
        lines
    }

    /// Component `c` of the field on `chart`, in [`BANDS`] colour bands of `±lim`: cells of
    /// one band merged into rectangles (a run along α1, grown along α2 while the rows above
    /// match), drawn in pixels one pixel wider than their share so that neighbours meet
    /// without seams.
    fn draw_cells<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        chart: &Chart<'_, DB>,
        k: Scale,
        c: Component,
        lim: f64,
    ) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let half = self.units.angle(std::f64::consts::PI);
        let n = self.field.centres.len();
        let w = self.units.angle(self.field.cell());
        let edge = |i: usize| -half + i as f64 * w;
        let band: Vec<usize> = (0..n * n)
            .map(|ij| Self::band(self.field.at(ij % n, ij / n)[c.index()] / lim))
            .collect();
        let mut done = vec![false; n * n];
        for j in 0..n {
            for i in 0..n {
                if done[j * n + i] {
                    continue;
                }
                let b = band[j * n + i];
                let same = |i: usize, j: usize| !done[j * n + i] && band[j * n + i] == b;
                let mut e = i + 1;
                while e < n && same(e, j) {
                    e += 1;
                }
                let mut top = j + 1;
                while top < n && (i..e).all(|x| same(x, top)) {
                    top += 1;
                }
                for y in j..top {
                    done[y * n + i..y * n + e].fill(true);
                }
                let p0 = chart.backend_coord(&(edge(i), edge(top)));
                let p1 = chart.backend_coord(&(edge(e), edge(j)));
                root.draw(&Rectangle::new(
                    [p0, (p1.0 + k.px(1.0), p1.1 + k.px(1.0))],
                    Self::band_color(b).filled(),
                ))?;
            }
        }
        Ok(())
    }

    /// The colour bar right of pixel column `right` from pixel rows `y0` to `y1`: the bands
    /// from `lim` down to `−lim`, with their ticks.
    fn draw_colour_bar<DB: DrawingBackend>(
        root: &DrawingArea<DB, Shift>,
        k: Scale,
        right: i32,
        (y0, y1): (i32, i32),
        lim: f64,
    ) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let bx = right + k.px(BAR_GAP);
        let bw = k.px(BAR_WIDTH);
        let height = (y1 - y0) as f64;
        for b in 0..BANDS {
            let top = y0 + (height * (BANDS - 1 - b) as f64 / BANDS as f64).round() as i32;
            let bottom = y0 + (height * (BANDS - b) as f64 / BANDS as f64).round() as i32;
            root.draw(&Rectangle::new(
                [(bx, top), (bx + bw, bottom)],
                Self::band_color(b).filled(),
            ))?;
        }
        root.draw(&Rectangle::new([(bx, y0), (bx + bw, y1)], k.line(INK, 2.0)))?;
        let fmt = tick_formatter((-lim, lim));
        let step = nice_step(lim);
        let mut v = -(lim / step).floor() * step;
        while v <= lim + 1e-12 * lim {
            let y = y0 + ((lim - v) / (2.0 * lim) * height).round() as i32;
            colour_bar_tick(root, k, bx + bw, y, fmt(v))?;
            v += step;
        }
        Ok(())
    }
}

/// A step of 1, 2 or 5 times a power of ten giving two or three ticks on each side of zero
/// up to `lim`.
fn nice_step(lim: f64) -> f64 {
    let base = 10f64.powf((lim / 2.0).log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * base)
        .find(|s| lim / s < 3.5)
        .unwrap_or(10.0 * base)
}

impl Figure for FieldFigure<'_> {
    fn size(&self) -> (u32, u32) {
        let legend = legend_height(self.legend_width(), &self.overlay.legend());
        let h =
            2.0 * MARGIN + TITLE_HEIGHT + legend + self.caption_height() + self.panel() + X_LABELS;
        (self.width().round() as u32, h.round() as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, scale: f64) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let k = Scale(scale);
        let legend = self.overlay.legend();
        let top = draw_heading(root, k, &self.title, &legend, self.legend_width())?;
        for (i, c) in self.components.iter().enumerate() {
            self.draw_panel(root, k, *c, (i as f64 * self.panel_width(), top))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plots::Options;

    #[test]
    fn motions_are_written_with_units_and_no_negative_zero() {
        let deg = Units::new(&Options { degrees: true });
        let rad = Units::new(&Options { degrees: false });
        assert_eq!(Component::X.motion(-0.0283, deg), "−0.028 m");
        assert_eq!(Component::Theta.motion(-1e-9, deg), "0.00°");
        assert_eq!(Component::Theta.motion(-0.0004, rad), "−0.0004 rad");
        assert_eq!(Component::Y.motion(-0.0001, rad), "0.000 m");
    }
}
