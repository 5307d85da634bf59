//! [`PixelRect`]: a rectangle of whole pixels, and [`Patch`]: the pixels of one, cut from an image or pasted into it.

use image::RgbaImage;
use std::ops::Range;

/// A rectangle of whole pixels in the image, `[x, x + width) × [y, y + height)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct PixelRect {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

impl PixelRect {
    /// `[x, x + width) × [y, y + height)`.
    pub const fn new(x: u32, y: u32, width: u32, height: u32) -> Self {
        PixelRect {
            x,
            y,
            width,
            height,
        }
    }

    /// The rows it covers.
    pub fn rows(&self) -> Range<u32> {
        self.y..self.y + self.height
    }

    /// The smallest rectangle holding both.
    pub fn union(&self, other: &PixelRect) -> PixelRect {
        let (x0, y0) = (self.x.min(other.x), self.y.min(other.y));
        let x1 = (self.x + self.width).max(other.x + other.width);
        let y1 = (self.y + self.height).max(other.y + other.height);
        PixelRect {
            x: x0,
            y: y0,
            width: x1 - x0,
            height: y1 - y0,
        }
    }

    /// Whether the two share a pixel.
    pub fn intersects(&self, other: &PixelRect) -> bool {
        self.x < other.x + other.width
            && other.x < self.x + self.width
            && self.y < other.y + other.height
            && other.y < self.y + self.height
    }
}

/// The pixels of a rectangle, RGBA8, `rect.width * 4` bytes per row.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Patch {
    pub rect: PixelRect,
    pub pixels: Vec<u8>,
}

impl Patch {
    /// The pixels of `rect` in `image`.
    #[cfg(test)]
    pub fn cut(image: &RgbaImage, rect: PixelRect) -> Patch {
        let mut pixels = Vec::with_capacity((rect.width * rect.height * 4) as usize);
        let columns = rect.x as usize * 4..(rect.x + rect.width) as usize * 4;
        for y in rect.rows() {
            pixels.extend_from_slice(&image.as_raw()[row_bytes(image, y)][columns.clone()]);
        }
        Patch { rect, pixels }
    }

    /// Copies the patch into `image` at its place.
    pub fn paste_into(&self, image: &mut RgbaImage) {
        let columns = self.rect.x as usize * 4..(self.rect.x + self.rect.width) as usize * 4;
        for y in self.rect.rows() {
            let row = row_bytes(image, y);
            let target: &mut [u8] = image;
            target[row][columns.clone()].copy_from_slice(self.row(y));
        }
    }

    /// The patch's part of image row `y` (which it must cover).
    fn row(&self, y: u32) -> &[u8] {
        let stride = self.rect.width as usize * 4;
        let start = (y - self.rect.y) as usize * stride;
        &self.pixels[start..start + stride]
    }
}

/// The byte range of row `y` of `image`.
fn row_bytes(image: &RgbaImage, y: u32) -> Range<usize> {
    let stride = image.width() as usize * 4;
    y as usize * stride..(y as usize + 1) * stride
}

/// A deterministic opaque noise image (xorshift), for tests of code that
/// moves pixels: no two neighbours are alike by chance.
#[cfg(test)]
pub(crate) fn noise(width: u32, height: u32, seed: u32) -> RgbaImage {
    let mut state = seed.wrapping_mul(2_654_435_761) | 1;
    RgbaImage::from_fn(width, height, |_, _| {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        let [r, g, b, _] = state.to_le_bytes();
        image::Rgba([r, g, b, 255])
    })
}
