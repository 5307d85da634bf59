//! Writing a run: numbered PNG frames and videos.
//!
//! The calling thread renders frame after frame and hands each image to:
//! - PNG workers, through a bounded queue (so memory stays flat however long
//!   the run), which encode with fast compression and write each frame under
//!   a hidden temporary name, renamed once complete;
//! - one thread per video format, through its own bounded queue, in frame
//!   order.
//!
//! Progress is reported on the calling thread, in frame order, as frames are
//! written. The first error stops the run; videos are renamed to their final
//! names only when every frame and every video succeeded.

use super::colormap::linear_to_srgb8;
use super::video::{self, VideoSpec, VideoWriter, rgba_to_rgb, temporary_path};
use super::{
    RenderError, RenderFrame, RenderMesh, RenderOutputs, RenderSettings, Renderer, VideoFormat,
};
use crossbeam_channel::{Receiver, Sender, bounded, unbounded};
use image::RgbaImage;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Arc;

/// Checks, before any simulation, that the requested videos can be written:
/// MP4 needs `ffmpeg` with libx264 on `PATH`. APNG and GIF always can.
pub fn check_video_support(videos: &[VideoFormat]) -> Result<(), RenderError> {
    if !videos.contains(&VideoFormat::Mp4) {
        return Ok(());
    }
    let output = Command::new("ffmpeg")
        .args(["-hide_banner", "-encoders"])
        .stdin(Stdio::null())
        .stderr(Stdio::null())
        .output()
        .map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => RenderError::FfmpegMissing,
            _ => RenderError::Ffmpeg {
                path: "video.mp4".into(),
                message: format!("cannot run ffmpeg: {e}"),
            },
        })?;
    if String::from_utf8_lossy(&output.stdout).contains("libx264") {
        Ok(())
    } else {
        Err(RenderError::FfmpegWithoutH264)
    }
}

/// The file name of frame `index` in a run of `frame_count` frames:
/// `frame_0000.png`, with more digits when the run has more than 10000.
pub fn frame_file_name(index: usize, frame_count: usize) -> String {
    let digits = frame_count
        .saturating_sub(1)
        .max(1)
        .to_string()
        .len()
        .max(4);
    format!("frame_{index:0digits$}.png")
}

/// Writes an opaque RGBA image as an RGB PNG with fast compression and an
/// sRGB chunk, as the frames of a run are written: under a hidden temporary
/// name first, renamed to `path` once complete.
pub fn write_png(path: &Path, image: &RgbaImage) -> Result<(), RenderError> {
    write_png_atomically(path, image, &mut Vec::new())
}

/// [`write_png`] with a reusable RGB buffer.
pub(crate) fn write_png_atomically(
    path: &Path,
    image: &RgbaImage,
    rgb: &mut Vec<u8>,
) -> Result<(), RenderError> {
    let temporary = temporary_path(path);
    let result = (|| {
        let file = File::create(&temporary).map_err(|source| RenderError::Io {
            path: path.to_owned(),
            source,
        })?;
        let mut encoder = png::Encoder::new(
            BufWriter::with_capacity(1 << 18, file),
            image.width(),
            image.height(),
        );
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::Fast);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let encode_error = |e: png::EncodingError| match e {
            png::EncodingError::IoError(source) => RenderError::Io {
                path: path.to_owned(),
                source,
            },
            other => RenderError::Encode {
                path: path.to_owned(),
                message: other.to_string(),
            },
        };
        let mut writer = encoder.write_header().map_err(encode_error)?;
        rgba_to_rgb(image, rgb);
        writer.write_image_data(rgb).map_err(encode_error)?;
        writer.finish().map_err(encode_error)?;
        std::fs::rename(&temporary, path).map_err(|source| RenderError::Io {
            path: path.to_owned(),
            source,
        })
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    result
}

struct Video {
    format: VideoFormat,
    path: PathBuf,
}

pub(crate) fn render_sequence(
    settings: &RenderSettings,
    mesh: &RenderMesh,
    frames: &[RenderFrame],
    outputs: &RenderOutputs,
    progress: &mut dyn FnMut(usize),
) -> Result<(), RenderError> {
    check_video_support(&outputs.videos)?;
    let fps_valid = outputs.fps > 0.0 && outputs.fps.is_finite();
    if !outputs.videos.is_empty() && !fps_valid {
        return Err(RenderError::InvalidInput(format!(
            "video frame rate {} must be positive",
            outputs.fps
        )));
    }
    let mut renderer = Renderer::new(settings, mesh, frames)?;
    create_dir(&outputs.frames_dir)?;
    if !outputs.videos.is_empty() {
        create_dir(&outputs.video_dir)?;
    }

    let mut videos: Vec<Video> = Vec::new();
    for &format in &outputs.videos {
        if !videos.iter().any(|v| v.format == format) {
            videos.push(Video {
                format,
                path: outputs.video_dir.join(video::file_name(format)),
            });
        }
    }
    let result = render_and_write(&mut renderer, settings, frames, outputs, &videos, progress);
    for video in &videos {
        let temporary = temporary_path(&video.path);
        if result.is_ok() {
            std::fs::rename(&temporary, &video.path).map_err(|source| RenderError::Io {
                path: video.path.clone(),
                source,
            })?;
        } else {
            let _ = std::fs::remove_file(&temporary);
        }
    }
    result
}

fn create_dir(dir: &Path) -> Result<(), RenderError> {
    std::fs::create_dir_all(dir).map_err(|source| RenderError::Io {
        path: dir.to_owned(),
        source,
    })
}

fn render_and_write(
    renderer: &mut Renderer,
    settings: &RenderSettings,
    frames: &[RenderFrame],
    outputs: &RenderOutputs,
    videos: &[Video],
    progress: &mut dyn FnMut(usize),
) -> Result<(), RenderError> {
    let frame_count = frames.len();
    let (width, height) = renderer.size();
    let mut writers: Vec<Box<dyn VideoWriter>> = Vec::with_capacity(videos.len());
    for video in videos {
        let spec = VideoSpec {
            path: &video.path,
            width,
            height,
            frame_count,
            fps: outputs.fps,
            background: linear_to_srgb8(settings.background),
        };
        writers.push(video::open(video.format, &spec)?);
    }
    let workers = std::thread::available_parallelism()
        .map_or(2, |n| n.get())
        .clamp(1, 4);

    std::thread::scope(|scope| {
        let (frame_sender, frame_receiver) = bounded::<(usize, Arc<RgbaImage>)>(2 * workers);
        let (done_sender, done_receiver) = unbounded::<Result<usize, RenderError>>();
        for _ in 0..workers {
            let (frames_in, done) = (frame_receiver.clone(), done_sender.clone());
            let dir = &outputs.frames_dir;
            scope.spawn(move || png_worker(dir, frame_count, frames_in, done));
        }
        drop((frame_receiver, done_sender));

        let mut video_senders: Vec<Sender<Arc<RgbaImage>>> = Vec::new();
        let mut video_threads = Vec::new();
        for mut writer in writers {
            let (sender, receiver) = bounded::<Arc<RgbaImage>>(3);
            video_senders.push(sender);
            video_threads.push(scope.spawn(move || -> Result<(), RenderError> {
                for image in receiver {
                    writer.push(&image)?;
                }
                writer.finish()
            }));
        }

        let mut reporter = Reporter {
            written: vec![false; frame_count],
            next: 0,
            progress,
        };
        let mut first_error: Option<RenderError> = None;
        'frames: for (index, frame) in frames.iter().enumerate() {
            let image = match renderer.render(frame) {
                Ok(image) => Arc::new(image),
                Err(error) => {
                    first_error = Some(error);
                    break;
                }
            };
            for sender in &video_senders {
                if sender.send(image.clone()).is_err() {
                    // That video's thread stopped; its error comes from join.
                    break 'frames;
                }
            }
            if frame_sender.send((index, image)).is_err() {
                break;
            }
            while let Ok(done) = done_receiver.try_recv() {
                if let Err(error) = reporter.record(done) {
                    first_error = Some(error);
                    break 'frames;
                }
            }
        }
        drop(frame_sender);
        drop(video_senders);
        for done in done_receiver.iter() {
            if let Err(error) = reporter.record(done) {
                first_error.get_or_insert(error);
            }
        }
        for thread in video_threads {
            if let Err(error) = thread
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
            {
                first_error.get_or_insert(error);
            }
        }
        match first_error {
            Some(error) => Err(error),
            None => Ok(()),
        }
    })
}

