//! Video writers, fed one frame at a time so nothing holds the whole run.
//!
//! Each writer writes to a hidden temporary file beside its final name; the
//! export renames it only when the whole run succeeded, so a failed run never
//! leaves a video that looks complete.
//!
//! - APNG (`video.png`): the `png` crate, RGB, fast compression, frame delay
//!   from the frame rate as an exact fraction where possible.
//! - MP4 (`video.mp4`): raw RGBA frames piped to `ffmpeg`, H.264 (libx264),
//!   yuv420p with BT.709 colours, dimensions padded to even numbers with the
//!   background colour.
//! - GIF (`video.gif`): the `gif` crate, one NeuQuant palette per frame.
//!   Viewers treat GIF delays under 2/100 s as 1/10 s, so above 50 frames per
//!   second the GIF keeps every n-th frame and plays at `fps / n`.

use super::image_file::{png_error, rgba_to_rgb, temporary_path};
use super::{RenderError, VideoFormat};
use image::RgbaImage;
use std::fs::File;
use std::io::{BufWriter, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};

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
    fn push(&mut self, frame: &RgbaImage) -> Result<(), RenderError>;
    /// Completes the temporary file.
    fn finish(self: Box<Self>) -> Result<(), RenderError>;
}

/// Opens a writer for `format`, writing to the temporary path of `spec.path`.
pub(crate) fn open(
    format: VideoFormat,
    spec: &VideoSpec<'_>,
) -> Result<Box<dyn VideoWriter>, RenderError> {
    Ok(match format {
        VideoFormat::Apng => Box::new(ApngWriter::new(spec)?),
        VideoFormat::Mp4 => Box::new(Mp4Writer::new(spec)?),
        VideoFormat::Gif => Box::new(GifWriter::new(spec)?),
    })
}

fn create(path: &Path) -> Result<BufWriter<File>, RenderError> {
    let temporary = temporary_path(path);
    File::create(&temporary)
        .map(|file| BufWriter::with_capacity(1 << 20, file))
        .map_err(|source| RenderError::Io {
            path: path.to_owned(),
            source,
        })
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
    rgb: Vec<u8>,
}

impl ApngWriter {
    fn new(spec: &VideoSpec<'_>) -> Result<Self, RenderError> {
        let encode_error = |e: png::EncodingError| png_error(spec.path, e);
        let frames = u32::try_from(spec.frame_count).map_err(|_| RenderError::Encode {
            path: spec.path.to_owned(),
            message: format!("{} frames are too many for APNG", spec.frame_count),
        })?;
        let mut encoder = png::Encoder::new(create(spec.path)?, spec.width, spec.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::Fast);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        encoder.set_animated(frames, 0).map_err(encode_error)?;
        let (numerator, denominator) = frame_delay(spec.fps);
        encoder
            .set_frame_delay(numerator, denominator)
            .map_err(encode_error)?;
        let writer = encoder.write_header().map_err(encode_error)?;
        Ok(Self {
            path: spec.path.to_owned(),
            writer,
            rgb: Vec::new(),
        })
    }
}

