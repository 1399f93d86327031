//! A plotters drawing backend that draws into a tiny-skia pixmap, so that `rigidref plot`
//! writes PNG with the same chart code as SVG. Lines, rectangles, circles and polygons are
//! tiny-skia's anti-aliased paths; text is the public-domain 8 × 8 bitmap font of `font8x8`,
//! scaled into the box plotters lays the text out in, so no font file (and no system font) is needed: plotters' own
//! bitmap backend needs one. docs/viewing.md §"Plots".

use font8x8::UnicodeFonts;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
    FontTransform,
};
use std::path::{Path, PathBuf};
use tiny_skia::{FillRule, LineCap, LineJoin, Paint, PathBuilder, Pixmap, Rect, Stroke, Transform};

/// Why a PNG could not be written.
#[derive(Debug)]
pub struct PixmapError(String);

impl std::fmt::Display for PixmapError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for PixmapError {}

/// Draws into a pixmap of a fixed size and writes it to `path` as PNG on `present`.
pub struct PixmapBackend {
    pixmap: Pixmap,
    path: PathBuf,
}

impl PixmapBackend {
    /// A white `width` × `height` canvas that `present` writes to `path`. None for a zero or
    /// absurd size.
    pub fn new(path: &Path, (width, height): (u32, u32)) -> Option<PixmapBackend> {
        let mut pixmap = Pixmap::new(width, height)?;
        pixmap.fill(tiny_skia::Color::WHITE);
        Some(PixmapBackend {
            pixmap,
            path: path.to_path_buf(),
        })
    }
}

fn paint(c: BackendColor) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color_rgba8(
        c.rgb.0,
        c.rgb.1,
        c.rgb.2,
        (c.alpha.clamp(0.0, 1.0) * 255.0).round() as u8,
    );
    p.anti_alias = true;
    p
}

type Result<T> = std::result::Result<T, DrawingErrorKind<PixmapError>>;

impl DrawingBackend for PixmapBackend {
    type ErrorType = PixmapError;

    fn get_size(&self) -> (u32, u32) {
        (self.pixmap.width(), self.pixmap.height())
    }

    fn ensure_prepared(&mut self) -> Result<()> {
        Ok(())
    }

    fn present(&mut self) -> Result<()> {
        let (w, h) = self.get_size();
        let mut img = image::RgbaImage::new(w, h);
        for (dst, src) in img.pixels_mut().zip(self.pixmap.pixels()) {
            let c = src.demultiply();
            *dst = image::Rgba([c.red(), c.green(), c.blue(), c.alpha()]);
        }
        img.save(&self.path).map_err(|e| {
            DrawingErrorKind::DrawingError(PixmapError(format!(
                "{}: cannot write: {e}",
                self.path.display()
            )))
        })
    }

