//! [`VideoWriter`]: what every video encoder offers the sequence writer, and
//! the [`VideoSpec`] it is opened with.

use super::RenderError;
use image::RgbaImage;
use std::path::Path;
use std::sync::Arc;

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
    fn push(&mut self, frame: &Arc<RgbaImage>) -> Result<(), RenderError>;
    /// Completes the temporary file.
    fn finish(self: Box<Self>) -> Result<(), RenderError>;
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
