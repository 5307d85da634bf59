//! [`Yuv420Frames`]: frames as the YUV 4:2:0 planes the MP4's encoder
//! takes.
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
use image::RgbaImage;
use yuv::{BufferStoreMut, YuvConversionMode, YuvPlanarImageMut, YuvRange, YuvStandardMatrix};

/// The size of the planes of frames of `size` pixels: rounded up to even
/// numbers.
pub(crate) fn padded_size((width, height): (u32, u32)) -> (u32, u32) {
    (width.next_multiple_of(2), height.next_multiple_of(2))
}

/// Converts the frames of one run (see the module documentation).
pub(crate) struct Yuv420Frames {
    /// The frames' size in pixels.
    size: (u32, u32),
    /// The size rounded up to even numbers.
    padded: (u32, u32),
    /// The colour of the padding, sRGB.
    background: [u8; 3],
    /// The padded RGBA rows, for odd sizes.
    rgba: Vec<u8>,
    /// The latest frame's planes, `Y`, `Cb`, `Cr` one after the other.
    planes: Vec<u8>,
}

impl Yuv420Frames {
    /// A converter for frames of `size` pixels, padded with `background`.
    pub fn new(size: (u32, u32), background: [u8; 3]) -> Self {
        Yuv420Frames {
            size,
            padded: padded_size(size),
            background,
            rgba: Vec::new(),
            planes: Vec::new(),
        }
    }

    /// `frame`'s planes, `Y` then `Cb` then `Cr`, each row-major with no
    /// padding between rows (the I420 layout).
    pub fn convert(&mut self, frame: &RgbaImage) -> &[u8] {
        debug_assert_eq!(frame.dimensions(), self.size);
        let rgba: &[u8] = if self.padded == self.size {
            frame.as_raw()
        } else {
            let [r, g, b] = self.background;
            let pad = [r, g, b, 255];
            self.rgba.clear();
            for row in frame.as_raw().chunks_exact(self.size.0 as usize * 4) {
                self.rgba.extend_from_slice(row);
                if self.padded.0 > self.size.0 {
                    self.rgba.extend_from_slice(&pad);
                }
            }
            if self.padded.1 > self.size.1 {
                self.rgba
                    .extend(std::iter::repeat_n(pad, self.padded.0 as usize).flatten());
            }
            &self.rgba
        };
        let (width, height) = self.padded;
        let luma = (width * height) as usize;
        self.planes.resize(luma * 3 / 2, 0);
        let (y, chroma) = self.planes.split_at_mut(luma);
        let (cb, cr) = chroma.split_at_mut(luma / 4);
        let mut image = YuvPlanarImageMut {
            y_plane: BufferStoreMut::Borrowed(y),
            y_stride: width,
            u_plane: BufferStoreMut::Borrowed(cb),
            u_stride: width / 2,
            v_plane: BufferStoreMut::Borrowed(cr),
            v_stride: width / 2,
            width,
            height,
        };
        yuv::rgba_to_yuv420(
            &mut image,
            rgba,
            width * 4,
            YuvRange::Limited,
            YuvStandardMatrix::Bt709,
            YuvConversionMode::Balanced,
        )
        .expect("the planes and rows are sized for the padded image");
        &self.planes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// All of `frame`'s planes, joined.
    fn planes_of(frames: &mut Yuv420Frames, frame: &RgbaImage) -> Vec<u8> {
        frames.convert(frame).to_vec()
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
            let planes = planes_of(&mut frames, &image);
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
        let planes = planes_of(&mut frames, &image);
        assert_eq!(planes.len(), 16 + 4 + 4);
        let luma = |x: usize, y: usize| planes[y * 4 + x];
        assert_eq!((luma(0, 0), luma(2, 2)), (235, 235));
        assert_eq!((luma(3, 0), luma(0, 3), luma(3, 3)), (16, 16, 16));
    }
}
