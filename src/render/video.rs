//! Video writers, fed one frame at a time so nothing holds the whole run:
//! [`open`] gives the writer of a [`VideoFormat`] behind the one
//! [`VideoWriter`] trait.
//!
//! Two callers use them: the sequence writer (`sequence.rs`) for a run's
//! `video.png`, `video.mp4` and `video.gif`, each on a thread of its own fed
//! in frame order, and [`write_image_video`](super::write_image_video)
//! (`image_video.rs`) for a sweep's `comparison.*`. Each writer writes to the
//! hidden temporary file of a [`PartialFile`] beside its final name; the
//! caller publishes it only when every frame is written, so a failed or
//! interrupted run never leaves a video that looks complete.
//!
//! - APNG (`video.png`): the `png` crate, RGB, fast compression, frame delay
//!   the fraction of a second closest to `1 / fps` ([`frame_delay`]: exact
//!   where a numerator up to 1000 gives it). The first frame
//!   is whole; after it, a frame over the same base as the one before
//!   (`frame_image`) stores only the rectangle where the two can differ, the
//!   union of their patches, drawn over the previous frame (dispose `None`,
//!   blend `Source`), so a small body costs a small frame.
//! - MP4 (`video.mp4`): H.264 encoded in the process with OpenH264 from YUV
//!   4:2:0 planes, muxed with the `mp4` crate (see [`Mp4Writer`]).
//! - GIF (`video.gif`): the `gif` crate, one NeuQuant palette per frame.
//!   Viewers treat GIF delays under 2/100 s as 1/10 s, so above 50 frames per
//!   second the GIF keeps every n-th frame and plays at `fps / n`.

use super::frame_image::{FrameBase, FrameImage, PixelRect};
use super::frame_png::png_encoder;
use super::image_file::png_error;
use super::mp4_writer::Mp4Writer;
use super::partial_file::PartialFile;
use super::{RenderError, VideoFormat};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The file name a video format is written to: `video.png`, `video.mp4`, `video.gif`.
pub fn file_name(format: VideoFormat) -> &'static str {
    match format {
        VideoFormat::Apng => "video.png",
        VideoFormat::Mp4 => "video.mp4",
        VideoFormat::Gif => "video.gif",
    }
}

/// What every video writer needs to know.
pub(crate) struct VideoSpec<'a> {
    /// Final path of the video.
    pub path: &'a Path,
    /// Frame size in pixels.
    pub width: u32,
    /// Frame size in pixels.
    pub height: u32,
    /// Number of frames that will be pushed.
    pub frame_count: usize,
    /// Frames per second.
    pub fps: f64,
    /// Background colour, 8-bit sRGB (MP4 padding).
    pub background: [u8; 3],
}

/// A video being written.
pub(crate) trait VideoWriter: Send {
    /// Appends the next frame.
    fn push(&mut self, frame: &Arc<FrameImage>) -> Result<(), RenderError>;
    /// Completes the temporary file.
    fn finish(self: Box<Self>) -> Result<(), RenderError>;
}

/// Opens a writer for `format`, writing to the temporary file of `partial`
/// (whose final name is `spec.path`).
pub(crate) fn open(
    format: VideoFormat,
    spec: &VideoSpec<'_>,
    partial: &PartialFile,
) -> Result<Box<dyn VideoWriter>, RenderError> {
    Ok(match format {
        VideoFormat::Apng => Box::new(ApngWriter::new(spec, partial)?),
        VideoFormat::Mp4 => Box::new(Mp4Writer::new(spec, partial)?),
        VideoFormat::Gif => Box::new(GifWriter::new(spec, partial)?),
    })
}

fn create(partial: &PartialFile) -> Result<BufWriter<File>, RenderError> {
    partial
        .create()
        .map(|file| BufWriter::with_capacity(1 << 20, file))
}

/// The frame delay `numerator / denominator` seconds closest to `1 / fps`.
pub(crate) fn frame_delay(fps: f64) -> (u16, u16) {
    let mut best = (1u16, fps.round().clamp(1.0, u16::MAX as f64) as u16);
    let mut best_error = f64::INFINITY;
    for numerator in 1..=1000u16 {
        let denominator = (fps * numerator as f64).round();
        if denominator < 1.0 || denominator > u16::MAX as f64 {
            continue;
        }
        let error = (denominator / numerator as f64 - fps).abs();
        if error < best_error - 1e-12 {
            best = (numerator, denominator as u16);
            best_error = error;
        }
        if error < 1e-9 {
            break;
        }
    }
    best
}

struct ApngWriter {
    path: PathBuf,
    writer: png::Writer<BufWriter<File>>,
    size: (u32, u32),
    /// The previous frame's base and the rectangle where it differed from
    /// it; `None` before the first frame or after a whole one.
    previous: Option<(Arc<FrameBase>, Option<PixelRect>)>,
    rgb: Vec<u8>,
}

