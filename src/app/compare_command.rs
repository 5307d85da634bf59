//! `elasto compare`: FLIP comparison of rendered frames with golden images.

use super::AppError;
use super::cli::CompareArgs;
use crate::compare::{CompareThresholds, compare_directories};

/// Runs `elasto compare`: prints the report table, fails when a frame does not pass.
pub fn compare(args: &CompareArgs) -> Result<(), AppError> {
    let diff = args.diff.clone().unwrap_or_else(|| {
        let parent = args
            .frames
            .parent()
            .map(|p| p.to_owned())
            .unwrap_or_default();
        parent.join("diff")
    });
    let defaults = CompareThresholds::default();
    let thresholds = CompareThresholds {
        mean: args.threshold_mean.unwrap_or(defaults.mean),
        percentile_value: args
            .threshold_percentile
            .unwrap_or(defaults.percentile_value),
        percentile: args.percentile.unwrap_or(defaults.percentile),
    };
    let report = compare_directories(&args.golden, &args.frames, &diff, &thresholds)
        .map_err(AppError::Compare)?;
    print!("{}", report.table());
    if report.all_passed() {
        Ok(())
    } else {
        let failed = report
            .frames
            .iter()
            .filter(|f| f.outcome != crate::compare::FrameOutcome::Pass)
            .count();
        Err(AppError::FramesDiffer {
            failed,
            total: report.frames.len(),
        })
    }
}
