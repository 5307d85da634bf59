//! [`Yuv420Frames`]: frames as the YUV 4:2:0 planes the MP4's encoder
//! takes, converted in proportion to what changed.
//!
//! H.264 video is stored as luma `Y` at every pixel and the chroma `Cb`,
//! `Cr` at one sample per 2x2 block. The frames are 8-bit sRGB; with
//! `R', G', B'` in [0, 1], BT.709 in limited ("TV") range is
//!
//! ```text
//! E  = 0.2126 R' + 0.7152 G' + 0.0722 B'
//! Y  = 16  + 219 E
//! Cb = 128 + 224 (B' − E) / 1.8556
//! Cr = 128 + 224 (R' − E) / 1.5748
//! ```
//!
//! with each block's chroma from its four pixels (the `yuv` crate's
//! `rgba_to_yuv420`; the MP4 is tagged BT.709, limited range, so players
//! invert exactly this). 4:2:0 needs even dimensions: an odd width or height
//! is padded on the right or at the bottom with the background colour.
//!
//! A frame over its run's base ([`FrameImage`]) differs from the base only
//! in the rows its patch crosses, and a 2x2 block depends on its own two
//! rows only. So the base's planes are converted once per run, and a frame
//! converts only the band of rows `[y0 − y0 mod 2, y1 + y1 mod 2)` around
//! its patch's rows `[y0, y1)`: its planes are the base's rows above the
//! band, the band, the base's rows below, for `Y`, then `Cb`, then `Cr`.
//! The MP4 writer joins those pieces into the one I420 buffer the H.264
//! encoder takes.

use super::frame_image::{FrameBase, FrameImage};
use std::ops::Range;
use std::sync::Arc;
use yuv::{BufferStoreMut, YuvConversionMode, YuvPlanarImageMut, YuvRange, YuvStandardMatrix};

/// The size of the planes of frames of `size` pixels: rounded up to even
/// numbers.
pub(crate) fn padded_size((width, height): (u32, u32)) -> (u32, u32) {
    (width.next_multiple_of(2), height.next_multiple_of(2))
}

/// The Y, Cb and Cr planes of a band of rows of the padded width.
#[derive(Default)]
struct Planes {
    y: Vec<u8>,
    cb: Vec<u8>,
    cr: Vec<u8>,
}

/// Converts the frames of one run (see the module documentation).
pub(crate) struct Yuv420Frames {
    /// The frames' size in pixels.
    size: (u32, u32),
    /// The size rounded up to even numbers.
    padded: (u32, u32),
    /// The colour of the padding, sRGB.
    background: [u8; 3],
    /// The base of the latest frame over one, and its planes.
    base: Option<(Arc<FrameBase>, Planes)>,
    /// The padded RGBA rows being converted.
    rgba: Vec<u8>,
    /// The latest frame's band (or whole planes).
    band: Planes,
}

impl Yuv420Frames {
    /// A converter for frames of `size` pixels, padded with `background`.
    pub fn new(size: (u32, u32), background: [u8; 3]) -> Self {
        Yuv420Frames {
            size,
            padded: padded_size(size),
            background,
            base: None,
            rgba: Vec::new(),
            band: Planes::default(),
        }
    }

    /// Hands `frame`'s planes, `Y` then `Cb` then `Cr`, each row-major with
    /// no padding between rows, to `span` as a few contiguous pieces.
    pub fn for_each_span(&mut self, frame: &FrameImage, mut span: impl FnMut(&[u8])) {
        debug_assert_eq!(frame.dimensions(), self.size);
        let Some((base, changed)) = frame.over_base() else {
            self.convert(frame, 0..self.padded.1, None);
            for plane in [&self.band.y, &self.band.cb, &self.band.cr] {
                span(plane);
            }
            return;
        };
        if !matches!(&self.base, Some((held, _)) if Arc::ptr_eq(held, base)) {
            let mut planes = Planes::default();
            let whole_base = FrameImage::patched(base.clone(), None);
            self.convert(&whole_base, 0..self.padded.1, Some(&mut planes));
            self.base = Some((base.clone(), planes));
        }
        let (_, planes) = self.base.as_ref().expect("held above");
        let Some(changed) = changed else {
            for plane in [&planes.y, &planes.cb, &planes.cr] {
                span(plane);
            }
            return;
        };
        let band = changed.y & !1..(changed.y + changed.height).next_multiple_of(2);
        self.convert(frame, band.clone(), None);
        let (_, planes) = self.base.as_ref().expect("held above");
        let (width, chroma_width) = (self.padded.0 as usize, self.padded.0 as usize / 2);
        let (top, bottom) = (band.start as usize, band.end as usize);
        span(&planes.y[..top * width]);
        span(&self.band.y);
        span(&planes.y[bottom * width..]);
        for (whole, band) in [(&planes.cb, &self.band.cb), (&planes.cr, &self.band.cr)] {
            span(&whole[..top / 2 * chroma_width]);
            span(band);
            span(&whole[bottom / 2 * chroma_width..]);
        }
    }