fn png_worker(
    dir: &Path,
    frame_count: usize,
    frames: Receiver<(usize, Arc<RgbaImage>)>,
    done: Sender<Result<usize, RenderError>>,
) {
    let mut rgb = Vec::new();
    for (index, image) in frames {
        let path = dir.join(frame_file_name(index, frame_count));
        let result = write_png_atomically(&path, &image, &mut rgb).map(|()| index);
        let failed = result.is_err();
        let _ = done.send(result);
        if failed {
            break;
        }
    }
}

/// Calls `progress` in frame order as frames complete in any order.
struct Reporter<'a> {
    written: Vec<bool>,
    next: usize,
    progress: &'a mut dyn FnMut(usize),
}

impl Reporter<'_> {
    fn record(&mut self, done: Result<usize, RenderError>) -> Result<(), RenderError> {
        self.written[done?] = true;
        while self.next < self.written.len() && self.written[self.next] {
            (self.progress)(self.next);
            self.next += 1;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_names_pad_to_four_digits_or_more() {
        assert_eq!(frame_file_name(0, 1), "frame_0000.png");
        assert_eq!(frame_file_name(42, 100), "frame_0042.png");
        assert_eq!(frame_file_name(9999, 10000), "frame_9999.png");
        assert_eq!(frame_file_name(7, 10001), "frame_00007.png");
        assert_eq!(frame_file_name(123456, 200000), "frame_123456.png");
    }

    #[test]
    fn reporter_reports_in_order() {
        let mut seen = Vec::new();
        let mut callback = |i: usize| seen.push(i);
        let mut reporter = Reporter {
            written: vec![false; 4],
            next: 0,
            progress: &mut callback,
        };
        for i in [2, 0, 3, 1] {
            reporter.record(Ok(i)).unwrap();
        }
        assert_eq!(seen, [0, 1, 2, 3]);
    }

    #[test]
    fn png_written_atomically_decodes_back() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("frame_0000.png");
        let image = RgbaImage::from_fn(5, 3, |x, y| {
            image::Rgba([x as u8 * 40, y as u8 * 80, 7, 255])
        });
        write_png_atomically(&path, &image, &mut Vec::new()).unwrap();
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["frame_0000.png"]);
        let back = image::open(&path).unwrap().to_rgba8();
        assert_eq!(back, image);
    }

    #[test]
    fn png_error_names_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("missing").join("frame_0000.png");
        let error =
            write_png_atomically(&path, &RgbaImage::new(2, 2), &mut Vec::new()).unwrap_err();
        assert!(
            error.to_string().contains("missing/frame_0000.png"),
            "{error}"
        );
    }
}
