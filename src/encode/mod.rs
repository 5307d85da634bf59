//! Image and video files from whole images: numbered PNG frames and APNG,
//! MP4 or GIF videos, each written under a hidden temporary name until it is
//! complete.
//!
//! The renderer (`crate::render`) turns a frame into a whole
//! [`RgbaImage`](image::RgbaImage); this module writes such images. A run
//! goes [`SequenceWriter`] → [`Renderer`](crate::render::Renderer) (one
//! image per frame, the frame before the one being drawn read back
//! meanwhile) → a pool of PNG workers ([`write_png`], the `png` crate) and
//! one thread per video (`video`: APNG with the `png` crate, MP4 with
//! OpenH264 in the process and the `mp4` muxer, GIF with the `gif`
//! crate), fed in frame order. A sweep's comparison video goes through the
//! same writers ([`write_image_video`]). Every file of a run — frames,
//! videos, and the data files `crate::output` writes through
//! [`write_whole_file`] — lives under `.NAME.partial` until complete and is
//! then renamed; an interrupt removes the partial ones
//! ([`remove_partial_files`]).

mod export;
mod frame_yuv;
mod image_file;
mod image_video;
mod mp4_writer;
mod partial_file;
mod sequence;
mod video;
mod video_writer;

pub use export::{check_video_support, frame_file_name, write_png};
pub use image_video::write_image_video;
pub use partial_file::{remove_partial_files, write_whole_file};
pub use sequence::{FrameCost, SequenceWriter, render_sequence};
pub use video::file_name as video_file_name;

use crate::render::RenderError;
use std::path::PathBuf;

/// Video container to write besides the PNG frames.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VideoFormat {
    /// Animated PNG (`video.png`), always available.
    Apng,
    /// H.264 MP4 (`video.mp4`), encoded in the process (OpenH264).
    Mp4,
    /// Animated GIF (`video.gif`).
    Gif,
}

/// Where a render run writes.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOutputs {
    /// Folder for frame_0000.png, ...
    pub frames_dir: PathBuf,
    /// Folder for the video files (`video.png`, `video.mp4`, `video.gif`).
    pub video_dir: PathBuf,
    /// Videos to write (empty: none).
    pub videos: Vec<VideoFormat>,
    /// Frames per second of the video.
    pub fps: f64,
}