impl ApngWriter {
    fn new(spec: &VideoSpec<'_>, partial: &PartialFile) -> Result<Self, RenderError> {
        let encode_error = |e: png::EncodingError| png_error(spec.path, e);
        let frames = u32::try_from(spec.frame_count).map_err(|_| RenderError::Encode {
            path: spec.path.to_owned(),
            message: format!("{} frames are too many for APNG", spec.frame_count),
        })?;
        let mut encoder = png_encoder(create(partial)?, spec.width, spec.height);
        encoder.set_animated(frames, 0).map_err(encode_error)?;
        let (numerator, denominator) = frame_delay(spec.fps);
        encoder
            .set_frame_delay(numerator, denominator)
            .map_err(encode_error)?;
        let writer = encoder.write_header().map_err(encode_error)?;
        Ok(Self {
            path: spec.path.to_owned(),
            writer,
            size: (spec.width, spec.height),
            previous: None,
            rgb: Vec::new(),
        })
    }

    /// The rectangle of `frame` to store: where it can differ from the
    /// previous frame, or the whole image.
    fn region(&self, frame: &FrameImage) -> PixelRect {
        let (width, height) = self.size;
        let whole = PixelRect::new(0, 0, width, height);
        match (&self.previous, frame.over_base()) {
            (Some((previous_base, before)), Some((base, now)))
                if Arc::ptr_eq(previous_base, base) =>
            {
                match (*before, now) {
                    (Some(before), Some(now)) => before.union(&now),
                    (Some(only), None) | (None, Some(only)) => only,
                    // The same image again: one pixel, unchanged.
                    (None, None) => PixelRect::new(0, 0, 1, 1),
                }
            }
            _ => whole,
        }
    }
}

impl VideoWriter for ApngWriter {
    fn push(&mut self, frame: &Arc<FrameImage>) -> Result<(), RenderError> {
        let encode_error = |e: png::EncodingError| png_error(&self.path, e);
        let region = self.region(frame);
        // Back to the origin first, so that no intermediate rectangle leaves the image.
        self.writer.reset_frame_position().map_err(encode_error)?;
        self.writer
            .set_frame_dimension(region.width, region.height)
            .map_err(encode_error)?;
        self.writer
            .set_frame_position(region.x, region.y)
            .map_err(encode_error)?;
        self.rgb.clear();
        frame.push_rgb_rect(region, &mut self.rgb);
        self.writer
            .write_image_data(&self.rgb)
            .map_err(|e| png_error(&self.path, e))?;
        self.previous = frame
            .over_base()
            .map(|(base, changed)| (base.clone(), changed));
        Ok(())
    }

    fn finish(self: Box<Self>) -> Result<(), RenderError> {
        let path = self.path;
        self.writer.finish().map_err(|e| png_error(&path, e))
    }
}

struct GifWriter {
    path: PathBuf,
    encoder: gif::Encoder<BufWriter<File>>,
    width: u16,
    height: u16,
    fps: f64,
    /// Keep every `stride`-th frame.
    stride: usize,
    pushed: usize,
    written: usize,
    pixels: Vec<u8>,
    scratch: Vec<u8>,
}

impl GifWriter {
    fn new(spec: &VideoSpec<'_>, partial: &PartialFile) -> Result<Self, RenderError> {
        let too_large = || RenderError::Encode {
            path: spec.path.to_owned(),
            message: format!(
                "{}x{} exceeds GIF's limit of 65535 pixels per side",
                spec.width, spec.height
            ),
        };
        let width = u16::try_from(spec.width).map_err(|_| too_large())?;
        let height = u16::try_from(spec.height).map_err(|_| too_large())?;
        let gif_error = |e: gif::EncodingError| gif_error(spec.path, e);
        let mut encoder =
            gif::Encoder::new(create(partial)?, width, height, &[]).map_err(gif_error)?;
        encoder
            .set_repeat(gif::Repeat::Infinite)
            .map_err(gif_error)?;
        let stride = (spec.fps / 50.0).ceil().max(1.0) as usize;
        Ok(Self {
            path: spec.path.to_owned(),
            encoder,
            width,
            height,
            fps: spec.fps / stride as f64,
            stride,
            pushed: 0,
            written: 0,
            pixels: Vec::new(),
            scratch: Vec::new(),
        })
    }
}

