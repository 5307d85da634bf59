//! [`LegendStamp`]: the legend drawn once per run and stamped onto every
//! frame, bit for bit what drawing it would give.
//!
//! The legend blends a panel, a bar, ticks and text onto the pixels under
//! it; for fixed pixels under it the result is fixed. The legend sits in a
//! strip the camera keeps free of the body, so from frame to frame the
//! pixels under it are almost always the same (the background, perhaps the
//! ground). The stamp keeps the pixels under the legend's footprint and the
//! result of drawing it there; a frame whose pixels under the footprint are
//! equal to the kept ones gets the kept result copied in (a compare and a
//! copy of a few hundred rows), any other frame is drawn in full and becomes
//! the kept one.
//!
//! The footprint is found once by drawing the legend on a black and on a
//! white canvas: a blend that changes no pixel of either changes no pixel at
//! all (the change `round(c + a (t - c)) - c` is largest in size at
//! `c = 0` or `c = 255`), and a margin of two pixels is added. The canvases
//! hold only the legend's neighbourhood (its panel and twice the text size
//! around it), with the legend moved onto them by whole pixels; should a
//! changed pixel reach the canvas's edge inside the image, the search is
//! repeated on canvases of the whole image.

use super::legend::Legend;
use super::pixel_rect::PixelRect;
use image::RgbaImage;

/// A legend with its footprint and the last drawn result.
#[derive(Debug, Clone)]
pub(crate) struct LegendStamp {
    legend: Legend,
    /// Footprint `[x0, y0, x1, y1)` in pixels, inside the image.
    footprint: [u32; 4],
    /// The image size the footprint is for.
    size: (u32, u32),
    /// Pixels under the footprint before and after the last full draw.
    under: Vec<u8>,
    over: Vec<u8>,
}

impl LegendStamp {
    /// A stamp of `legend` for images of `width` x `height` pixels.
    pub fn new(legend: Legend, width: u32, height: u32) -> Self {
        let near = near_window(&legend, width, height);
        let whole = [0, 0, width, height];
        let footprint = match changed_pixels(&legend, near) {
            Some(found) if !reaches_inner_edge(found, near, whole) => Some(found),
            _ => changed_pixels(&legend, whole),
        };
        Self {
            legend,
            footprint: with_margin(footprint, width, height),
            size: (width, height),
            under: Vec::new(),
            over: Vec::new(),
        }
    }

    /// Draws the legend onto `image`, exactly as [`Legend::draw`] would.
    pub fn draw(&mut self, image: &mut RgbaImage) {
        if image.dimensions() != self.size {
            self.legend.draw(image);
            return;
        }
        let under = self.copy_footprint(image);
        if !self.under.is_empty() && under == self.under {
            self.paste_footprint(image);
            return;
        }
        self.legend.draw(image);
        self.over = self.copy_footprint(image);
        self.under = under;
    }

    /// The pixels the legend can change, or `None` when it changes none.
    pub fn footprint_rect(&self) -> Option<PixelRect> {
        let [x0, y0, x1, y1] = self.footprint;
        (x1 > x0 && y1 > y0).then_some(PixelRect {
            x: x0,
            y: y0,
            width: x1 - x0,
            height: y1 - y0,
        })
    }

    /// The footprint `[x0, y0, x1, y1)` (for tests).
    #[cfg(test)]
    fn footprint(&self) -> [u32; 4] {
        self.footprint
    }

    fn rows(&self) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
        let [x0, y0, x1, y1] = self.footprint.map(|v| v as usize);
        let stride = self.size.0 as usize * 4;
        (y0..y1).map(move |y| y * stride + x0 * 4..y * stride + x1 * 4)
    }

    fn copy_footprint(&self, image: &RgbaImage) -> Vec<u8> {
        let raw: &[u8] = image.as_raw();
        self.rows().flat_map(|row| &raw[row]).copied().collect()
    }

    fn paste_footprint(&self, image: &mut RgbaImage) {
        let rows: Vec<_> = self.rows().collect();
        let raw: &mut [u8] = image;
        let mut kept = self
            .over
            .chunks_exact(rows.first().map_or(1, |r| r.len().max(1)));
        for row in rows {
            if let Some(source) = kept.next() {
                raw[row].copy_from_slice(source);
            }
        }
    }
}

