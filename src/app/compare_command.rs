//! `elasto compare`: FLIP comparison of rendered frames with golden images.

use super::AppError;
use super::cli::CompareArgs;
use crate::compare::{CompareThresholds, compare_directories};
use crate::scene::num;

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
    let in_range = |flag: &str, value: Option<f64>, open: bool| -> Result<(), AppError> {
        let Some(x) = value else { return Ok(()) };
        let ok = if open {
            x > 0.0 && x < 1.0
        } else {
            (0.0..=1.0).contains(&x)
        };
        if ok {
            return Ok(());
        }
        let range = if open {
            "must lie strictly between 0 and 1 (e.g. 0.999)"
        } else {
            "must lie in [0, 1], the range of FLIP errors"
        };
        Err(AppError::Flag {
            flag: format!("{flag} {}", num(x)),
            reason: format!("{range}, got {}", num(x)),
        })
    };
    in_range("--threshold-mean", args.threshold_mean, false)?;
    in_range("--threshold-percentile", args.threshold_percentile, false)?;
    in_range("--percentile", args.percentile, true)?;
    let thresholds = CompareThresholds {
        mean: args.threshold_mean.map_or(defaults.mean, |x| x as f32),
        percentile_value: args
            .threshold_percentile
            .map_or(defaults.percentile_value, |x| x as f32),
        percentile: args.percentile.map_or(defaults.percentile, |x| x as f32),
    };
    let report = compare_directories(&args.golden, &args.frames, &diff, &thresholds)
        .map_err(AppError::Compare)?;
    super::standard_output::print(&report.table())?;
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
