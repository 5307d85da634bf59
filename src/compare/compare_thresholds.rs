//! [`CompareThresholds`] and the verdict on a frame, [`FrameOutcome`].

use super::CompareError;

/// Pass/fail thresholds on the FLIP error map (values in [0, 1]).
///
/// A frame passes when its mean error is at most `mean` **and** its error at
/// the `percentile` (nearest rank over all pixels, unweighted) is at most
/// `percentile_value`.
///
/// The defaults, `mean ≤ 0.02` and `99.9th percentile ≤ 0.1` (at most 0.1%
/// of the pixels may show a FLIP error above 0.1), come from measurements on
/// 320×240 frames of an anti-aliased body of flat-coloured cells with dark
/// edges on a light background (`tests/integration/compare_flip.rs` checks them):
///
/// | change to the frame                        | mean        | p99.9       |
/// |--------------------------------------------|-------------|-------------|
/// | re-render, same driver (bit-identical)     | 0           | 0           |
/// | another 4× MSAA sample pattern             | 0           | 0           |
/// | every channel off by ±1/255 (rounding)     | ≤ 0.002     | ≤ 0.012     |
/// | every channel off by ±2/255                | ≤ 0.012     | ≤ 0.03      |
/// | 20×10 px body shifted by 1 px / 4 px       | 0.001/0.003 | 0.32/0.72   |
/// | 80×20 px body shifted by 1 px / 4 px       | 0.007/0.016 | 0.50/0.87   |
/// | 200×100 px body shifted by 1 px / 4 px     | 0.07/0.15   | 0.58/0.97   |
///
/// So the percentile fails a body shifted by a pixel or more, however small,
/// while rasteriser noise stays well below both limits; the mean fails a
/// change over a large area. A lower percentile would miss the small body:
/// at the 99th, its 4-pixel shift scores 0.008, as under 1% of the pixels
/// change. The unweighted percentile is used, not FLIP's error-weighted one
/// (which wgpu's tests use): the weighted percentile of a map with a single
/// wrong pixel is that pixel's error, so it would fail on one stray pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompareThresholds {
    /// Maximum mean FLIP error (default: 0.02).
    pub mean: f32,
    /// Maximum FLIP error at the given percentile (default: 0.1).
    pub percentile_value: f32,
    /// The percentile checked, in (0, 1), e.g. 0.99 (default: 0.999).
    pub percentile: f32,
}

impl Default for CompareThresholds {
    fn default() -> Self {
        Self {
            mean: 0.02,
            percentile_value: 0.1,
            percentile: 0.999,
        }
    }
}

impl CompareThresholds {
    /// Checks every field: the maxima in [0, 1], the percentile in (0, 1).
    pub fn validate(&self) -> Result<(), CompareError> {
        let unit = |key: &'static str, value: f32| {
            if (0.0..=1.0).contains(&value) {
                Ok(())
            } else {
                Err(CompareError::InvalidThreshold {
                    key,
                    value,
                    reason: "FLIP errors lie in [0, 1]",
                })
            }
        };
        unit("mean", self.mean)?;
        unit("percentile_value", self.percentile_value)?;
        if self.percentile > 0.0 && self.percentile < 1.0 {
            Ok(())
        } else {
            Err(CompareError::InvalidThreshold {
                key: "percentile",
                value: self.percentile,
                reason: "a percentile lies strictly between 0 and 1, e.g. 0.99",
            })
        }
    }

    /// The percentile as a short column label, e.g. `p99` or `p99.5`.
    pub fn percentile_label(&self) -> String {
        let percent = f64::from(self.percentile) * 100.0;
        let rounded = (percent * 100.0).round() / 100.0;
        format!("p{rounded}")
    }

    /// True when both figures are within their maxima.
    pub fn accepts(&self, mean: f32, percentile_value: f32) -> bool {
        mean <= self.mean && percentile_value <= self.percentile_value
    }
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

impl FrameOutcome {
    /// The verdict as the table prints it.
    pub fn label(&self) -> String {
        match self {
            FrameOutcome::Pass => "pass".to_owned(),
            FrameOutcome::Fail => "FAIL".to_owned(),
            FrameOutcome::Missing => "MISSING".to_owned(),
            FrameOutcome::SizeMismatch { golden, actual } => format!(
                "SIZE MISMATCH (golden {}x{}, actual {}x{})",
                golden.0, golden.1, actual.0, actual.1
            ),
        }
    }
}
