//! A video of images made elsewhere (e.g. a sweep's tiled comparison), through the same writers as a run's video.

use super::partial_file::PartialFile;
use super::video;
use super::video_writer::VideoSpec;
use super::{RenderError, VideoFormat};
use image::RgbaImage;
use std::path::Path;
use std::sync::Arc;

/// Writes `frames` (all `width` x `height`, `frame_count` of them) as a video
/// of `format` at `path`, at `fps` frames per second. Like a run's video it
/// is written under a hidden temporary name and appears at `path` only when
/// complete; `background` (8-bit sRGB) pads an MP4 to even sides.
pub fn write_image_video(
    format: VideoFormat,
    path: &Path,
    (width, height): (u32, u32),
    fps: f64,
    background: [u8; 3],
    frame_count: usize,
    frames: impl IntoIterator<Item = Result<RgbaImage, RenderError>>,
) -> Result<(), RenderError> {
    let spec = VideoSpec {
        path,
        width,
        height,
        frame_count,
        fps,
        background,
    };
    let partial = PartialFile::new(path)?;
    let mut writer = video::open(format, &spec, &partial)?;
    let mut pushed = 0;
    for frame in frames {
        let frame = frame?;
        if frame.dimensions() != (width, height) {
            return Err(RenderError::InvalidInput(format!(
                "video frame {pushed} is {}x{}, not {width}x{height}",
                frame.width(),
                frame.height()
            )));
        }
        writer.push(&Arc::new(frame))?;
        pushed += 1;
    }
    if pushed != frame_count {
        return Err(RenderError::InvalidInput(format!(
            "{pushed} video frames given, {frame_count} announced"
        )));
    }
    writer.finish()?;
    partial.publish()
}
