//! [`FrameImage`]: one rendered frame, either a whole image or the run's
//! fixed base image with a patch over the part that changed.
//!
//! Everything but the body (and in 3D its contact shadow) is the same in
//! every frame of a run: the background, the ground and the legend make the
//! *base*, and a frame is the base with the pixel rectangle around its body
//! replaced (the *patch*, drawn as a tile, see `body_tile` and
//! `scene_tile`). Keeping a frame in that form lets everything downstream
//! work in proportion to what changed instead of to the image:
//!
//! - the PNG file reuses the base's rows, filtered and compressed once per
//!   run, and compresses only the rows the patch crosses (`frame_png`);
//! - the APNG stores only the rectangle that differs from the previous frame
//!   (the union of both patches, `video`);
//! - nothing copies the whole image per frame unless it needs every pixel
//!   (the MP4's raw input, the GIF), and then in three spans: the base's rows
//!   above the patch, the patch's rows composed, the base's rows below.
//!
//! Pixels are RGBA8, opaque, sRGB, row-major with no padding.

use image::RgbaImage;
use std::ops::Range;
use std::sync::{Arc, OnceLock};

use super::frame_png::CompressedRows;

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

/// The fixed part of a run's 2D frames, shared by all of them.
pub(crate) struct FrameBase {
    image: RgbaImage,
    /// The base's rows as a PNG encodes them, made once by whichever PNG
    /// writer needs them first.
    png_rows: OnceLock<Result<CompressedRows, String>>,
}

impl FrameBase {
    /// A base image for the frames of one run.
    pub fn new(image: RgbaImage) -> Arc<Self> {
        Arc::new(FrameBase {
            image,
            png_rows: OnceLock::new(),
        })
    }

    /// The base image.
    #[cfg(test)]
    pub fn image(&self) -> &RgbaImage {
        &self.image
    }

