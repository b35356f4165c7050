//! The bitmap backend with text drawn right: [`Glyphs`] wraps a plotters
//! backend and draws text itself, each glyph at its pen position plus its
//! left side bearing. plotters' own drawing (its `ab_glyph` font, 0.3.7)
//! drops the bearing: in the PNG files `t = 0` read `t= 0`, `a, b` read
//! `a , b`, and a combining accent (the macron of `d̄`) stood beside its
//! letter instead of over it. The SVG files are not concerned (their text
//! is drawn by the viewer).
//!
//! Layout (the text's box, its anchor, the pixel rows) is plotters': a
//! glyph moves by its bearing, at most a pixel or two, nothing else does;
//! but bold text is drawn and measured in the bold face (plotters measures
//! and draws it in the regular one, while the SVG files show it bold).

use super::style::FONT;
use ab_glyph::{point, Font, FontRef, GlyphId, ScaleFont};
use plotters::prelude::*;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind, FontStyle,
};
use std::sync::OnceLock;

/// A drawing backend whose text is drawn by [`draw_glyphs`]; everything
/// else is the wrapped backend's.
pub(super) struct Glyphs<DB>(pub(super) DB);

/// The DejaVu Sans faces, regular and bold (`None`: the embedded font
/// could not be read, then plotters draws the text).
fn faces() -> Option<&'static (FontRef<'static>, FontRef<'static>)> {
    static FACES: OnceLock<Option<(FontRef<'static>, FontRef<'static>)>> = OnceLock::new();
    FACES
        .get_or_init(|| {
            let regular = FontRef::try_from_slice(dejavu::sans::regular()).ok()?;
            let bold = FontRef::try_from_slice(dejavu::sans::bold()).ok()?;
            Some((regular, bold))
        })
        .as_ref()
}

/// The box of `text` in `font` at `size` pixels, as plotters lays it out
/// (the advances and kerns; the height `size / 1.24`): the same numbers
/// for the regular face, the bold face's own width for bold text
/// (plotters measures bold text with the regular face).
fn layout(font: &FontRef<'static>, size: f64, text: &str) -> ((i32, i32), (i32, i32)) {
    let font = font.as_scaled(size as f32);
    let mut x = 0f32;
    let mut prev: Option<GlyphId> = None;
    for c in text.chars() {
        let id = font.glyph_id(c);
        x += font.h_advance(id);
        if let Some(p) = prev {
            x += font.kern(p, id);
        }
        prev = Some(id);
    }
    ((0, 0), (x as i32, (size / 1.24) as i32))
}

/// The face of `style` (DejaVu Sans regular or bold), `None` for another
/// family or when the embedded font cannot be read.
fn face<S: BackendTextStyle>(style: &S) -> Option<&'static FontRef<'static>> {
    let (regular, bold) = faces()?;
    (style.family().as_str() == FONT).then_some(match style.style() {
        FontStyle::Bold => bold,
        _ => regular,
    })
}

/// Calls `pixel(x, y, coverage)` for every pixel of `text` in `font` at
/// `size` pixels, from the pen at `(0, 0)`: glyphs advance and kern as in
/// plotters, and each is drawn at its own bounds (its bearing kept);
/// vertically as plotters draws them.
fn draw_glyphs<E>(
    font: &FontRef<'static>,
    size: f64,
    text: &str,
    mut pixel: impl FnMut(i32, i32, f32) -> Result<(), E>,
) -> Result<(), E> {
    let font = font.as_scaled(size as f32);
    let mut x = 0f32;
    let mut prev: Option<GlyphId> = None;
    for c in text.chars() {
        let id = font.glyph_id(c);
        if let Some(p) = prev {
            x += font.kern(p, id);
        }
        let glyph = id.with_scale_and_position(font.scale(), point(x, 0.0));
        if let Some(outline) = font.outline_glyph(glyph) {
            let r = outline.px_bounds();
            let (x0, y0) = (r.min.x as i32, ((size as f32) / 2.0 + r.min.y) as i32);
            let mut buf = Vec::new();
            outline.draw(|gx, gy, a| buf.push((gx as i32, gy as i32, a)));
            for (gx, gy, a) in buf {
                pixel(x0 + gx, y0 + gy, a)?;
            }
        }
        x += font.h_advance(id);
        prev = Some(id);
    }
    Ok(())
}

