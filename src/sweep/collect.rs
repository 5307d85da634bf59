//! The sweep's own outputs, rebuilt from its run folders: `sweep.csv`, `sweep.json`, `contact_sheet.png`, `comparison.{png,mp4}`.
//!
//! The same code serves the end of a sweep and `--collect` after sharded
//! runs, so both give the same files: everything comes from what the run
//! folders hold (each run's record and `stats.csv`, its frames), nothing
//! from memory of the runs.

use super::contact_sheet::{MAX_COMPARISON_SIZE, MAX_SHEET_SIZE, TileGrid, read_frame, run_frames};
use super::run_record::{RunRecord, RunStatus};
use super::sweep_table::{RowStatus, SweepDescription, SweepRow, write_csv, write_json};
use super::{RunSpec, RunSummary, SweepError};
use crate::encode::{VideoFormat, write_image_video};
use crate::render::RenderError;
use image::RgbaImage;
use std::path::{Path, PathBuf};

/// The images to make besides the table.
#[derive(Debug, Clone, PartialEq)]
pub struct SheetOptions {
    /// Frame shown in the contact sheet (`None`: each run's last).
    pub frame: Option<usize>,
    /// Videos of the comparison (APNG → `comparison.png`, MP4 → `comparison.mp4`).
    pub videos: Vec<VideoFormat>,
    /// Frames per second of the comparison video.
    pub fps: f64,
}

/// What [`collect`] wrote and found.
#[derive(Debug, Clone, PartialEq)]
pub struct Collected {
    /// One row per run.
    pub rows: Vec<SweepRow>,
    /// The files written, in the sweep folder.
    pub written: Vec<String>,
}

/// Reads every run's folder under `dir` and writes the sweep's table and,
/// with `sheet`, its images. A run is `ok` when its record says so, `failed`
/// when its record says it failed (or was left running by a killed sweep),
/// `skipped` when its folder has no record.
pub fn collect(
    dir: &Path,
    runs: &[RunSpec],
    sweep: SweepDescription<'_>,
    sheet: Option<&SheetOptions>,
) -> Result<Collected, SweepError> {
    let mut rows = Vec::with_capacity(runs.len());
    for spec in runs {
        let run_dir = dir.join(spec.folder_name());
        let record = RunRecord::read(&run_dir)?;
        let (status, exit_code, wall_seconds) = match &record {
            None => (RowStatus::Skipped, None, None),
            Some(r) => {
                let status = match r.status {
                    RunStatus::Ok => RowStatus::Ok,
                    RunStatus::Failed => {
                        RowStatus::Failed(r.reason.clone().unwrap_or_else(|| "unknown".into()))
                    }
                    RunStatus::Running => {
                        RowStatus::Failed("did not finish (the sweep was stopped)".into())
                    }
                };
                (status, r.exit_code, Some(r.wall_seconds))
            }
        };
        let summary = match status {
            RowStatus::Skipped => None,
            _ => RunSummary::read(&run_dir.join("stats.csv")),
        };
        rows.push(SweepRow {
            spec: spec.clone(),
            status,
            exit_code,
            wall_seconds,
            summary,
        });
    }
    write_csv(&dir.join("sweep.csv"), sweep.axes, &rows)?;
    write_json(&dir.join("sweep.json"), sweep, &rows)?;
    let mut written = vec!["sweep.csv".to_owned(), "sweep.json".to_owned()];
    if let Some(options) = sheet {
        let frames: Vec<Vec<PathBuf>> = runs
            .iter()
            .map(|spec| run_frames(&dir.join(spec.folder_name())))
            .collect();
        if let Some(frame_size) = first_frame_size(&frames) {
            let labels: Vec<Vec<String>> = rows.iter().map(tile_label).collect();
            written.push(contact_sheet(
                dir,
                &frames,
                &labels,
                frame_size,
                options.frame,
            )?);
            written.extend(comparison(dir, &frames, &labels, frame_size, options)?);
        }
    }
    Ok(Collected { rows, written })
}