    /// Converts the padded rows `rows` (an even start and end) of `frame`
    /// into `planes`, or into the band's when `None`.
    fn convert(&mut self, frame: &FrameImage, rows: Range<u32>, planes: Option<&mut Planes>) {
        let [r, g, b] = self.background;
        let pad = [r, g, b, 255];
        self.rgba.clear();
        for y in rows.clone() {
            if y < self.size.1 {
                frame.push_rgba_row(y, &mut self.rgba);
            } else {
                self.rgba
                    .extend(std::iter::repeat_n(pad, self.size.0 as usize).flatten());
            }
            if self.padded.0 > self.size.0 {
                self.rgba.extend_from_slice(&pad);
            }
        }
        let planes = planes.unwrap_or(&mut self.band);
        let (width, height) = (self.padded.0, rows.len() as u32);
        let luma = (width * height) as usize;
        planes.y.resize(luma, 0);
        planes.cb.resize(luma / 4, 0);
        planes.cr.resize(luma / 4, 0);
        let mut image = YuvPlanarImageMut {
            y_plane: BufferStoreMut::Borrowed(&mut planes.y),
            y_stride: width,
            u_plane: BufferStoreMut::Borrowed(&mut planes.cb),
            u_stride: width / 2,
            v_plane: BufferStoreMut::Borrowed(&mut planes.cr),
            v_stride: width / 2,
            width,
            height,
        };
        yuv::rgba_to_yuv420(
            &mut image,
            &self.rgba,
            width * 4,
            YuvRange::Limited,
            YuvStandardMatrix::Bt709,
            YuvConversionMode::Balanced,
        )
        .expect("the planes and rows are sized for the padded image");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::frame_image::{Patch, PixelRect, noise};
    use image::RgbaImage;

    /// All of `frame`'s planes, joined.
    fn planes_of(frames: &mut Yuv420Frames, frame: &FrameImage) -> Vec<u8> {
        let mut planes = Vec::new();
        frames.for_each_span(frame, |span| planes.extend_from_slice(span));
        planes
    }

    #[test]
    fn colours_follow_bt709_in_limited_range() {
        // One 2x2 block of each colour: Y, Cb, Cr (ITU-R BT.709 limited range).
        for (rgb, expected) in [
            ([0, 0, 0], [16, 128, 128]),
            ([255, 255, 255], [235, 128, 128]),
            ([255, 0, 0], [63, 102, 240]),
            ([0, 255, 0], [173, 42, 26]),
            ([0, 0, 255], [32, 240, 118]),
        ] {
            let [r, g, b] = rgb;
            let image = RgbaImage::from_pixel(2, 2, image::Rgba([r, g, b, 255]));
            let mut frames = Yuv420Frames::new((2, 2), [0, 0, 0]);
            let planes = planes_of(&mut frames, &FrameImage::from(image));
            assert_eq!(planes.len(), 4 + 1 + 1);
            let got = [planes[0], planes[4], planes[5]];
            for (g, e) in got.iter().zip(expected) {
                assert!(
                    g.abs_diff(e) <= 1,
                    "{rgb:?}: {got:?}, expected {expected:?}"
                );
            }
            assert!(planes[..4].iter().all(|&y| y == planes[0]));
        }
    }

    #[test]
    fn odd_sizes_are_padded_with_the_background() {
        let image = RgbaImage::from_pixel(3, 3, image::Rgba([255, 255, 255, 255]));
        let mut frames = Yuv420Frames::new((3, 3), [0, 0, 0]);
        assert_eq!(padded_size((3, 3)), (4, 4));
        let planes = planes_of(&mut frames, &FrameImage::from(image));
        assert_eq!(planes.len(), 16 + 4 + 4);
        let luma = |x: usize, y: usize| planes[y * 4 + x];
        assert_eq!((luma(0, 0), luma(2, 2)), (235, 235));
        assert_eq!((luma(3, 0), luma(0, 3), luma(3, 3)), (16, 16, 16));
    }

    #[test]
    fn a_patched_frame_has_the_planes_of_its_whole_image() {
        // Odd sizes and patches on odd and even rows: the band rounds out to
        // whole 2x2 blocks and the padding stays the background.
        let (width, height) = (37, 29);
        let base = FrameBase::new(noise(width, height, 1));
        let mut frames = Yuv420Frames::new((width, height), [10, 20, 30]);
        let mut whole = Yuv420Frames::new((width, height), [10, 20, 30]);
        let rects = [
            PixelRect::new(3, 5, 10, 7),
            PixelRect::new(0, 0, 37, 2),
            PixelRect::new(20, 28, 17, 1),
            PixelRect::new(1, 10, 1, 1),
        ];
        for (seed, rect) in rects.into_iter().enumerate() {
            let patch = Patch::cut(&noise(width, height, 2 + seed as u32), rect);
            let frame = FrameImage::patched(base.clone(), Some(patch));
            let expected = planes_of(&mut whole, &FrameImage::from(frame.to_rgba()));
            assert!(planes_of(&mut frames, &frame) == expected, "{rect:?}");
        }
        // The base itself, after the patched frames.
        let expected = planes_of(&mut whole, &FrameImage::from(base.image().clone()));
        assert!(planes_of(&mut frames, &FrameImage::patched(base, None)) == expected);
    }
}
