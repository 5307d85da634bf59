//! Perceptual comparison of rendered frames against golden images (FLIP).
//!
//! STUB: the public API below is the contract; the rendering work fills it in.

use std::path::{Path, PathBuf};

/// Pass/fail thresholds on the FLIP error map (values in [0, 1]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompareThresholds {
    /// Maximum mean FLIP error.
    pub mean: f32,
    /// Maximum FLIP error at the given percentile.
    pub percentile_value: f32,
    /// The percentile checked, in (0, 1), e.g. 0.99.
    pub percentile: f32,
}

/// The verdict on one frame.
#[derive(Debug, Clone, PartialEq)]
pub enum FrameOutcome {
    /// Within both thresholds.
    Pass,
    /// Over a threshold.
    Fail,
    /// The frame exists in the golden folder but not in the frames folder.
    Missing,
    /// Image sizes differ.
    SizeMismatch {
        /// Golden image size.
        golden: (u32, u32),
        /// Actual image size.
        actual: (u32, u32),
    },
}

/// The comparison of one frame file.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameComparison {
    /// File name, e.g. `frame_0012.png`.
    pub name: String,
    /// Verdict.
    pub outcome: FrameOutcome,
    /// Mean FLIP error (when compared).
    pub mean: Option<f32>,
    /// FLIP error at the checked percentile (when compared).
    pub percentile_value: Option<f32>,
    /// Difference image written (when compared).
    pub diff_image: Option<PathBuf>,
}

/// All frame comparisons of a run.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CompareReport {
    /// One entry per golden frame, in file-name order.
    pub frames: Vec<FrameComparison>,
}

/// Errors that stop a comparison before any verdict.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// Not implemented yet.
    #[error("comparison is not implemented yet")]
    NotImplemented,
}

impl CompareReport {
    /// True when every frame passed.
    pub fn all_passed(&self) -> bool {
        self.frames.iter().all(|f| f.outcome == FrameOutcome::Pass)
    }
    /// A printable table: one row per frame with its figures and verdict.
    pub fn table(&self) -> String {
        String::new()
    }
}

/// Compares every `*.png` in `golden` with the same-named file in `frames`,
/// writing difference images into `diff_dir`.
pub fn compare_directories(
    _golden: &Path,
    _frames: &Path,
    _diff_dir: &Path,
    _thresholds: &CompareThresholds,
) -> Result<CompareReport, CompareError> {
    Err(CompareError::NotImplemented)
}
