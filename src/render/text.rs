//! Text on CPU images: the embedded ASCII-and-symbols subset of DejaVu Sans
//! (see `fonts/LICENSE-DejaVu.txt`), laid out with its advances and kerning
//! and rasterised with ab_glyph. The legend, the sweep's contact sheet and
//! the study's plot all use this one font.

use ab_glyph::{Font, FontRef, GlyphId, PxScale, ScaleFont};
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

/// Each glyph of `text` at `px` pixels with the caret's x where it starts,
/// from `x`: advances and kerning.
fn laid_out(text: &str, px: f32, x: f32) -> impl Iterator<Item = (GlyphId, f32)> {
    let font = font().as_scaled(PxScale::from(px));
    let mut caret = x;
    let mut previous = None;
    text.chars().map(move |c| {
        let id = font.glyph_id(c);
        if let Some(p) = previous {
            caret += font.kern(p, id);
        }
        let start = caret;
        caret += font.h_advance(id);
        previous = Some(id);
        (id, start)
    })
}

/// The advance width of `text` at `px` pixels, in pixels.
pub fn text_width(text: &str, px: f32) -> f32 {
    let font = font().as_scaled(PxScale::from(px));
    laid_out(text, px, 0.0)
        .last()
        .map_or(0.0, |(id, start)| start + font.h_advance(id))
}

/// Draws `text` with its baseline at `(x, baseline)`, `px` pixels high, in
/// the sRGB colour `ink`, blended by glyph coverage; pixels outside the
/// image are skipped.
pub fn draw_text(image: &mut RgbaImage, text: &str, x: f32, baseline: f32, px: f32, ink: [u8; 3]) {
    let scale = PxScale::from(px);
    let font = font().as_scaled(scale);
    for (id, caret) in laid_out(text, px, x) {
        let glyph = id.with_scale_and_position(scale, ab_glyph::point(caret, baseline));
        let Some(outline) = font.outline_glyph(glyph) else {
            continue;
        };
        let bounds = outline.px_bounds();
        outline.draw(|gx, gy, coverage| {
            let column = bounds.min.x as i64 + gx as i64;
            let row = bounds.min.y as i64 + gy as i64;
            blend_pixel(image, column, row, ink, coverage);
        });
    }
}

/// Blends the sRGB `colour` over pixel `(x, y)` of `image` by `alpha`
/// (clamped to `[0, 1]`), channel by channel in sRGB; a pixel outside the
/// image is skipped. Text and the legend's panel and bar are drawn with it.
pub(super) fn blend_pixel(image: &mut RgbaImage, x: i64, y: i64, colour: [u8; 3], alpha: f32) {
    if x < 0 || y < 0 || x >= i64::from(image.width()) || y >= i64::from(image.height()) {
        return;
    }
    let alpha = alpha.clamp(0.0, 1.0);
    let pixel = image.get_pixel_mut(x as u32, y as u32);
    for (channel, &target) in pixel.0.iter_mut().zip(&colour) {
        *channel = (*channel as f32 * (1.0 - alpha) + target as f32 * alpha).round() as u8;
    }
}
