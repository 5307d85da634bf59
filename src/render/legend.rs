//! The colour-bar legend, drawn on the CPU over the rendered image.
//!
//! It is drawn once per run into the base image every frame starts from,
//! and again only over a frame whose bodies reach its footprint
//! ([`Legend::footprint`]; the camera frames the bodies beside it).
//!
//! A vertical viridis bar on the right, the label above it and "nice" tick
//! values (1, 2, 2.5 or 5 times a power of ten) beside it, on a translucent
//! white panel. Text is drawn by [`super::text`] (an ASCII-and-symbols subset
//! of DejaVu Sans rasterised with ab_glyph). Sizes scale with the
//! image height (reference: 720 pixels).

use super::colormap::viridis;
use super::pixel_rect::PixelRect;
use super::text::{self, blend_pixel, text_width};
use image::RgbaImage;

/// Text colour, sRGB.
const INK: [u8; 3] = [40, 40, 46];

/// A laid-out legend for one image size and value range.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Legend {
    label: String,
    range: [f32; 2],
    ticks: Vec<(f32, String)>,
    font_px: f32,
    panel: Rect,
    bar: Rect,
    margin: f32,
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Rect {
    x: f32,
    y: f32,
    w: f32,
    h: f32,
}

impl Legend {
    /// Lays out a legend, or `None` when the image is too small to hold one
    /// without covering much of the picture.
    pub fn new(label: &str, range: [f32; 2], width: u32, height: u32) -> Option<Legend> {
        let (w, h) = (width as f32, height as f32);
        let s = h / 720.0;
        let font_px = (17.0 * s).round().clamp(10.0, 72.0);
        let margin = (18.0 * s).round().max(4.0);
        let pad = (12.0 * s).round().max(3.0);
        let bar_w = (18.0 * s).round().max(6.0);
        let tick_len = (6.0 * s).round().max(2.0);
        let gap = (5.0 * s).round().max(2.0);
        let bar_h = (0.45 * h).round();

        let ticks: Vec<(f32, String)> = nice_ticks(
            range[0] as f64,
            range[1] as f64,
            if bar_h > 8.0 * font_px { 6 } else { 3 },
        )
        .into_iter()
        .map(|(v, text)| (v as f32, text))
        .collect();
        let label_w = ticks
            .iter()
            .map(|(_, t)| text_width(t, font_px))
            .fold(0.0, f32::max);
        let title_w = text_width(label, font_px);
        let title_h = if label.is_empty() { 0.0 } else { 1.6 * font_px };
        let content_w = title_w.max(bar_w + tick_len + gap + label_w);
        let panel_w = (content_w + 2.0 * pad).ceil();
        let panel_h = (title_h + bar_h + font_px + 2.0 * pad).ceil();
        if panel_w + 2.0 * margin > 0.45 * w || panel_h > h - 2.0 * margin {
            return None;
        }
        let panel = Rect {
            x: (w - margin - panel_w).round(),
            y: ((h - panel_h) / 2.0).round(),
            w: panel_w,
            h: panel_h,
        };
        let bar = Rect {
            x: panel.x
                + pad
                + ((content_w - (bar_w + tick_len + gap + label_w)) / 2.0)
                    .max(0.0)
                    .round(),
            y: panel.y + pad + title_h + (0.5 * font_px).round(),
            w: bar_w,
            h: bar_h,
        };
        Some(Legend {
            label: label.to_owned(),
            range,
            ticks,
            font_px,
            panel,
            bar,
            margin,
        })
    }

    /// Pixels on the right the legend needs, including margins.
    pub fn reserved_width(&self) -> u32 {
        (self.panel.w + 2.0 * self.margin).ceil() as u32
    }

    /// The pixels `[x0, y0, x1, y1)` of the panel, which holds everything
    /// the legend draws (the title, the bar and the ticks are laid out
    /// inside it).
    fn panel_pixels(&self) -> [i64; 4] {
        let Rect { x, y, w, h } = self.panel;
        [
            x.floor() as i64,
            y.floor() as i64,
            (x + w).ceil() as i64,
            (y + h).ceil() as i64,
        ]
    }

    /// The pixels drawing the legend can change in a `width` x `height`
    /// image: its panel, which holds the title, the bar and the ticks, two
    /// pixels further all round (glyphs and the rounded corners' blending),
    /// inside the image.
    pub fn footprint(&self, width: u32, height: u32) -> PixelRect {
        const MARGIN: i64 = 2;
        let [x0, y0, x1, y1] = self.panel_pixels();
        let clamp = |v: i64, size: u32| v.clamp(0, i64::from(size)) as u32;
        let (x0, y0) = (clamp(x0 - MARGIN, width), clamp(y0 - MARGIN, height));
        let (x1, y1) = (clamp(x1 + MARGIN, width), clamp(y1 + MARGIN, height));
        PixelRect::new(x0, y0, x1 - x0, y1 - y0)
    }

