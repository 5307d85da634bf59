//! [`compare_directories`]: every golden frame of a folder against its
//! namesake in a frames folder, with difference images written beside.

use super::compare_images;
use super::{CompareError, CompareReport, CompareThresholds, FrameComparison, FrameOutcome};
use image::{ImageFormat, ImageReader, RgbaImage};
use rayon::prelude::*;
use std::ffi::OsString;
use std::path::Path;

/// Compares every `*.png` in `golden` with the same-named file in `frames`,
/// writing difference images into `diff_dir`.
///
/// Frames are taken in file-name order. A golden frame absent from `frames` is
/// [`FrameOutcome::Missing`], one of another size
/// [`FrameOutcome::SizeMismatch`]; frames without a golden image are ignored.
/// For every frame found, its copy is written as `diff_dir/STEM.actual.png`;
/// for every frame compared, the magma-coloured error map as `diff_dir/NAME`.
/// `diff_dir` is created when absent and must differ from both other folders.
pub fn compare_directories(
    golden: &Path,
    frames: &Path,
    diff_dir: &Path,
    thresholds: &CompareThresholds,
) -> Result<CompareReport, CompareError> {
    thresholds.validate()?;
    let names = png_files(golden)?;
    if names.is_empty() {
        return Err(CompareError::NoGoldenImages {
            path: golden.to_path_buf(),
        });
    }
    if let Err(source) = std::fs::read_dir(frames) {
        return Err(CompareError::ReadDir {
            role: "frames",
            path: frames.to_path_buf(),
            source,
        });
    }
    std::fs::create_dir_all(diff_dir).map_err(|source| CompareError::Write {
        path: diff_dir.to_path_buf(),
        source: source.into(),
    })?;
    for (role, dir) in [("golden", golden), ("frames", frames)] {
        if same_dir(diff_dir, dir) {
            return Err(CompareError::DiffDirOverlap {
                role,
                path: diff_dir.to_path_buf(),
            });
        }
    }

    let comparisons = names
        .par_iter()
        .map(|name| compare_frame(name, golden, frames, diff_dir, thresholds))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(CompareReport {
        frames: comparisons,
        thresholds: *thresholds,
        golden_dir: golden.to_path_buf(),
        frames_dir: frames.to_path_buf(),
    })
}

/// Compares one golden frame with its namesake in `frames`.
fn compare_frame(
    name: &OsString,
    golden_dir: &Path,
    frames_dir: &Path,
    diff_dir: &Path,
    thresholds: &CompareThresholds,
) -> Result<FrameComparison, CompareError> {
    let display_name = name.to_string_lossy().into_owned();
    let golden_path = golden_dir.join(name);
    let actual_path = frames_dir.join(name);
    let golden = read_rgba(&golden_path)?;
    let mut comparison = FrameComparison {
        name: display_name,
        outcome: FrameOutcome::Missing,
        mean: None,
        percentile_value: None,
        diff_image: None,
        actual_image: None,
    };
    if !actual_path.is_file() {
        return Ok(comparison);
    }
    let actual = read_rgba(&actual_path)?;

    let copy_path = diff_dir.join(actual_copy_name(name));
    std::fs::read(&actual_path)
        .and_then(|bytes| write_replacing(&copy_path, &bytes))
        .map_err(|source| CompareError::Write {
            path: copy_path.clone(),
            source: source.into(),
        })?;
    comparison.actual_image = Some(copy_path);

    if golden.dimensions() != actual.dimensions() {
        comparison.outcome = FrameOutcome::SizeMismatch {
            golden: golden.dimensions(),
            actual: actual.dimensions(),
        };
        return Ok(comparison);
    }
    let result = compare_images(&golden, &actual, thresholds)?;
    let diff_path = diff_dir.join(name);
    let mut png = std::io::Cursor::new(Vec::new());
    result
        .diff_image()
        .write_to(&mut png, ImageFormat::Png)
        .and_then(|()| write_replacing(&diff_path, png.get_ref()).map_err(Into::into))
        .map_err(|source| CompareError::Write {
            path: diff_path.clone(),
            source,
        })?;
    comparison.outcome = if result.passed {
        FrameOutcome::Pass
    } else {
        FrameOutcome::Fail
    };
    comparison.mean = Some(result.mean);
    comparison.percentile_value = Some(result.percentile_value);
    comparison.diff_image = Some(diff_path);
    Ok(comparison)
}

/// Writes `bytes` to a temporary file beside `path` and renames it over
/// `path`: whatever `path` was (a symbolic link to a golden frame, say) is
/// replaced, never written through, and a failed write leaves no cut-off
/// file under the final name.
fn write_replacing(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write as _;
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    let temporary = path.with_file_name(format!(".{name}.partial"));
    // A stale temporary (or a link placed there) is removed, not followed.
    match std::fs::remove_file(&temporary) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(e),
        _ => {}
    }
    let written = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&temporary)
        .and_then(|mut file| file.write_all(bytes).and_then(|()| file.sync_data()))
        .and_then(|()| std::fs::rename(&temporary, path));
    if written.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    written
}

/// Reads a PNG file as 8-bit RGBA.
pub fn read_rgba(path: &Path) -> Result<RgbaImage, CompareError> {
    let read = || -> Result<RgbaImage, image::ImageError> {
        let mut reader = ImageReader::open(path)?;
        reader.set_format(ImageFormat::Png);
        Ok(reader.decode()?.into_rgba8())
    };
    read().map_err(|source| CompareError::ReadImage {
        path: path.to_path_buf(),
        source,
    })
}

/// The `*.png` file names in `dir`, sorted.
fn png_files(dir: &Path) -> Result<Vec<OsString>, CompareError> {
    let read_dir_error = |source| CompareError::ReadDir {
        role: "golden",
        path: dir.to_path_buf(),
        source,
    };
    let mut names = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(read_dir_error)? {
        let entry = entry.map_err(read_dir_error)?;
        let path = entry.path();
        let is_png = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        if is_png && path.is_file() {
            names.push(entry.file_name());
        }
    }
    names.sort();
    Ok(names)
}

/// `frame_0012.png` → `frame_0012.actual.png`.
fn actual_copy_name(name: &OsString) -> OsString {
    let stem = Path::new(name)
        .file_stem()
        .map_or_else(|| name.clone(), |s| s.to_os_string());
    let mut copy = stem;
    copy.push(".actual.png");
    copy
}

/// True when both paths name the same existing folder.
fn same_dir(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}
