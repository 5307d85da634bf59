//! [`PixelRect`]: a rectangle of whole pixels, and [`Patch`]: the pixels of
//! one, cut from an image or pasted into it; [`projected_rect`]: the pixels
//! that points seen by a camera can touch.

use image::RgbaImage;
use nalgebra::{Matrix4, Vector4};
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

    /// The rectangle grown to start on an even pixel (its far edges kept).
    pub fn grown_to_even_pixel(&self) -> PixelRect {
        let (x, y) = (self.x & !1, self.y & !1);
        PixelRect::new(x, y, self.width + (self.x - x), self.height + (self.y - y))
    }

    /// Whether the two share a pixel.
    pub fn intersects(&self, other: &PixelRect) -> bool {
        self.x < other.x + other.width
            && other.x < self.x + self.width
            && self.y < other.y + other.height
            && other.y < self.y + self.height
    }
}

/// The pixel rectangle holding the projections of `points` by `view_proj`,
/// `reach` pixels further all round, clamped to the `width × height` image:
/// `None` when it is entirely outside, the whole image when a point does not
/// project to a finite pixel in front of the eye (clip `w > 0`).
pub(crate) fn projected_rect(
    view_proj: &Matrix4<f32>,
    points: impl IntoIterator<Item = [f32; 3]>,
    reach: f32,
    width: u32,
    height: u32,
) -> Option<PixelRect> {
    let (w, h) = (width as f32, height as f32);
    let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
    for point in points {
        let clip = view_proj * Vector4::new(point[0], point[1], point[2], 1.0);
        let p = [
            (clip.x / clip.w + 1.0) * 0.5 * w,
            (1.0 - clip.y / clip.w) * 0.5 * h,
        ];
        if !(clip.w > 0.0 && p.iter().all(|c| c.is_finite())) {
            return Some(PixelRect::new(0, 0, width, height));
        }
        for axis in 0..2 {
            lo[axis] = lo[axis].min(p[axis] - reach);
            hi[axis] = hi[axis].max(p[axis] + reach);
        }
    }
    if lo[0] > hi[0] {
        return None;
    }
    let clamp = |c: f32, size: u32| c.clamp(0.0, size as f32) as u32;
    let (x0, x1) = (clamp(lo[0].floor(), width), clamp(hi[0].ceil(), width));
    let (y0, y1) = (clamp(lo[1].floor(), height), clamp(hi[1].ceil(), height));
    (x1 > x0 && y1 > y0).then_some(PixelRect::new(x0, y0, x1 - x0, y1 - y0))
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
/// moves or blends pixels: no two neighbours are alike by chance.
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_projected_rect_holds_every_point_with_its_reach() {
        // Clip = world: pixel x = (x + 1) 50, y = (1 - y) 25 in a 100 x 50 image.
        let identity = Matrix4::identity();
        let points = [[-0.5, 0.0, 0.0], [0.0, 0.5, 0.0], [0.25, -0.25, 0.0]];
        // The points span pixels x in [25, 62.5], y in [12.5, 31.25].
        let rect = projected_rect(&identity, points, 2.0, 100, 50).unwrap();
        assert_eq!(rect, PixelRect::new(23, 10, 65 - 23, 34 - 10));
        assert_eq!(rect.grown_to_even_pixel(), PixelRect::new(22, 10, 43, 24));
        // Clamped to the image, and nothing when all of it is outside.
        let wide = [[-3.0, -3.0, 0.0], [0.0, 0.0, 0.0]];
        let rect = projected_rect(&identity, wide, 2.0, 100, 50).unwrap();
        assert_eq!((rect.x, rect.y, rect.width, rect.height), (0, 23, 52, 27));
        let outside = [[5.0, 5.0, 0.0], [6.0, 7.0, 0.0]];
        assert_eq!(projected_rect(&identity, outside, 2.0, 100, 50), None);
        assert_eq!(projected_rect(&identity, [], 2.0, 100, 50), None);
        // A position that projects nowhere gives the whole image.
        let broken = [[f32::NAN, 0.0, 0.0], [0.0, 0.0, 0.0]];
        let rect = projected_rect(&identity, broken, 2.0, 100, 50).unwrap();
        assert_eq!((rect.x, rect.y, rect.width, rect.height), (0, 0, 100, 50));
        // So does one behind the eye: with clip w = z, a point at z = −1
        // would project, mirrored, to a finite pixel.
        let mut w_is_z = identity;
        w_is_z[(3, 3)] = 0.0;
        w_is_z[(3, 2)] = 1.0;
        let in_front = [[0.2, 0.1, 1.0], [0.3, 0.2, 1.0]];
        assert!(
            projected_rect(&w_is_z, in_front, 2.0, 100, 50)
                .unwrap()
                .width
                < 100
        );
        let behind = [[0.2, 0.1, 1.0], [0.3, 0.2, -1.0]];
        let rect = projected_rect(&w_is_z, behind, 2.0, 100, 50).unwrap();
        assert_eq!((rect.x, rect.y, rect.width, rect.height), (0, 0, 100, 50));
    }

    #[test]
    fn a_patch_cut_and_pasted_moves_exactly_its_pixels() {
        let (from, mut to) = (noise(40, 30, 1), noise(40, 30, 2));
        let before = to.clone();
        let rect = PixelRect::new(5, 7, 11, 13);
        Patch::cut(&from, rect).paste_into(&mut to);
        for (x, y, pixel) in to.enumerate_pixels() {
            let inside = (5..16).contains(&x) && (7..20).contains(&y);
            let expected = if inside {
                from.get_pixel(x, y)
            } else {
                before.get_pixel(x, y)
            };
            assert_eq!(pixel, expected, "({x}, {y})");
        }
        let union = PixelRect::new(2, 3, 4, 5).union(&PixelRect::new(10, 1, 2, 2));
        assert_eq!(union, PixelRect::new(2, 1, 10, 7));
        assert!(union.intersects(&PixelRect::new(11, 7, 5, 5)));
        assert!(!union.intersects(&PixelRect::new(12, 0, 5, 5)));
    }
}