    /// Draws the legend onto an sRGB image.
    pub fn draw(&self, image: &mut RgbaImage) {
        let s = self.font_px / 17.0;
        fill_rounded(image, self.panel, 6.0 * s, [255, 255, 255], 0.82);

        if !self.label.is_empty() {
            let title_w = text_width(&self.label, self.font_px);
            let x = self.panel.x + (self.panel.w - title_w) / 2.0;
            draw_text(
                image,
                &self.label,
                x,
                self.panel.y + (12.0 * s).round().max(3.0) + self.font_px,
                self.font_px,
            );
        }

        let bar = self.bar;
        let (x0, x1) = (bar.x as i64, (bar.x + bar.w) as i64);
        let (y0, y1) = (bar.y as i64, (bar.y + bar.h) as i64);
        for y in y0..y1 {
            let t = 1.0 - ((y - y0) as f32 + 0.5) / (y1 - y0) as f32;
            let c = viridis(t).map(|v| (v * 255.0).round() as u8);
            for x in x0..x1 {
                blend_pixel(image, x, y, c, 1.0);
            }
        }
        let border = (s.round() as i64).max(1);
        stroke_rect(image, x0, y0, x1, y1, border, INK);

        let tick_len = (6.0 * s).round().max(2.0) as i64;
        let gap = (5.0 * s).round().max(2.0);
        let span = self.range[1] - self.range[0];
        for (value, text) in &self.ticks {
            let y = bar.y + bar.h * (1.0 - (value - self.range[0]) / span);
            let yi = y.round() as i64;
            for dy in 0..border {
                for x in x1..x1 + tick_len {
                    blend_pixel(image, x, yi - border / 2 + dy, INK, 1.0);
                }
            }
            let baseline = y + 0.36 * self.font_px;
            draw_text(
                image,
                text,
                (x1 + tick_len) as f32 + gap,
                baseline,
                self.font_px,
            );
        }
    }
}

/// Ticks at 1, 2, 2.5 or 5 times a power of ten inside `[lo, hi]`, at most
/// `max_ticks` of them, formatted with as many decimals as the step needs.
pub(crate) fn nice_ticks(lo: f64, hi: f64, max_ticks: usize) -> Vec<(f64, String)> {
    let span = hi - lo;
    if span.is_nan() || span <= 0.0 || span.is_infinite() {
        return vec![(lo, format_tick(lo, 1.0))];
    }
    let raw = span / (max_ticks.max(2) - 1) as f64;
    let power = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * power)
        .find(|&step| span / step <= (max_ticks - 1) as f64 + 1e-9)
        .unwrap_or(10.0 * power);
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last)
        .map(|k| {
            let v = k as f64 * step;
            (v, format_tick(v, step))
        })
        .collect()
}

fn format_tick(v: f64, step: f64) -> String {
    let magnitude = v.abs().max(step.abs());
    let step_exponent = step.abs().log10().floor();
    let text = if !(1e-3..1e5).contains(&magnitude) {
        if v == 0.0 {
            "0".to_owned()
        } else {
            // Scientific: as many mantissa digits as the step needs.
            let digits = (magnitude.log10().floor() - step_exponent).clamp(0.0, 6.0) as usize;
            format!("{v:.digits$e}")
        }
    } else {
        // A step of 2.5 x 10^k needs one decimal more than 10^k.
        let quarter = (step / 10f64.powf(step_exponent) - 2.5).abs() < 1e-9;
        let decimals = (-step_exponent).max(0.0) as usize + usize::from(quarter);
        format!("{v:.decimals$}")
    };
    text.replace('-', "\u{2212}")
}

/// Legend text: the caret and baseline start on whole pixels.
fn draw_text(image: &mut RgbaImage, text: &str, x: f32, baseline: f32, px: f32) {
    text::draw_text(image, text, x.round(), baseline.round(), px, INK);
}

fn stroke_rect(
    image: &mut RgbaImage,
    x0: i64,
    y0: i64,
    x1: i64,
    y1: i64,
    width: i64,
    colour: [u8; 3],
) {
    for y in y0 - width..y1 + width {
        for x in x0 - width..x1 + width {
            if x < x0 || x >= x1 || y < y0 || y >= y1 {
                blend_pixel(image, x, y, colour, 1.0);
            }
        }
    }
}

