//! Output files of a run: frame names, PNG images written atomically, and the
//! check that the requested videos can be written at the run's image size.

use super::image_file::{png_encoder, png_error, push_rgb};
use super::partial_file::PartialFile;
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
/// sRGB chunk, as the frames of a run are written: encoded in memory, then
/// written under a hidden temporary name and renamed to `path` once complete.
pub fn write_png(path: &Path, image: &RgbaImage) -> Result<(), RenderError> {
    let encode_error = |e: png::EncodingError| png_error(path, e);
    let mut rgb = Vec::with_capacity(image.as_raw().len() / 4 * 3);
    push_rgb(image.as_raw(), &mut rgb);
    let mut file = Vec::new();
    let mut writer = png_encoder(&mut file, image.width(), image.height())
        .write_header()
        .map_err(encode_error)?;
    writer.write_image_data(&rgb).map_err(encode_error)?;
    writer.finish().map_err(encode_error)?;
    // Dropped on an error, the partial file removes itself.
    let partial = PartialFile::new(path)?;
    partial.write_whole(&file)?;
    partial.publish()
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
