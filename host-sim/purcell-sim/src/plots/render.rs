//! One drawing routine, two files: SVG and PNG.
//!
//! A [`Figure`] draws itself on any plotters backend at a scale factor. The SVG is drawn at
//! scale 1 by plotters' SVG backend. The PNG is drawn at scale [`SUPERSAMPLE`] on plotters'
//! bitmap backend, averaged down over `SUPERSAMPLE × SUPERSAMPLE` blocks to the figure's size
//! (anti-aliasing for every line, marker and glyph), and encoded by `png`. Text in both comes
//! from the bundled DejaVu Sans ([`FONT`]), so nothing depends on the fonts of the machine:
//! the bitmap backend's own text path misplaces glyphs (it drops their side bearings), so
//! `Raster` draws text itself, with SVG's placement rules, and draws thick polylines with
//! round joins.

use super::PlotError;
use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind, FontTransform,
};
use std::sync::OnceLock;

/// DejaVu Sans, reduced to the characters the figures use (see `assets/fonts/`).
pub const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// The font family the figures ask for. It is registered under this name for layout and for
/// the bitmap text, and the SVG writes it as a CSS font list, so a viewer with DejaVu Sans
/// shows what the PNG shows and any other falls back to its sans-serif.
pub const FAMILY: &str = "DejaVu Sans, sans-serif";

/// The PNG is drawn at this multiple of its size and averaged down.
pub const SUPERSAMPLE: u32 = 3;

/// A drawing error, whatever the backend.
pub type DrawResult = Result<(), Box<dyn std::error::Error>>;

/// A figure that can draw itself on any backend.
pub trait Figure {
    /// Size in pixels (of the SVG's canvas and of the PNG).
    fn size(&self) -> (u32, u32);

    /// Draws the figure on `area`, whose size is `size()` times `scale`.
    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, scale: f64) -> DrawResult
    where
        DB::ErrorType: 'static;
}

fn font() -> Result<&'static FontRef<'static>, PlotError> {
    static FONT_REF: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    FONT_REF
        .get_or_init(|| {
            let f = FontRef::try_from_slice(FONT).ok()?;
            plotters::style::register_font(FAMILY, FontStyle::Normal, FONT).ok()?;
            Some(f)
        })
        .as_ref()
        .ok_or(PlotError::Font)
}

/// Advance width of `text` in pixels at plotters' font size `size` (SVG font-size
/// `size/1.24`), with kerning: what both backends draw.
pub fn text_width(text: &str, size: f64) -> f64 {
    font().map_or(0.6 * size / 1.24 * text.chars().count() as f64, |f| {
        Metrics::new(f, size).width(text) as f64
    })
}

/// The bundled font at one size.
struct Metrics<'f> {
    font: &'f FontRef<'static>,
    scaled: ab_glyph::PxScaleFont<&'f FontRef<'static>>,
    em: f32,
}

impl<'f> Metrics<'f> {
    fn new(font: &'f FontRef<'static>, size: f64) -> Self {
        let units = font.units_per_em().unwrap_or(2048.0);
        let em = (size / 1.24) as f32;
        // ab_glyph scales by ascent − descent; SVG's font-size is the em.
        let scaled = font.as_scaled(PxScale::from(em * font.height_unscaled() / units));
        Metrics { font, scaled, em }
    }

    fn width(&self, text: &str) -> f32 {
        let ids: Vec<_> = text.chars().map(|c| self.font.glyph_id(c)).collect();
        let mut width = 0.0;
        for (i, id) in ids.iter().enumerate() {
            if i > 0 {
                width += self.scaled.kern(ids[i - 1], *id);
            }
            width += self.scaled.h_advance(*id);
        }
        width
    }

    /// Height of the letter x (CSS `1ex`).
    fn x_height(&self) -> f32 {
        let units = self.font.units_per_em().unwrap_or(2048.0);
        self.font
            .outline(self.font.glyph_id('x'))
            .map_or(0.55 * units, |o| (o.bounds.max.y - o.bounds.min.y).abs())
            / units
            * self.em
    }
}

/// `(name.svg, SVG)` and `(name.png, PNG)` of a figure.
pub fn render(name: &str, figure: &impl Figure) -> Result<[(String, Vec<u8>); 2], PlotError> {
    let font = font()?;
    let draw_err = |e: Box<dyn std::error::Error>| PlotError::Draw(format!("{name}: {e}"));
    let (w, h) = figure.size();
    let mut svg = String::new();
    {
        let area = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
        figure.draw(&area, 1.0).map_err(draw_err)?;
        area.present().map_err(|e| draw_err(e.into()))?;
    }
    let s = SUPERSAMPLE;
    let (bw, bh) = (w * s, h * s);
    let mut big = vec![255u8; (bw * bh * 3) as usize];
    {
        let backend = BitMapBackend::with_buffer_and_format(&mut big, (bw, bh))
            .map_err(|e| draw_err(e.into()))?;
        let area = Raster {
            inner: backend,
            font,
        }
        .into_drawing_area();
        figure.draw(&area, s as f64).map_err(draw_err)?;
        area.present().map_err(|e| draw_err(e.into()))?;
    }
    let png = encode_png(&downsample(&big, (w, h), s), (w, h))?;
    Ok([
        (format!("{name}.svg"), svg.into_bytes()),
        (format!("{name}.png"), png),
    ])
}