impl<DB: DrawingBackend> DrawingBackend for Glyphs<DB> {
    type ErrorType = DB::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.0.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_path(path, style)
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.fill_polygon(vert, style)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.blit_bitmap(pos, size, src)
    }

    /// The text's box by [`layout`] (plotters' for the other fonts).
    fn estimate_text_size<TStyle: BackendTextStyle>(
        &self,
        text: &str,
        style: &TStyle,
    ) -> Result<(u32, u32), DrawingErrorKind<Self::ErrorType>> {
        match face(style) {
            Some(f) => {
                let ((x0, y0), (x1, y1)) = layout(f, style.size(), text);
                Ok(((x1 - x0).max(0) as u32, (y1 - y0).max(0) as u32))
            }
            None => self.0.estimate_text_size(text, style),
        }
    }

    /// plotters' placement of the text (its box by [`layout`], the anchor,
    /// the rotation), the glyphs by [`draw_glyphs`].
    fn draw_text<TStyle: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &TStyle,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let Some(face) = face(style) else {
            return self.0.draw_text(text, style, pos);
        };
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let ((min_x, min_y), (max_x, max_y)) = layout(face, style.size(), text);
        let (width, height) = (max_x - min_x, max_y - min_y);
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
        let trans = style.transform();
        let (w, h) = self.get_size();
        draw_glyphs(face, style.size(), text, |x, y, a| {
            let (x, y) = trans.transform(x + dx - min_x, y + dy - min_y);
            let (x, y) = (pos.0 + x, pos.1 + y);
            if x >= 0 && x < w as i32 && y >= 0 && y < h as i32 {
                let c = BackendColor {
                    alpha: color.alpha * a as f64,
                    rgb: color.rgb,
                };
                self.0.draw_pixel((x, y), c)
            } else {
                Ok(())
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::{draw_glyphs, faces, layout};
    use ab_glyph::{Font, ScaleFont};

    /// The columns of the pixels `text` covers, at 20 pixels.
    fn columns(text: &str) -> Vec<i32> {
        let (regular, _) = faces().expect("the embedded font");
        let mut xs = Vec::new();
        draw_glyphs(regular, 20.0, text, |x, _, a| {
            if a > 0.0 {
                xs.push(x);
            }
            Ok::<(), ()>(())
        })
        .unwrap();
        xs
    }

    #[test]
    fn a_glyph_keeps_its_bearing() {
        let (regular, _) = faces().expect("the embedded font");
        let f = regular.as_scaled(20.0);
        // `=` has a bearing of a few pixels: its ink starts there, not at
        // the pen (plotters' drawing put it at the pen: `t= 0`).
        let lsb = f.h_side_bearing(f.glyph_id('='));
        assert!(lsb >= 1.0, "{lsb}");
        let first = columns("=").into_iter().min().unwrap();
        assert_eq!(first, lsb.floor() as i32);
        // A space then `=`: the ink starts past the space's advance.
        let space = f.h_advance(f.glyph_id(' '));
        let after = columns(" =").into_iter().min().unwrap();
        assert_eq!(after, (space + lsb).floor() as i32);
    }

    #[test]
    fn a_combining_mark_is_drawn_over_its_letter() {
        let (regular, _) = faces().expect("the embedded font");
        let f = regular.as_scaled(20.0);
        let d = f.h_advance(f.glyph_id('d'));
        // The macron of d̄ adds no width and no pixel beyond the d.
        assert_eq!(
            layout(regular, 20.0, "d\u{304}"),
            layout(regular, 20.0, "d")
        );
        let right = columns("d\u{304}").into_iter().max().unwrap();
        assert!(right <= d.ceil() as i32, "{right} > {d}");
        assert!(columns("d\u{304}").len() > columns("d").len());
    }
}