/// The legend's neighbourhood `[x0, y0, x1, y1)` in a `width` x `height`
/// image: its panel and twice the text size around it.
fn near_window(legend: &Legend, width: u32, height: u32) -> [u32; 4] {
    let reach = (2.0 * legend.font_px()).ceil() as i64;
    let [x0, y0, x1, y1] = legend.panel_pixels();
    let clamp = |v: i64, size: u32| v.clamp(0, i64::from(size)) as u32;
    [
        clamp(x0 - reach, width),
        clamp(y0 - reach, height),
        clamp(x1 + reach, width),
        clamp(y1 + reach, height),
    ]
}

/// The pixels `[x0, y0, x1, y1)` of the image that drawing `legend` changes
/// within `window` (`[x0, y0, x1, y1)` too), found on a black and a white
/// canvas of the window's size; `None` when it changes none there.
fn changed_pixels(legend: &Legend, window: [u32; 4]) -> Option<[u32; 4]> {
    let [wx0, wy0, wx1, wy1] = window;
    if wx1 <= wx0 || wy1 <= wy0 {
        return None;
    }
    let moved = legend.translated(-i64::from(wx0), -i64::from(wy0));
    let mut found: Option<[u32; 4]> = None;
    for shade in [0u8, 255] {
        let mut canvas = RgbaImage::from_pixel(wx1 - wx0, wy1 - wy0, image::Rgba([shade; 4]));
        moved.draw(&mut canvas);
        for (x, y, pixel) in canvas.enumerate_pixels() {
            if pixel.0 != [shade; 4] {
                let (x, y) = (x + wx0, y + wy0);
                let f = found.get_or_insert([x, y, x + 1, y + 1]);
                *f = [f[0].min(x), f[1].min(y), f[2].max(x + 1), f[3].max(y + 1)];
            }
        }
    }
    found
}

/// `changed` grown by a margin of two pixels, inside the `width` x `height`
/// image (empty when nothing changes).
fn with_margin(changed: Option<[u32; 4]>, width: u32, height: u32) -> [u32; 4] {
    let [x0, y0, x1, y1] = changed.unwrap_or([0, 0, 0, 0]);
    let margin = 2;
    [
        x0.saturating_sub(margin),
        y0.saturating_sub(margin),
        (x1 + margin).min(width),
        (y1 + margin).min(height),
    ]
}