/// The mean of each `s × s` block of an RGB image `s` times the size `(w, h)`.
fn downsample(big: &[u8], (w, h): (u32, u32), s: u32) -> Vec<u8> {
    let (w, h, s) = (w as usize, h as usize, s as usize);
    let n = (s * s) as u32;
    let mut out = Vec::with_capacity(w * h * 3);
    let mut sums = vec![0u32; w * 3];
    for rows in big.chunks_exact(w * s * 3 * s).take(h) {
        sums.fill(0);
        for row in rows.chunks_exact(w * s * 3) {
            for (x, block) in row.chunks_exact(s * 3).enumerate() {
                for px in block.chunks_exact(3) {
                    sums[3 * x] += px[0] as u32;
                    sums[3 * x + 1] += px[1] as u32;
                    sums[3 * x + 2] += px[2] as u32;
                }
            }
        }
        out.extend(sums.iter().map(|&v| ((v + n / 2) / n) as u8));
    }
    out
}

fn encode_png(rgb: &[u8], (w, h): (u32, u32)) -> Result<Vec<u8>, PlotError> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Balanced);
    let mut writer = encoder
        .write_header()
        .map_err(|e| PlotError::Draw(e.to_string()))?;
    writer
        .write_image_data(rgb)
        .map_err(|e| PlotError::Draw(e.to_string()))?;
    writer
        .finish()
        .map_err(|e| PlotError::Draw(e.to_string()))?;
    Ok(bytes)
}

/// plotters' bitmap backend with our text and thick polylines.
struct Raster<'a> {
    inner: BitMapBackend<'a>,
    font: &'static FontRef<'static>,
}

type RasterError = DrawingErrorKind<<BitMapBackend<'static> as DrawingBackend>::ErrorType>;

impl Raster<'_> {
    /// Blends `color` at coverage `c` onto pixel `p`.
    fn cover(&mut self, p: BackendCoord, color: BackendColor, c: f64) -> Result<(), RasterError> {
        if c <= 0.0 {
            return Ok(());
        }
        let alpha = color.alpha * c.min(1.0);
        self.inner.draw_pixel(p, BackendColor { alpha, ..color })
    }
}

impl DrawingBackend for Raster<'_> {
    type ErrorType = <BitMapBackend<'static> as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }
    fn ensure_prepared(&mut self) -> Result<(), RasterError> {
        self.inner.ensure_prepared()
    }
    fn present(&mut self) -> Result<(), RasterError> {
        self.inner.present()
    }
    fn draw_pixel(&mut self, p: BackendCoord, color: BackendColor) -> Result<(), RasterError> {
        self.inner.draw_pixel(p, color)
    }
    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), RasterError> {
        self.inner.draw_line(from, to, style)
    }
    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), RasterError> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }
    // `draw_circle` and `fill_polygon`: the trait's own, which rasterise through `draw_line`
    // and `draw_pixel` above, as they do for the bitmap backend (which has no others).

    /// Thick polylines as segments with round joins (plotters' outline polygon leaves holes
    /// where a path crosses itself).
    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), RasterError> {
        let w = style.stroke_width();
        if w <= 2 {
            return self.inner.draw_path(path, style);
        }
        let pts: Vec<BackendCoord> = path.into_iter().collect();
        let r = w / 2;
        for (i, p) in pts.iter().enumerate() {
            if i > 0 {
                self.inner.draw_line(pts[i - 1], *p, style)?;
            }
            if i > 0 && i + 1 < pts.len() {
                self.inner.draw_circle(*p, r, &style.color(), true)?;
            }
        }
        Ok(())
    }

    /// Text placed as the SVG backend places it: `font-size` = size/1.24, anchored at the
    /// start, middle or end, baseline `0.76em` below the point (top), `0.5ex` below
    /// (centre) or `0.5ex` above (bottom); rotated about the point.
    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), RasterError> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let m = Metrics::new(self.font, style.size());
        let (width, em) = (m.width(text), m.em);
        let x_height = m.x_height();
        let mut pen = match style.anchor().h_pos {
            HPos::Left => 0.0,
            HPos::Center => -width / 2.0,
            HPos::Right => -width,
        };
        let baseline = match style.anchor().v_pos {
            VPos::Top => 0.76 * em,
            VPos::Center => 0.5 * x_height,
            VPos::Bottom => -0.5 * x_height,
        };
        let rotate = |x: i32, y: i32| match style.transform() {
            FontTransform::Rotate90 => (-y, x),
            FontTransform::Rotate180 => (-x, -y),
            FontTransform::Rotate270 => (y, -x),
            _ => (x, y),
        };
        let ids: Vec<_> = text.chars().map(|c| m.font.glyph_id(c)).collect();
        for (i, id) in ids.iter().enumerate() {
            if i > 0 {
                pen += m.scaled.kern(ids[i - 1], *id);
            }
            let glyph = id.with_scale_and_position(m.scaled.scale(), point(pen, baseline));
            pen += m.scaled.h_advance(*id);
            let Some(outline) = m.font.outline_glyph(glyph) else {
                continue;
            };
            let b = outline.px_bounds();
            let mut pixels = Vec::new();
            outline.draw(|x, y, c| pixels.push((x as i32, y as i32, c)));
            for (x, y, c) in pixels {
                let (rx, ry) = rotate(b.min.x as i32 + x, b.min.y as i32 + y);
                self.cover((pos.0 + rx, pos.1 + ry), color, c as f64)?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn downsample_averages_blocks() {
        // 2×1 image at s = 2: left block white, right block half black.
        let mut big = vec![255u8; 4 * 2 * 3];
        for p in [(2, 0), (3, 0)] {
            let i = (p.1 * 4 + p.0) * 3;
            big[i..i + 3].fill(0);
        }
        let small = downsample(&big, (2, 1), 2);
        assert_eq!(small, vec![255, 255, 255, 128, 128, 128]);
    }
}
