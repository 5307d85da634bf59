//! Output files of a run: frame names, PNG images written atomically, and the
//! check that the requested videos can be written at the run's image size.

use super::frame_image::FrameImage;
use super::frame_png::FramePngWriter;
use super::{RenderError, VideoFormat, mp4_writer, video};
use image::RgbaImage;
use std::path::Path;

/// Checks, before any simulation, that the requested videos can be written
/// with frames of `width` x `height` pixels: MP4's H.264 encoder takes at
/// most 3840x2160 (either way up). APNG and GIF take every size a frame can
/// have.
pub fn check_video_support(
    videos: &[VideoFormat],
    width: u32,
    height: u32,
) -> Result<(), RenderError> {
    if videos.contains(&VideoFormat::Mp4) {
        let name = std::path::Path::new(video::file_name(VideoFormat::Mp4));
        mp4_writer::check_size(name, width, height)?;
    }
    Ok(())
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
    write_frame_png(path, &FrameImage::from(image.clone()))
}

/// [`write_png`] for a rendered frame, as a run writes it: a 2D frame over
/// its run's base compresses only the rows its patch crosses (the base's
/// rows are compressed once, by the first frame written).
pub fn write_frame_png(path: &Path, frame: &FrameImage) -> Result<(), RenderError> {
    FramePngWriter::default().write(path, frame)
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
    fn png_written_atomically_decodes_back() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("frame_0000.png");
        let image = RgbaImage::from_fn(5, 3, |x, y| {
            image::Rgba([x as u8 * 40, y as u8 * 80, 7, 255])
        });
        write_png(&path, &image).unwrap();
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
        let error = write_png(&path, &RgbaImage::new(2, 2)).unwrap_err();
        assert!(
            error.to_string().contains("missing/frame_0000.png"),
            "{error}"
        );
    }
}
