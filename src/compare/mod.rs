//! Perceptual comparison of rendered frames against golden images (FLIP).
//!
//! Two images are compared with NVIDIA's FLIP metric (Andersson et al. 2020,
//! "FLIP: A Difference Evaluator for Alternating Images") through the `nv-flip`
//! crate, the way wgpu's own image tests do. FLIP produces an error map `e(x) ∈
//! [0, 1]` per pixel, 0 where a viewer sees no difference and 1 for the largest
//! visible difference, taking colour, edges and viewing distance into account
//! (67 pixels per degree: a 0.7 m distance from a 24" 4K monitor).
//!
//! Two figures of the map decide a verdict (see [`CompareThresholds`]):
//! - the **mean** error, `Σ e(x) / N`, which grows with the area that changed;
//! - the error at a high **percentile** `p` (nearest rank over all `N` pixels):
//!   the value that only a fraction `1 − p` of the pixels exceed. It catches a
//!   small region that changed a lot (a body shifted by a few pixels), which
//!   barely moves the mean of a large image, while ignoring a handful of edge
//!   pixels that a different rasteriser anti-aliases differently.
//!
//! Images are compared as opaque sRGB: the alpha channel is ignored (rendered
//! frames are opaque).
//!
//! [`compare_directories`] compares every `*.png` of a golden folder with the
//! same-named frame of a frames folder and writes, for every compared frame,
//! the FLIP error map coloured with magma as `DIFF/NAME` and a copy of the
//! actual frame as `DIFF/STEM.actual.png`.
//!
//! The module is split by responsibility: thresholds and verdicts
//! (`compare_thresholds.rs`), FLIP on two images (`image_comparison.rs`),
//! folders of frames (`directories.rs`), the report and its table
//! (`compare_report.rs`), and the errors (`compare_error.rs`).

mod compare_error;
mod compare_report;
mod compare_thresholds;
mod directories;
mod image_comparison;

pub use compare_error::CompareError;
pub use compare_report::{CompareReport, FrameComparison};
pub use compare_thresholds::{CompareThresholds, FrameOutcome};
pub use directories::{compare_directories, read_rgba};
pub use image_comparison::{ImageComparison, compare_images};