/// Fills a rounded rectangle, with anti-aliased corners.
fn fill_rounded(image: &mut RgbaImage, r: Rect, radius: f32, colour: [u8; 3], alpha: f32) {
    let (x0, y0) = (r.x.floor() as i64, r.y.floor() as i64);
    let (x1, y1) = ((r.x + r.w).ceil() as i64, (r.y + r.h).ceil() as i64);
    for y in y0..y1 {
        for x in x0..x1 {
            let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
            // Signed distance to the rounded box.
            let qx = (px - (r.x + r.w / 2.0)).abs() - (r.w / 2.0 - radius);
            let qy = (py - (r.y + r.h / 2.0)).abs() - (r.h / 2.0 - radius);
            let outside =
                (qx.max(0.0).powi(2) + qy.max(0.0).powi(2)).sqrt() + qx.max(qy).min(0.0) - radius;
            let coverage = (0.5 - outside).clamp(0.0, 1.0);
            if coverage > 0.0 {
                blend_pixel(image, x, y, colour, alpha * coverage);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn values(ticks: &[(f64, String)]) -> Vec<String> {
        ticks.iter().map(|(_, t)| t.clone()).collect()
    }

    #[test]
    fn ticks_are_nice_and_inside() {
        assert_eq!(
            values(&nice_ticks(0.0, 1.0, 6)),
            ["0.0", "0.2", "0.4", "0.6", "0.8", "1.0"]
        );
        assert_eq!(
            values(&nice_ticks(0.13, 0.97, 6)),
            ["0.2", "0.4", "0.6", "0.8"]
        );
        assert_eq!(
            values(&nice_ticks(-10.0, 10.0, 6)),
            ["\u{2212}10", "\u{2212}5", "0", "5", "10"]
        );
        assert_eq!(
            values(&nice_ticks(0.0, 10.0, 6)),
            ["0", "2", "4", "6", "8", "10"]
        );
        assert_eq!(
            values(&nice_ticks(0.0, 10.0, 5)),
            ["0.0", "2.5", "5.0", "7.5", "10.0"]
        );
        assert_eq!(
            values(&nice_ticks(0.0, 3.0e6, 4)),
            ["0", "1e6", "2e6", "3e6"]
        );
        assert_eq!(
            values(&nice_ticks(0.0, 2.4e-4, 4)),
            ["0", "1e-4", "2e-4"].map(|s| s.replace('-', "\u{2212}"))
        );
        assert_eq!(values(&nice_ticks(2.0, 2.0, 6)), ["2"]);
    }

    #[test]
    fn legend_fits_or_steps_aside() {
        let legend = Legend::new("strain energy density", [0.0, 1.0], 1280, 720).unwrap();
        assert!(
            legend.reserved_width() > 100 && legend.reserved_width() < 400,
            "{}",
            legend.reserved_width()
        );
        assert!(
            Legend::new(
                "a very long label that cannot fit in a tiny picture",
                [0.0, 1.0],
                160,
                120
            )
            .is_none()
        );
    }

    #[test]
    fn drawing_changes_only_the_footprint() {
        let cases = [
            ("strain energy density", [-3.0, 7.5], 640, 360),
            ("value", [0.0, 1.0], 320, 240),
            ("von Mises stress", [0.0, 2.5e6], 1280, 720),
            ("J", [0.93, 1.07], 1920, 1080),
            ("", [-1.0e-4, 3.0e-4], 800, 800),
        ];
        for (seed, (label, range, width, height)) in cases.into_iter().enumerate() {
            let legend = Legend::new(label, range, width, height).unwrap();
            let footprint = legend.footprint(width, height);
            // On noise no blend leaves a pixel as it was by chance.
            let before = crate::render::noise(width, height, seed as u32);
            let mut after = before.clone();
            legend.draw(&mut after);
            let mut changed = 0;
            for (x, y, pixel) in after.enumerate_pixels() {
                if pixel != before.get_pixel(x, y) {
                    changed += 1;
                    let inside = (footprint.x..footprint.x + footprint.width).contains(&x)
                        && (footprint.y..footprint.y + footprint.height).contains(&y);
                    assert!(inside, "{label}: ({x}, {y}) outside {footprint:?}");
                }
            }
            // Most of the footprint is drawn on; it is a panel at the right.
            let area = footprint.width * footprint.height;
            assert!(2 * changed > area, "{label}: {changed} of {area}");
            assert!(footprint.x > width / 2, "{label}: {footprint:?}");
        }
        let legend = Legend::new("value", [0.0, 1.0], 640, 360).unwrap();
        let mut image = RgbaImage::from_pixel(640, 360, image::Rgba([10, 10, 10, 255]));
        legend.draw(&mut image);
        let bar_mid = image.get_pixel(
            (legend.bar.x + legend.bar.w / 2.0) as u32,
            (legend.bar.y + legend.bar.h / 2.0) as u32,
        );
        let expected = viridis(0.5).map(|v| (v * 255.0).round() as i32);
        for c in 0..3 {
            assert!(
                (bar_mid.0[c] as i32 - expected[c]).abs() <= 3,
                "{bar_mid:?} vs {expected:?}"
            );
        }
    }
}