    /// The base's rows filtered and compressed for PNG, made on first use.
    pub fn png_rows(&self) -> &Result<CompressedRows, String> {
        self.png_rows
            .get_or_init(|| CompressedRows::new(&self.image))
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

/// One rendered frame (see the module documentation).
#[derive(Clone)]
pub struct FrameImage {
    form: Form,
}

#[derive(Clone)]
enum Form {
    /// Every pixel of the frame.
    Whole(RgbaImage),
    /// The run's base with `patch` over it (none: the frame is the base).
    Patched {
        base: Arc<FrameBase>,
        patch: Option<Patch>,
    },
}

impl From<RgbaImage> for FrameImage {
    fn from(image: RgbaImage) -> Self {
        FrameImage {
            form: Form::Whole(image),
        }
    }
}

impl FrameImage {
    /// The frame `base` with `patch` over it. The patch lies inside the base.
    pub(crate) fn patched(base: Arc<FrameBase>, patch: Option<Patch>) -> Self {
        if let Some(patch) = &patch {
            let (width, height) = base.image.dimensions();
            let rect = patch.rect;
            debug_assert!(rect.x + rect.width <= width && rect.y + rect.height <= height);
            debug_assert_eq!(patch.pixels.len(), (rect.width * rect.height * 4) as usize);
        }
        FrameImage {
            form: Form::Patched { base, patch },
        }
    }

    /// Width and height in pixels.
    pub fn dimensions(&self) -> (u32, u32) {
        match &self.form {
            Form::Whole(image) => image.dimensions(),
            Form::Patched { base, .. } => base.image.dimensions(),
        }
    }

    /// The whole image.
    pub fn to_rgba(&self) -> RgbaImage {
        let (width, height) = self.dimensions();
        let mut pixels = Vec::with_capacity((width * height * 4) as usize);
        self.for_each_rgba_span(&mut Vec::new(), |span| pixels.extend_from_slice(span));
        RgbaImage::from_raw(width, height, pixels).expect("the spans hold every pixel")
    }

    /// Hands every pixel, in order, to `span` as a few contiguous pieces:
    /// the whole image, or the base's rows above the patch, the patch's rows
    /// composed in `scratch`, and the base's rows below.
    pub(crate) fn for_each_rgba_span(&self, scratch: &mut Vec<u8>, mut span: impl FnMut(&[u8])) {
        match &self.form {
            Form::Whole(image) => span(image.as_raw()),
            Form::Patched { base, patch } => {
                let raw: &[u8] = base.image.as_raw();
                let stride = base.image.width() as usize * 4;
                let Some(patch) = patch else {
                    span(raw);
                    return;
                };
                let rows = patch.rect.rows();
                let (start, end) = (rows.start as usize * stride, rows.end as usize * stride);
                scratch.clear();
                for y in rows {
                    self.push_rgba_row(y, scratch);
                }
                span(&raw[..start]);
                span(scratch);
                span(&raw[end..]);
            }
        }
    }

    /// The base this frame is a patch over, and the rectangle in which it
    /// differs from it (`None`: it is the base); `None` for a whole image.
    pub(crate) fn over_base(&self) -> Option<(&Arc<FrameBase>, Option<PixelRect>)> {
        match &self.form {
            Form::Whole(_) => None,
            Form::Patched { base, patch } => Some((base, patch.as_ref().map(|p| p.rect))),
        }
    }

    /// Appends the RGBA pixels of the whole row `y` to `rgba`.
    pub(crate) fn push_rgba_row(&self, y: u32, rgba: &mut Vec<u8>) {
        match &self.form {
            Form::Whole(image) => rgba.extend_from_slice(&image.as_raw()[row_bytes(image, y)]),
            Form::Patched { base, patch } => {
                let start = rgba.len();
                rgba.extend_from_slice(&base.image.as_raw()[row_bytes(&base.image, y)]);
                if let Some(patch) = patch.as_ref().filter(|p| p.rect.rows().contains(&y)) {
                    let x = start + patch.rect.x as usize * 4;
                    let source = patch.row(y);
                    rgba[x..x + source.len()].copy_from_slice(source);
                }
            }
        }
    }

    /// Appends the RGB pixels of row `y`, columns `columns`, to `rgb`.
    pub(crate) fn push_rgb_row(&self, y: u32, columns: Range<u32>, rgb: &mut Vec<u8>) {
        let pixel_bytes = |range: Range<u32>| range.start as usize * 4..range.end as usize * 4;
        match &self.form {
            Form::Whole(image) => {
                let row = &image.as_raw()[row_bytes(image, y)];
                push_rgb(&row[pixel_bytes(columns)], rgb);
            }
            Form::Patched { base, patch } => {
                let row = &base.image.as_raw()[row_bytes(&base.image, y)];
                let Some(patch) = patch.as_ref().filter(|p| p.rect.rows().contains(&y)) else {
                    push_rgb(&row[pixel_bytes(columns)], rgb);
                    return;
                };
                let over = patch.rect.x..patch.rect.x + patch.rect.width;
                let left = columns.start..columns.end.min(over.start);
                let middle = columns.start.max(over.start)..columns.end.min(over.end);
                let right = columns.start.max(over.end)..columns.end;
                if !left.is_empty() {
                    push_rgb(&row[pixel_bytes(left)], rgb);
                }
                if !middle.is_empty() {
                    let inside = middle.start - over.start..middle.end - over.start;
                    push_rgb(&patch.row(y)[pixel_bytes(inside)], rgb);
                }
                if !right.is_empty() {
                    push_rgb(&row[pixel_bytes(right)], rgb);
                }
            }
        }
    }

    /// Appends the RGB pixels of `rect` to `rgb`, row by row.
    pub(crate) fn push_rgb_rect(&self, rect: PixelRect, rgb: &mut Vec<u8>) {
        rgb.reserve((rect.width * rect.height * 3) as usize);
        for y in rect.rows() {
            self.push_rgb_row(y, rect.x..rect.x + rect.width, rgb);
        }
    }
}

/// The byte range of row `y` of `image`.
fn row_bytes(image: &RgbaImage, y: u32) -> Range<usize> {
    let stride = image.width() as usize * 4;
    y as usize * stride..(y as usize + 1) * stride
}

/// Appends the RGB channels of the opaque RGBA pixels `rgba` to `rgb`.
pub(crate) fn push_rgb(rgba: &[u8], rgb: &mut Vec<u8>) {
    let start = rgb.len();
    rgb.resize(start + rgba.len() / 4 * 3, 0);
    for (to, from) in rgb[start..].chunks_exact_mut(3).zip(rgba.chunks_exact(4)) {
        to.copy_from_slice(&from[..3]);
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The base with `rect` taken from `over`.
    fn composed(base: &RgbaImage, over: &RgbaImage, rect: PixelRect) -> RgbaImage {
        let mut image = base.clone();
        for y in rect.rows() {
            for x in rect.x..rect.x + rect.width {
                image.put_pixel(x, y, *over.get_pixel(x, y));
            }
        }
        image
    }

    fn rgb_of(image: &RgbaImage, rect: PixelRect) -> Vec<u8> {
        let mut rgb = Vec::new();
        for y in rect.rows() {
            for x in rect.x..rect.x + rect.width {
                rgb.extend_from_slice(&image.get_pixel(x, y).0[..3]);
            }
        }
        rgb
    }

    #[test]
    fn a_patched_frame_is_its_base_with_the_patch_pasted() {
        let (base, over) = (noise(37, 23, 1), noise(37, 23, 2));
        let shared = FrameBase::new(base.clone());
        let rects = [
            PixelRect::new(5, 3, 9, 7),
            PixelRect::new(0, 0, 37, 23),
            PixelRect::new(36, 22, 1, 1),
            PixelRect::new(0, 10, 1, 13),
        ];
        for rect in rects {
            let patch = Patch::cut(&over, rect);
            let want = composed(&base, &over, rect);
            let mut pasted = base.clone();
            patch.paste_into(&mut pasted);
            assert!(pasted == want, "{rect:?} pasted");
            let frame = FrameImage::patched(shared.clone(), Some(patch));
            assert!(frame.to_rgba() == want, "{rect:?}");
            assert_eq!(frame.over_base().unwrap().1, Some(rect));
            // Any rectangle's RGB, across and around the patch.
            for probe in [
                PixelRect::new(0, 0, 37, 23),
                PixelRect::new(4, 2, 11, 9),
                PixelRect::new(7, 5, 3, 2),
                PixelRect::new(20, 15, 17, 8),
            ] {
                let mut rgb = Vec::new();
                frame.push_rgb_rect(probe, &mut rgb);
                assert_eq!(rgb, rgb_of(&want, probe), "{rect:?} probed at {probe:?}");
            }
        }
        let plain = FrameImage::patched(shared, None);
        assert!(plain.to_rgba() == base);
        assert_eq!(plain.over_base().unwrap().1, None);
    }

    #[test]
    fn a_whole_frame_is_its_image() {
        let image = noise(8, 5, 3);
        let frame = FrameImage::from(image.clone());
        assert!(frame.to_rgba() == image);
        assert!(frame.over_base().is_none());
        let probe = PixelRect::new(2, 1, 5, 3);
        let mut rgb = Vec::new();
        frame.push_rgb_rect(probe, &mut rgb);
        assert_eq!(rgb, rgb_of(&image, probe));
    }

    #[test]
    fn rgb_drops_alpha() {
        let mut rgb = vec![9];
        push_rgb(&[1, 2, 3, 255, 4, 5, 6, 255], &mut rgb);
        assert_eq!(rgb, [9, 1, 2, 3, 4, 5, 6]);
    }

    #[test]
    fn rectangles_unite_and_intersect() {
        let a = PixelRect::new(2, 3, 4, 5);
        let b = PixelRect::new(6, 1, 2, 2);
        assert_eq!(a.union(&b), PixelRect::new(2, 1, 6, 7));
        assert!(!a.intersects(&b), "touching edges share no pixel");
        let c = PixelRect::new(5, 7, 3, 3);
        assert!(a.intersects(&c) && c.intersects(&a));
        assert_eq!(a.rows(), 3..8);
    }
}
