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
//!   where a numerator up to 1000 gives it). The first frame is whole;
//!   after it, each frame stores only the rectangle where it differs from
//!   the one before, drawn over it (dispose `None`, blend `Source`), so a
//!   small body costs a small frame.
//! - MP4 (`video.mp4`): H.264 encoded in the process with OpenH264 from YUV
//!   4:2:0 planes, muxed with the `mp4` crate (see [`Mp4Writer`]).
//! - GIF (`video.gif`): the `gif` crate, one NeuQuant palette per frame.
//!   Viewers treat GIF delays under 2/100 s as 1/10 s, so above 50 frames per
//!   second the GIF keeps every n-th frame and plays at `fps / n`.

use super::image_file::{png_encoder, png_error, push_rgb};
use super::mp4_writer::Mp4Writer;
use super::partial_file::PartialFile;
use super::video_writer::{VideoSpec, VideoWriter, frame_delay};
use super::{RenderError, VideoFormat};
use image::RgbaImage;
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

/// Opens a writer for `format`, writing to the temporary file of `partial`
/// (whose final name is `spec.path`).
pub(super) fn open(
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

struct ApngWriter {
    path: PathBuf,
    writer: png::Writer<BufWriter<File>>,
    /// The previous frame, `None` before the first.
    previous: Option<Arc<RgbaImage>>,
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
            previous: None,
            rgb: Vec::new(),
        })
    }
}

/// The smallest rectangle `[x, y, width, height]` holding every pixel where
/// `now` differs from `before` (one unchanged pixel when none does).
fn changed_rect(before: &RgbaImage, now: &RgbaImage) -> [u32; 4] {
    let width = now.width() as usize;
    let (mut x0, mut x1, mut y0, mut y1) = (usize::MAX, 0, usize::MAX, 0);
    let rows = before.as_raw().chunks_exact(width * 4);
    for (y, (a, b)) in rows.zip(now.as_raw().chunks_exact(width * 4)).enumerate() {
        if a == b {
            continue;
        }
        let pixels = || a.chunks_exact(4).zip(b.chunks_exact(4));
        let first = pixels().position(|(p, q)| p != q).expect("the rows differ");
        let last = width
            - 1
            - pixels()
                .rev()
                .position(|(p, q)| p != q)
                .expect("they differ");
        (x0, x1, y0, y1) = (x0.min(first), x1.max(last), y0.min(y), y);
    }
    if y0 == usize::MAX {
        return [0, 0, 1, 1];
    }
    [x0, y0, x1 - x0 + 1, y1 - y0 + 1].map(|v| v as u32)
}

impl VideoWriter for ApngWriter {
    /// The first frame is stored whole; each later one as the rectangle
    /// where it differs from the one before, drawn over it (dispose `None`,
    /// blend `Source`), so a small moving body costs a small frame.
    fn push(&mut self, frame: &Arc<RgbaImage>) -> Result<(), RenderError> {
        let encode_error = |e: png::EncodingError| png_error(&self.path, e);
        let [x, y, width, height] = match &self.previous {
            Some(previous) => changed_rect(previous, frame),
            None => [0, 0, frame.width(), frame.height()],
        };
        // Back to the origin first, so that no intermediate rectangle leaves the image.
        self.writer.reset_frame_position().map_err(encode_error)?;
        self.writer
            .set_frame_dimension(width, height)
            .map_err(encode_error)?;
        self.writer.set_frame_position(x, y).map_err(encode_error)?;
        self.rgb.clear();
        let columns = x as usize * 4..(x + width) as usize * 4;
        for row in frame
            .as_raw()
            .chunks_exact(frame.width() as usize * 4)
            .skip(y as usize)
            .take(height as usize)
        {
            push_rgb(&row[columns.clone()], &mut self.rgb);
        }
        self.writer
            .write_image_data(&self.rgb)
            .map_err(|e| png_error(&self.path, e))?;
        self.previous = Some(frame.clone());
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
        })
    }
}

impl VideoWriter for GifWriter {
    fn push(&mut self, frame: &Arc<RgbaImage>) -> Result<(), RenderError> {
        let index = self.pushed;
        self.pushed += 1;
        if !index.is_multiple_of(self.stride) {
            return Ok(());
        }
        self.pixels.clear();
        self.pixels.extend_from_slice(frame.as_raw());
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
    use crate::render::noise;
    use image::AnimationDecoder;

    /// Writes `frames` as an APNG and returns the frames a player shows,
    /// with the size of each stored rectangle.
    fn through_apng(frames: &[RgbaImage]) -> (Vec<image::RgbaImage>, Vec<(u32, u32)>) {
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
        let base = noise(width, height, 1);
        let body = noise(width, height, 3);
        // The base with the body's pixels in `[x, y, width, height]`.
        let over = |rect: Option<[u32; 4]>| {
            let mut image = base.clone();
            if let Some([x0, y0, w, h]) = rect {
                for (x, y) in (x0..x0 + w).flat_map(|x| (y0..y0 + h).map(move |y| (x, y))) {
                    image.put_pixel(x, y, *body.get_pixel(x, y));
                }
            }
            image
        };
        let frames = [
            over(Some([2, 3, 6, 5])),
            // Moved: the union of both places.
            over(Some([5, 4, 6, 5])),
            // Left the image: the last place, back to the base.
            over(None),
            // Nothing changed: one pixel.
            over(None),
            over(Some([30, 20, 10, 10])),
            // Everything changed: stored whole.
            noise(width, height, 4),
        ];
        let (shown, stored) = through_apng(&frames);
        assert_eq!(
            stored,
            [(40, 30), (9, 6), (6, 5), (1, 1), (10, 10), (40, 30)]
        );
        assert_eq!(shown.len(), frames.len());
        for (i, (shown, frame)) in shown.iter().zip(&frames).enumerate() {
            assert!(shown == frame, "frame {i} shows differently");
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