    fn draw_pixel(&mut self, point: BackendCoord, color: BackendColor) -> Result<()> {
        if let Some(r) = Rect::from_xywh(point.0 as f32, point.1 as f32, 1.0, 1.0) {
            let mut p = paint(color);
            p.anti_alias = false;
            self.pixmap.fill_rect(r, &p, Transform::identity(), None);
        }
        Ok(())
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<()> {
        self.draw_path([from, to], style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<()> {
        let (x0, y0) = (
            upper_left.0.min(bottom_right.0),
            upper_left.1.min(bottom_right.1),
        );
        let (x1, y1) = (
            upper_left.0.max(bottom_right.0),
            upper_left.1.max(bottom_right.1),
        );
        if fill {
            if let Some(r) = Rect::from_ltrb(x0 as f32, y0 as f32, x1 as f32 + 1.0, y1 as f32 + 1.0)
            {
                let mut p = paint(style.color());
                p.anti_alias = false;
                self.pixmap.fill_rect(r, &p, Transform::identity(), None);
            }
            Ok(())
        } else {
            self.draw_path([(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)], style)
        }
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<()> {
        let mut pb = PathBuilder::new();
        for (i, (x, y)) in path.into_iter().enumerate() {
            // Pixel centres, so that a 1-pixel line covers one pixel column or row.
            let (x, y) = (x as f32 + 0.5, y as f32 + 0.5);
            if i == 0 {
                pb.move_to(x, y);
            } else {
                pb.line_to(x, y);
            }
        }
        if let Some(p) = pb.finish() {
            let stroke = Stroke {
                width: style.stroke_width().max(1) as f32,
                line_cap: LineCap::Butt,
                line_join: LineJoin::Round,
                ..Stroke::default()
            };
            self.pixmap.stroke_path(
                &p,
                &paint(style.color()),
                &stroke,
                Transform::identity(),
                None,
            );
        }
        Ok(())
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<()> {
        let Some(circle) = PathBuilder::from_circle(
            center.0 as f32 + 0.5,
            center.1 as f32 + 0.5,
            radius.max(1) as f32,
        ) else {
            return Ok(());
        };
        if fill {
            self.pixmap.fill_path(
                &circle,
                &paint(style.color()),
                FillRule::Winding,
                Transform::identity(),
                None,
            );
        } else {
            let stroke = Stroke {
                width: style.stroke_width().max(1) as f32,
                ..Stroke::default()
            };
            self.pixmap.stroke_path(
                &circle,
                &paint(style.color()),
                &stroke,
                Transform::identity(),
                None,
            );
        }
        Ok(())
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<()> {
        let mut pb = PathBuilder::new();
        for (i, (x, y)) in vert.into_iter().enumerate() {
            if i == 0 {
                pb.move_to(x as f32, y as f32);
            } else {
                pb.line_to(x as f32, y as f32);
            }
        }
        pb.close();
        if let Some(p) = pb.finish() {
            self.pixmap.fill_path(
                &p,
                &paint(style.color()),
                FillRule::Winding,
                Transform::identity(),
                None,
            );
        }
        Ok(())
    }

    fn draw_text<TStyle: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &TStyle,
        pos: BackendCoord,
    ) -> Result<()> {
        let colour = style.color();
        if colour.alpha == 0.0 {
            return Ok(());
        }
        // The text fills the box plotters lays it out in (its size estimate, which the legend
        // and the axis labels are placed by): each character a cell of that box, its 8 × 8
        // glyph (7 columns used) scaled into it.
        let count = text.chars().count().max(1) as f32;
        let (width, height) = text_box(style.size(), text);
        let (cell_w, cell_h) = (width as f32 / count, height as f32);
        let (px, py) = (cell_w / 7.0, cell_h / 8.0);
        let dx = match style.anchor().h_pos {
            HPos::Left => 0,
            HPos::Right => -width,
            HPos::Center => -width / 2,
        };
        let dy = match style.anchor().v_pos {
            VPos::Top => 0,
            VPos::Center => -height / 2,
            VPos::Bottom => -height,
        };
        let transform = style.transform();
        let p = paint(colour);
        let mut pb = PathBuilder::new();
        for (col, ch) in text.chars().enumerate() {
            let bits = glyph(ch);
            for (gy, byte) in bits.iter().enumerate() {
                for gx in 0..8 {
                    if byte & (1 << gx) == 0 {
                        continue;
                    }
                    // The font pixel's rectangle in the text's frame, rotated as the style asks.
                    let x = dx as f32 + col as f32 * cell_w + gx as f32 * px;
                    let y = dy as f32 + gy as f32 * py;
                    let (ax, ay) = rotate(&transform, x, y);
                    let (bx, by) = rotate(&transform, x + px, y + py);
                    if let Some(r) = Rect::from_ltrb(
                        pos.0 as f32 + ax.min(bx),
                        pos.1 as f32 + ay.min(by),
                        pos.0 as f32 + ax.max(bx),
                        pos.1 as f32 + ay.max(by),
                    ) {
                        pb.push_rect(r);
                    }
                }
            }
        }
        if let Some(path) = pb.finish() {
            self.pixmap
                .fill_path(&path, &p, FillRule::Winding, Transform::identity(), None);
        }
        Ok(())
    }

    fn estimate_text_size<TStyle: BackendTextStyle>(
        &self,
        text: &str,
        style: &TStyle,
    ) -> Result<(u32, u32)> {
        let (w, h) = text_box(style.size(), text);
        Ok((w as u32, h as u32))
    }
}

/// The box plotters' own layout gives text of `size` pixels (its estimate without a font:
/// an em of size/1.24², characters 0.7 em wide), in pixels, so that what is drawn fills the
/// space the chart left for it.
fn text_box(size: f64, text: &str) -> (i32, i32) {
    let em = size / 1.24 / 1.24;
    (
        (em * 0.7 * text.chars().count() as f64).round() as i32,
        (em * 1.24).round() as i32,
    )
}

/// The 8 × 8 bitmap of `ch` (row by row, bit 0 the leftmost pixel): Basic Latin, Latin-1 and
/// Greek (ω, λ, …) from `font8x8`, a question mark for anything else.
pub fn glyph(ch: char) -> [u8; 8] {
    font8x8::BASIC_FONTS
        .get(ch)
        .or_else(|| font8x8::LATIN_FONTS.get(ch))
        .or_else(|| font8x8::GREEK_FONTS.get(ch))
        .or_else(|| font8x8::BASIC_FONTS.get('?'))
        .unwrap_or([0; 8])
}

/// A point of the text's frame turned as plotters turns text (`FontTransform::transform`).
fn rotate(t: &FontTransform, x: f32, y: f32) -> (f32, f32) {
    match t {
        FontTransform::None => (x, y),
        FontTransform::Rotate90 => (-y, x),
        FontTransform::Rotate180 => (-x, -y),
        FontTransform::Rotate270 => (y, -x),
    }
}