/// The label lines of a run's tile: `#3` (with its status when not ok),
/// then `key=value` per varied key.
fn tile_label(row: &SweepRow) -> Vec<String> {
    let head = match &row.status {
        RowStatus::Ok => format!("#{}", row.spec.index),
        RowStatus::Failed(_) => format!("#{} failed", row.spec.index),
        RowStatus::Skipped => format!("#{} not run", row.spec.index),
    };
    std::iter::once(head)
        .chain(
            row.spec
                .values
                .iter()
                .map(|(k, v)| format!("{k}={}", v.label)),
        )
        .collect()
}

fn first_frame_size(frames: &[Vec<PathBuf>]) -> Option<(u32, u32)> {
    frames
        .iter()
        .filter_map(|f| f.first())
        .find_map(|path| image::image_dimensions(path).ok())
}

fn image_error(path: &Path, reason: impl ToString) -> SweepError {
    SweepError::Image {
        path: path.to_owned(),
        reason: reason.to_string(),
    }
}

/// `contact_sheet.png`: frame `frame` (default: the last) of every run.
fn contact_sheet(
    dir: &Path,
    frames: &[Vec<PathBuf>],
    labels: &[Vec<String>],
    frame_size: (u32, u32),
    frame: Option<usize>,
) -> Result<String, SweepError> {
    let lines = labels.iter().map(Vec::len).max().unwrap_or(1);
    let grid = TileGrid::new(frames.len(), frame_size, lines, MAX_SHEET_SIZE);
    let tiles: Vec<Option<RgbaImage>> = frames
        .iter()
        .map(|run| {
            let path = match frame {
                Some(i) => run.get(i),
                None => run.last(),
            };
            path.and_then(|p| read_frame(p))
        })
        .collect();
    let sheet = grid.compose(&tiles, labels);
    let path = dir.join("contact_sheet.png");
    write_png(&path, &sheet)?;
    Ok("contact_sheet.png".into())
}

fn write_png(path: &Path, image: &RgbaImage) -> Result<(), SweepError> {
    let mut bytes = Vec::new();
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .map_err(|e| image_error(path, e))?;
    super::write_atomically(path, &bytes).map_err(|(path, e)| image_error(&path, e))
}

/// `comparison.png` / `comparison.mp4`: every run tiled, frame by frame in
/// step (a run with fewer frames holds its last one).
fn comparison(
    dir: &Path,
    frames: &[Vec<PathBuf>],
    labels: &[Vec<String>],
    frame_size: (u32, u32),
    options: &SheetOptions,
) -> Result<Vec<String>, SweepError> {
    let count = frames.iter().map(Vec::len).max().unwrap_or(0);
    if count == 0 || options.videos.is_empty() {
        return Ok(Vec::new());
    }
    let lines = labels.iter().map(Vec::len).max().unwrap_or(1);
    let grid = TileGrid::new(frames.len(), frame_size, lines, MAX_COMPARISON_SIZE);
    let compose = |i: usize| -> Result<RgbaImage, RenderError> {
        let tiles: Vec<Option<RgbaImage>> = frames
            .iter()
            .map(|run| run.get(i).or(run.last()).and_then(|p| read_frame(p)))
            .collect();
        Ok(grid.compose(&tiles, labels))
    };
    let mut written = Vec::new();
    for &format in &options.videos {
        let name = match format {
            VideoFormat::Apng => "comparison.png",
            VideoFormat::Mp4 => "comparison.mp4",
            VideoFormat::Gif => "comparison.gif",
        };
        let path = dir.join(name);
        write_image_video(
            format,
            &path,
            grid.size(),
            options.fps,
            [255, 255, 255],
            count,
            (0..count).map(compose),
        )
        .map_err(|e| image_error(&path, e))?;
        written.push(name.to_owned());
    }
    Ok(written)
}
