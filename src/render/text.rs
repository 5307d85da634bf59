//! Text on CPU images: the embedded ASCII-and-symbols subset of DejaVu Sans
//! (see `fonts/LICENSE-DejaVu.txt`), laid out with its advances and kerning
//! and rasterised with ab_glyph. The legend, the sweep's contact sheet and
//! the study's plot all use this one font.

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};
use image::RgbaImage;
use std::sync::OnceLock;

/// The font file (TrueType).
pub static FONT_BYTES: &[u8] = include_bytes!("fonts/DejaVuSans-subset.ttf");

fn font() -> &'static FontRef<'static> {
    static FONT: OnceLock<FontRef<'static>> = OnceLock::new();
    FONT.get_or_init(|| {
        FontRef::try_from_slice(FONT_BYTES).expect("the embedded font is a valid TrueType file")
    })
}

/// The advance width of `text` at `px` pixels, in pixels.
pub fn text_width(text: &str, px: f32) -> f32 {
    let font = font().as_scaled(PxScale::from(px));
    let mut width = 0.0;
    let mut previous = None;
    for c in text.chars() {
        let id = font.glyph_id(c);
        if let Some(p) = previous {
            width += font.kern(p, id);
        }
        width += font.h_advance(id);
        previous = Some(id);
    }
    width
}

/// Draws `text` with its baseline at `(x, baseline)`, `px` pixels high, in
/// the sRGB colour `ink`, blended by glyph coverage; pixels outside the
/// image are skipped.
pub fn draw_text(image: &mut RgbaImage, text: &str, x: f32, baseline: f32, px: f32, ink: [u8; 3]) {
    let scale = PxScale::from(px);
    let font = font().as_scaled(scale);
    let mut caret = x;
    let mut previous = None;
    for c in text.chars() {
        let id = font.glyph_id(c);
        if let Some(p) = previous {
            caret += font.kern(p, id);
        }
        let glyph = id.with_scale_and_position(scale, ab_glyph::point(caret, baseline));
        caret += font.h_advance(id);
        previous = Some(id);
        let Some(outline) = font.outline_glyph(glyph) else {
            continue;
        };
        let bounds = outline.px_bounds();
        outline.draw(|gx, gy, coverage| {
            let px_x = bounds.min.x as i64 + gx as i64;
            let px_y = bounds.min.y as i64 + gy as i64;
            if px_x < 0 || px_y < 0 || px_x >= image.width() as i64 || px_y >= image.height() as i64
            {
                return;
            }
            let pixel = image.get_pixel_mut(px_x as u32, px_y as u32);
            let a = coverage.clamp(0.0, 1.0);
            for (channel, &i) in pixel.0.iter_mut().zip(&ink) {
                *channel = (*channel as f32 * (1.0 - a) + i as f32 * a).round() as u8;
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_darkens_pixels_and_has_a_width() {
        let mut image = RgbaImage::from_pixel(120, 20, image::Rgba([255, 255, 255, 255]));
        draw_text(&mut image, "young=300", 2.0, 15.0, 14.0, [0, 0, 0]);
        let dark = image.pixels().filter(|p| p.0[0] < 128).count();
        assert!(dark > 30, "{dark} dark pixels");
        let wide = text_width("material.young=300", 12.0);
        assert!(wide > 60.0 && wide < 160.0, "{wide}");
        assert!(text_width("ab", 12.0) < text_width("abc", 12.0));
    }
}