/// Whether `found` touches an edge of `window` that is not an edge of the
/// image `whole`: the legend may reach beyond the window there.
fn reaches_inner_edge(found: [u32; 4], window: [u32; 4], whole: [u32; 4]) -> bool {
    (found[0] == window[0] && window[0] > whole[0])
        || (found[1] == window[1] && window[1] > whole[1])
        || (found[2] == window[2] && window[2] < whole[2])
        || (found[3] == window[3] && window[3] < whole[3])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic noisy image (xorshift), so no blend leaves a pixel as it was by chance.
    fn noise(width: u32, height: u32, seed: u64) -> RgbaImage {
        let mut state = seed | 1;
        RgbaImage::from_fn(width, height, |_, _| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            image::Rgba(state.to_le_bytes()[..4].try_into().unwrap())
        })
    }

    #[test]
    fn the_footprint_holds_every_changed_pixel() {
        let legend = Legend::new("strain energy density", [-3.0, 7.5], 640, 360).unwrap();
        let stamp = LegendStamp::new(legend.clone(), 640, 360);
        let [x0, y0, x1, y1] = stamp.footprint();
        assert!(x0 < x1 && y0 < y1 && x1 <= 640 && y1 <= 360);
        // The legend is a panel on the right, not the whole image.
        assert!(x0 > 320, "{:?}", stamp.footprint());
        let before = noise(640, 360, 7);
        let mut after = before.clone();
        legend.draw(&mut after);
        let mut changed = 0;
        for (x, y, pixel) in after.enumerate_pixels() {
            if pixel != before.get_pixel(x, y) {
                changed += 1;
                assert!((x0..x1).contains(&x) && (y0..y1).contains(&y), "({x}, {y})");
            }
        }
        assert!(changed > 1000, "{changed} pixels changed");
    }

    #[test]
    fn the_search_near_the_panel_finds_what_the_whole_image_search_finds() {
        let cases = [
            ("strain energy density", [-3.0, 7.5], 640, 360),
            ("value", [0.0, 1.0], 320, 240),
            ("von Mises stress", [0.0, 2.5e6], 1280, 720),
            ("J", [0.93, 1.07], 1920, 1080),
            ("", [-1.0e-4, 3.0e-4], 800, 800),
            ("speed", [0.0, 12.0], 3840, 2160),
        ];
        for (label, range, width, height) in cases {
            let legend = Legend::new(label, range, width, height).unwrap();
            let image = [0, 0, width, height];
            let whole = changed_pixels(&legend, image);
            assert!(whole.is_some(), "{label}: the legend changes pixels");
            // The search near the panel finds it all, without the fallback.
            let near = near_window(&legend, width, height);
            let found = changed_pixels(&legend, near);
            assert_eq!(found, whole, "{label} at {width}x{height}");
            assert!(!reaches_inner_edge(found.unwrap(), near, image));
            let area = |[x0, y0, x1, y1]: [u32; 4]| u64::from(x1 - x0) * u64::from(y1 - y0);
            assert!(5 * area(near) < area(image), "{label}: {near:?}");
            let stamp = LegendStamp::new(legend, width, height);
            assert_eq!(
                stamp.footprint(),
                with_margin(whole, width, height),
                "{label} at {width}x{height}"
            );
        }
    }

    #[test]
    fn only_a_window_edge_inside_the_image_sends_the_search_to_the_whole_image() {
        let whole = [0, 0, 100, 50];
        let window = [60, 10, 100, 40];
        // Inside the window, or on its right edge, which is the image's.
        assert!(!reaches_inner_edge([61, 11, 100, 39], window, whole));
        // On its left, top or bottom edge, which are inside the image.
        assert!(reaches_inner_edge([60, 11, 99, 39], window, whole));
        assert!(reaches_inner_edge([61, 10, 99, 39], window, whole));
        assert!(reaches_inner_edge([61, 11, 99, 40], window, whole));
        // A window at the image's corner has no inner edge there.
        assert!(!reaches_inner_edge([0, 0, 10, 10], [0, 0, 20, 20], whole));
    }

    #[test]
    fn stamping_equals_drawing_whatever_is_under_the_legend() {
        let legend = Legend::new("value", [0.0, 1.0], 320, 240).unwrap();
        let mut stamp = LegendStamp::new(legend.clone(), 320, 240);
        let backgrounds = [
            RgbaImage::from_pixel(320, 240, image::Rgba([242, 242, 242, 255])),
            RgbaImage::from_pixel(320, 240, image::Rgba([242, 242, 242, 255])),
            noise(320, 240, 3),
            noise(320, 240, 3),
            noise(320, 240, 4),
            RgbaImage::from_pixel(320, 240, image::Rgba([242, 242, 242, 255])),
        ];
        for (i, background) in backgrounds.iter().enumerate() {
            let mut drawn = background.clone();
            legend.draw(&mut drawn);
            let mut stamped = background.clone();
            stamp.draw(&mut stamped);
            assert!(drawn == stamped, "image {i} differs");
        }
        // Another image size is drawn in full.
        let mut small = noise(200, 150, 9);
        let mut drawn = small.clone();
        legend.draw(&mut drawn);
        stamp.draw(&mut small);
        assert!(drawn == small);
    }
}
