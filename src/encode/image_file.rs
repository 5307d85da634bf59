//! The files of a run written one safe way: under a hidden temporary name
//! until complete, PNG encoded one way, with encoder errors naming the file.
//! Shared by PNG frames (`export.rs`) and videos (`video.rs`).

use super::RenderError;
use std::io::Write;
use std::path::{Path, PathBuf};

/// A PNG encoder set up as every frame and video of a run is written: RGB,
/// 8 bits, the `png` crate's `Fast` compression, an sRGB chunk. `Fastest`
/// took the default scene's frames from 16 to 26 MB for 10% less wall time
/// (docs/benchmarks.md): the files are what users keep.
pub(crate) fn png_encoder<W: Write>(
    writer: W,
    width: u32,
    height: u32,
) -> png::Encoder<'static, W> {
    let mut encoder = png::Encoder::new(writer, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Fast);
    encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    encoder
}

/// Appends the RGB channels of the opaque RGBA pixels `rgba` to `rgb`.
pub(crate) fn push_rgb(rgba: &[u8], rgb: &mut Vec<u8>) {
    let start = rgb.len();
    rgb.resize(start + rgba.len() / 4 * 3, 0);
    for (to, from) in rgb[start..].chunks_exact_mut(3).zip(rgba.chunks_exact(4)) {
        to.copy_from_slice(&from[..3]);
    }
}

/// The hidden temporary name a file is written under before it is
/// complete: its hidden sibling `.NAME.partial`.
pub(crate) fn temporary_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.partial"))
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
}
