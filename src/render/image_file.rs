//! The files of a run written one safe way: under a hidden temporary name
//! until complete, as RGB from the renderer's opaque RGBA, with encoder
//! errors naming the file. Shared by PNG frames (`export.rs`) and videos
//! (`video.rs`).

use super::RenderError;
use image::RgbaImage;
use std::path::{Path, PathBuf};

/// The hidden temporary name a file is written under before it is complete.
pub(crate) fn temporary_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.partial"))
}

/// Copies the RGB channels of an opaque RGBA image.
pub(crate) fn rgba_to_rgb(image: &RgbaImage, rgb: &mut Vec<u8>) {
    rgb.clear();
    rgb.extend(
        image
            .as_raw()
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]]),
    );
}

/// A PNG encoder's error, naming the file being written.
pub(crate) fn png_error(path: &Path, error: png::EncodingError) -> RenderError {
    match error {
        png::EncodingError::IoError(source) => RenderError::Io {
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

    #[test]
    fn temporary_names_are_hidden_siblings() {
        assert_eq!(
            temporary_path(Path::new("out/video.mp4")),
            PathBuf::from("out/.video.mp4.partial")
        );
        assert_eq!(
            temporary_path(Path::new("frames/frame_0001.png")),
            PathBuf::from("frames/.frame_0001.png.partial")
        );
    }

    #[test]
    fn rgb_drops_alpha() {
        let image = RgbaImage::from_raw(2, 1, vec![1, 2, 3, 255, 4, 5, 6, 255]).unwrap();
        let mut rgb = vec![9; 10];
        rgba_to_rgb(&image, &mut rgb);
        assert_eq!(rgb, [1, 2, 3, 4, 5, 6]);
    }
}
