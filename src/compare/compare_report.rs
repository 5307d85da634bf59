//! [`CompareReport`]: the comparison of every frame of a folder, and the
//! table `elasto compare` prints.

use super::{CompareThresholds, FrameOutcome};
use std::fmt::Write as _;
use std::path::PathBuf;

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
    /// Copy of the actual frame written next to the difference image (when the
    /// frame exists).
    pub actual_image: Option<PathBuf>,
}

/// All frame comparisons of a run.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CompareReport {
    /// One entry per golden frame, in file-name order.
    pub frames: Vec<FrameComparison>,
    /// The thresholds the verdicts were made with.
    pub thresholds: CompareThresholds,
    /// The golden folder.
    pub golden_dir: PathBuf,
    /// The frames folder.
    pub frames_dir: PathBuf,
}

impl CompareReport {
    /// True when every frame passed.
    pub fn all_passed(&self) -> bool {
        self.frames.iter().all(|f| f.outcome == FrameOutcome::Pass)
    }

    /// The frames that did not pass.
    pub fn failures(&self) -> impl Iterator<Item = &FrameComparison> {
        self.frames
            .iter()
            .filter(|f| f.outcome != FrameOutcome::Pass)
    }

    /// A printable table: one row per frame with its figures and verdict.
    ///
    /// ```text
    /// FLIP comparison of frames/ against golden/
    /// thresholds: mean <= 0.02, p99.9 <= 0.1
    /// frame               mean     p99.9  verdict
    /// frame_0000.png  0.000000  0.000000  pass
    /// frame_0010.png  0.012512  0.712430  FAIL (p99.9 0.7124 > 0.1)
    /// 1 of 2 frames failed
    /// ```
    pub fn table(&self) -> String {
        let t = &self.thresholds;
        let label = t.percentile_label();
        let name_width = self
            .frames
            .iter()
            .map(|f| f.name.chars().count())
            .chain(["frame".len()])
            .max()
            .unwrap_or(5);
        let figure = |v: Option<f32>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.6}"));

        let mut out = String::new();
        let _ = writeln!(
            out,
            "FLIP comparison of {} against {}",
            self.frames_dir.display(),
            self.golden_dir.display()
        );
        let _ = writeln!(
            out,
            "thresholds: mean <= {}, {label} <= {}",
            t.mean, t.percentile_value
        );
        let _ = writeln!(
            out,
            "{:<name_width$}  {:>8}  {:>8}  verdict",
            "frame", "mean", label
        );
        for f in &self.frames {
            let mut verdict = f.outcome.label();
            if f.outcome == FrameOutcome::Fail {
                let over: Vec<String> = [
                    ("mean", f.mean, t.mean),
                    (label.as_str(), f.percentile_value, t.percentile_value),
                ]
                .into_iter()
                .filter_map(|(key, value, max)| {
                    value
                        .filter(|v| *v > max)
                        .map(|v| format!("{key} {v:.4} > {max}"))
                })
                .collect();
                let _ = write!(verdict, " ({})", over.join(", "));
            }
            let _ = writeln!(
                out,
                "{:<name_width$}  {:>8}  {:>8}  {verdict}",
                f.name,
                figure(f.mean),
                figure(f.percentile_value),
            );
        }
        let failed = self.failures().count();
        if failed == 0 {
            let _ = writeln!(out, "all {} frames passed", self.frames.len());
        } else {
            let _ = writeln!(out, "{failed} of {} frames failed", self.frames.len());
        }
        out
    }
}
