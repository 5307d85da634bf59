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
//! white image: a blend that changes no pixel of either changes no pixel at
//! all (the change `round(c + a (t - c)) - c` is largest in size at
//! `c = 0` or `c = 255`), and a margin of two pixels is added.

use super::frame_image::PixelRect;
use super::legend::Legend;
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
        let mut footprint: Option<[u32; 4]> = None;
        for shade in [0u8, 255] {
            let mut drawn = RgbaImage::from_pixel(width, height, image::Rgba([shade; 4]));
            legend.draw(&mut drawn);
            let changed = drawn
                .as_raw()
                .chunks_exact(4)
                .enumerate()
                .filter(|(_, pixel)| *pixel != [shade; 4]);
            for (index, _) in changed {
                let (x, y) = (index as u32 % width, index as u32 / width);
                let f = footprint.get_or_insert([x, y, x + 1, y + 1]);
                *f = [f[0].min(x), f[1].min(y), f[2].max(x + 1), f[3].max(y + 1)];
            }
        }
        let [x0, y0, x1, y1] = footprint.unwrap_or([0, 0, 0, 0]);
        let margin = 2;
        let footprint = [
            x0.saturating_sub(margin),
            y0.saturating_sub(margin),
            (x1 + margin).min(width),
            (y1 + margin).min(height),
        ];
        Self {
            legend,
            footprint,
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