impl VideoWriter for GifWriter {
    fn push(&mut self, frame: &Arc<FrameImage>) -> Result<(), RenderError> {
        let index = self.pushed;
        self.pushed += 1;
        if !index.is_multiple_of(self.stride) {
            return Ok(());
        }
        self.pixels.clear();
        frame.for_each_rgba_span(&mut self.scratch, |span| {
            self.pixels.extend_from_slice(span)
        });
        let mut gif_frame =
            gif::Frame::from_rgba_speed(self.width, self.height, &mut self.pixels, 10);
        // Delays in 1/100 s, rounded so that the total stays on time.
        let n = self.written as f64;
        let centiseconds = ((n + 1.0) * 100.0 / self.fps).round() - (n * 100.0 / self.fps).round();
        gif_frame.delay = centiseconds.clamp(2.0, u16::MAX as f64) as u16;
        self.written += 1;
        self.encoder
            .write_frame(&gif_frame)
            .map_err(|e| gif_error(&self.path, e))
    }

    fn finish(self: Box<Self>) -> Result<(), RenderError> {
        let path = self.path;
        let mut file = self.encoder.into_inner().map_err(|e| gif_error(&path, e))?;
        file.flush()
            .map_err(|source| RenderError::Io { path, source })
    }
}

fn gif_error(path: &Path, error: gif::EncodingError) -> RenderError {
    match error {
        gif::EncodingError::Io(source) => RenderError::Io {
            path: path.to_owned(),
            source,
        },
        other => RenderError::Encode {
            path: path.to_owned(),
            message: other.to_string(),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::frame_image::{Patch, noise};
    use image::AnimationDecoder;

    /// Writes `frames` as an APNG and returns the frames a player shows,
    /// with the size of each stored rectangle.
    fn through_apng(frames: &[FrameImage]) -> (Vec<image::RgbaImage>, Vec<(u32, u32)>) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("video.png");
        let (width, height) = frames[0].dimensions();
        let spec = VideoSpec {
            path: &path,
            width,
            height,
            frame_count: frames.len(),
            fps: 25.0,
            background: [0; 3],
        };
        let partial = PartialFile::new(&path).unwrap();
        let mut writer = open(VideoFormat::Apng, &spec, &partial).unwrap();
        for frame in frames {
            writer.push(&Arc::new(frame.clone())).unwrap();
        }
        writer.finish().unwrap();
        partial.publish().unwrap();

        let mut reader = png::Decoder::new(std::io::BufReader::new(File::open(&path).unwrap()))
            .read_info()
            .unwrap();
        let mut buffer = vec![0; reader.output_buffer_size().unwrap()];
        let mut stored = Vec::new();
        while let Ok(info) = reader.next_frame(&mut buffer) {
            stored.push((info.width, info.height));
        }
        let decoder = image::codecs::png::PngDecoder::new(std::io::BufReader::new(
            File::open(&path).unwrap(),
        ))
        .unwrap();
        let shown = decoder
            .apng()
            .unwrap()
            .into_frames()
            .map(|frame| frame.unwrap().into_buffer())
            .collect();
        (shown, stored)
    }

    #[test]
    fn apng_frames_store_what_changed_and_show_whole_frames() {
        let (width, height) = (40, 30);
        let base = FrameBase::new(noise(width, height, 1));
        let other_base = FrameBase::new(noise(width, height, 2));
        let body = noise(width, height, 3);
        let over = |base: &Arc<FrameBase>, rect: Option<PixelRect>| {
            FrameImage::patched(base.clone(), rect.map(|rect| Patch::cut(&body, rect)))
        };
        let frames = [
            over(&base, Some(PixelRect::new(2, 3, 6, 5))),
            // Moved: the union of both patches.
            over(&base, Some(PixelRect::new(5, 4, 6, 5))),
            // Left the image: the last patch's place, back to the base.
            over(&base, None),
            // Nothing changed: one pixel.
            over(&base, None),
            over(&base, Some(PixelRect::new(30, 20, 10, 10))),
            // Another base, then a whole image: stored whole.
            over(&other_base, Some(PixelRect::new(1, 1, 3, 3))),
            FrameImage::from(noise(width, height, 4)),
            over(&base, Some(PixelRect::new(0, 0, 1, 1))),
        ];
        let (shown, stored) = through_apng(&frames);
        assert_eq!(
            stored,
            [
                (40, 30),
                (9, 6),
                (6, 5),
                (1, 1),
                (10, 10),
                (40, 30),
                (40, 30),
                (40, 30)
            ]
        );
        assert_eq!(shown.len(), frames.len());
        for (i, (shown, frame)) in shown.iter().zip(&frames).enumerate() {
            assert!(*shown == frame.to_rgba(), "frame {i} shows differently");
        }
    }

    #[test]
    fn frame_delays_are_exact_fractions() {
        assert_eq!(frame_delay(30.0), (1, 30));
        assert_eq!(frame_delay(24.0), (1, 24));
        assert_eq!(frame_delay(0.5), (2, 1));
        let (n, d) = frame_delay(29.97);
        assert!((d as f64 / n as f64 - 29.97).abs() < 1e-9, "{n}/{d}");
    }
}