impl VideoWriter for ApngWriter {
    fn push(&mut self, frame: &RgbaImage) -> Result<(), RenderError> {
        rgba_to_rgb(frame, &mut self.rgb);
        self.writer
            .write_image_data(&self.rgb)
            .map_err(|e| png_error(&self.path, e))
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
    fn new(spec: &VideoSpec<'_>) -> Result<Self, RenderError> {
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
            gif::Encoder::new(create(spec.path)?, width, height, &[]).map_err(gif_error)?;
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
    fn push(&mut self, frame: &RgbaImage) -> Result<(), RenderError> {
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

struct Mp4Writer {
    path: PathBuf,
    child: Child,
    stdin: Option<ChildStdin>,
    stderr: Option<std::thread::JoinHandle<String>>,
}

/// The ffmpeg arguments for `spec`, writing MP4 to `output`.
pub(crate) fn ffmpeg_arguments(spec: &VideoSpec<'_>, output: &Path) -> Vec<String> {
    let [r, g, b] = spec.background;
    let mut args: Vec<String> = [
        "-hide_banner",
        "-loglevel",
        "error",
        "-nostdin",
        "-y",
        "-f",
        "rawvideo",
        "-pix_fmt",
        "rgba",
        "-s",
    ]
    .map(String::from)
    .into();
    args.push(format!("{}x{}", spec.width, spec.height));
    args.push("-r".into());
    args.push(format!("{}", spec.fps));
    args.extend(
        [
            "-i", "-", "-c:v", "libx264", "-preset", "medium", "-crf", "18", "-pix_fmt", "yuv420p",
        ]
        .map(String::from),
    );
    args.push("-vf".into());
    args.push(format!(
        "pad=ceil(iw/2)*2:ceil(ih/2)*2:0:0:color=0x{r:02x}{g:02x}{b:02x},scale=out_color_matrix=bt709:out_range=tv"
    ));
    args.extend(
        [
            "-colorspace",
            "bt709",
            "-color_primaries",
            "bt709",
            "-color_trc",
            "bt709",
            "-movflags",
            "+faststart",
            "-f",
            "mp4",
        ]
        .map(String::from),
    );
    args.push(output.to_string_lossy().into_owned());
    args
}

impl Mp4Writer {
    fn new(spec: &VideoSpec<'_>) -> Result<Self, RenderError> {
        let temporary = temporary_path(spec.path);
        let mut child = Command::new("ffmpeg")
            .args(ffmpeg_arguments(spec, &temporary))
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| match e.kind() {
                std::io::ErrorKind::NotFound => RenderError::FfmpegMissing,
                _ => RenderError::Ffmpeg {
                    path: spec.path.to_owned(),
                    message: format!("cannot start ffmpeg: {e}"),
                },
            })?;
        let stdin = child.stdin.take();
        // Drain stderr on a thread so that a chatty ffmpeg never blocks on it.
        let stderr = child.stderr.take().map(|mut pipe| {
            std::thread::spawn(move || {
                let mut text = String::new();
                let _ = pipe.read_to_string(&mut text);
                text
            })
        });
        Ok(Self {
            path: spec.path.to_owned(),
            child,
            stdin,
            stderr,
        })
    }

    /// Waits for ffmpeg and turns a failure into an error with its output.
    fn wait(&mut self) -> Result<(), RenderError> {
        self.stdin = None;
        let status = self.child.wait().map_err(|e| RenderError::Ffmpeg {
            path: self.path.clone(),
            message: format!("cannot wait for ffmpeg: {e}"),
        })?;
        let output = self
            .stderr
            .take()
            .and_then(|h| h.join().ok())
            .unwrap_or_default();
        if status.success() {
            Ok(())
        } else {
            let output = output.trim();
            Err(RenderError::Ffmpeg {
                path: self.path.clone(),
                message: if output.is_empty() {
                    format!("{status}")
                } else {
                    format!("{status}: {output}")
                },
            })
        }
    }
}

impl VideoWriter for Mp4Writer {
    fn push(&mut self, frame: &RgbaImage) -> Result<(), RenderError> {
        let Some(stdin) = self.stdin.as_mut() else {
            return Err(RenderError::Ffmpeg {
                path: self.path.clone(),
                message: "ffmpeg input already closed".into(),
            });
        };
        if let Err(e) = stdin.write_all(frame.as_raw()) {
            // ffmpeg quit early; its own message says why.
            self.wait()?;
            return Err(RenderError::Ffmpeg {
                path: self.path.clone(),
                message: format!("ffmpeg stopped reading frames: {e}"),
            });
        }
        Ok(())
    }

    fn finish(mut self: Box<Self>) -> Result<(), RenderError> {
        self.wait()
    }
}

impl Drop for Mp4Writer {
    fn drop(&mut self) {
        // An abandoned encode: close its input and reap the process.
        if self.stdin.take().is_some() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_delays_are_exact_fractions() {
        assert_eq!(frame_delay(30.0), (1, 30));
        assert_eq!(frame_delay(24.0), (1, 24));
        assert_eq!(frame_delay(0.5), (2, 1));
        let (n, d) = frame_delay(29.97);
        assert!((d as f64 / n as f64 - 29.97).abs() < 1e-9, "{n}/{d}");
    }

    #[test]
    fn ffmpeg_pads_to_even_sizes_in_the_background_colour() {
        let spec = VideoSpec {
            path: Path::new("v.mp4"),
            width: 101,
            height: 61,
            frame_count: 3,
            fps: 25.0,
            background: [245, 245, 250],
        };
        let args = ffmpeg_arguments(&spec, Path::new(".v.mp4.partial"));
        let joined = args.join(" ");
        assert!(joined.contains("-s 101x61 -r 25 -i -"), "{joined}");
        assert!(
            joined.contains("pad=ceil(iw/2)*2:ceil(ih/2)*2:0:0:color=0xf5f5fa"),
            "{joined}"
        );
        assert!(
            joined.contains("-c:v libx264") && joined.contains("-pix_fmt yuv420p"),
            "{joined}"
        );
        assert_eq!(args.last().unwrap(), ".v.mp4.partial");
    }
}
