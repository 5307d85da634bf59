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

use std::ffi::OsString;
use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

use image::{ImageBuffer, ImageFormat, ImageReader, Luma, RgbImage, RgbaImage};
use rayon::prelude::*;

/// Pass/fail thresholds on the FLIP error map (values in [0, 1]).
///
/// A frame passes when its mean error is at most `mean` **and** its error at
/// the `percentile` (nearest rank over all pixels, unweighted) is at most
/// `percentile_value`.
///
/// The defaults, `mean ≤ 0.02` and `99.9th percentile ≤ 0.1` (at most 0.1%
/// of the pixels may show a FLIP error above 0.1), come from measurements on
/// 320×240 frames of an anti-aliased body of flat-coloured cells with dark
/// edges on a light background (`tests/compare_flip.rs` checks them):
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

/// Errors that stop a comparison before any verdict.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// A folder could not be listed.
    #[error("cannot read the {role} folder {}: {source}", path.display())]
    ReadDir {
        /// `golden` or `frames`.
        role: &'static str,
        /// The folder.
        path: PathBuf,
        /// The cause.
        #[source]
        source: io::Error,
    },
    /// The golden folder holds no `*.png` file.
    #[error("the golden folder {} holds no *.png images", path.display())]
    NoGoldenImages {
        /// The folder.
        path: PathBuf,
    },
    /// An image could not be read or decoded.
    #[error("cannot read image {}: {source}", path.display())]
    ReadImage {
        /// The image file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: image::ImageError,
    },
    /// A difference image, or the copy of a frame, could not be written.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The file or folder written.
        path: PathBuf,
        /// The cause.
        #[source]
        source: image::ImageError,
    },
    /// The difference folder is the golden or the frames folder, whose images
    /// the difference images would overwrite.
    #[error(
        "the diff folder {} is the {role} folder; difference images would overwrite its frames",
        path.display()
    )]
    DiffDirOverlap {
        /// `golden` or `frames`.
        role: &'static str,
        /// The folder.
        path: PathBuf,
    },
    /// A threshold is out of range.
    #[error("threshold {key} = {value} is invalid: {reason}")]
    InvalidThreshold {
        /// The field: `mean`, `percentile_value` or `percentile`.
        key: &'static str,
        /// The value given.
        value: f32,
        /// Why it is rejected.
        reason: &'static str,
    },
    /// Two images given to [`compare_images`] differ in size.
    #[error("image sizes differ: golden {}x{}, actual {}x{}", golden.0, golden.1, actual.0, actual.1)]
    SizeMismatch {
        /// Golden image size.
        golden: (u32, u32),
        /// Actual image size.
        actual: (u32, u32),
    },
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

/// The FLIP comparison of two same-sized images.
#[derive(Clone, PartialEq)]
pub struct ImageComparison {
    /// Mean FLIP error.
    pub mean: f32,
    /// FLIP error at the thresholds' percentile.
    pub percentile_value: f32,
    /// Largest FLIP error of any pixel.
    pub max: f32,
    /// Within both thresholds.
    pub passed: bool,
    /// Per-pixel FLIP error in [0, 1].
    pub error_map: ImageBuffer<Luma<f32>, Vec<f32>>,
}

impl std::fmt::Debug for ImageComparison {
    /// The figures and the map's size, not its pixels.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ImageComparison")
            .field("mean", &self.mean)
            .field("percentile_value", &self.percentile_value)
            .field("max", &self.max)
            .field("passed", &self.passed)
            .field("error_map", &self.error_map.dimensions())
            .finish()
    }
}

impl ImageComparison {
    /// The error map coloured with the magma palette (black: no error,
    /// yellow-white: largest error).
    pub fn diff_image(&self) -> RgbImage {
        let (width, height) = self.error_map.dimensions();
        let map = nv_flip::FlipImageFloat::with_data(width, height, self.error_map.as_raw());
        let coloured = map.apply_color_lut(&nv_flip::magma_lut());
        RgbImage::from_raw(width, height, coloured.to_vec())
            .expect("nv-flip returns width * height RGB pixels")
    }
}

/// Compares `actual` with `golden` by FLIP and judges it with `thresholds`.
///
/// Fails only when the sizes differ.
pub fn compare_images(
    golden: &RgbaImage,
    actual: &RgbaImage,
    thresholds: &CompareThresholds,
) -> Result<ImageComparison, CompareError> {
    if golden.dimensions() != actual.dimensions() {
        return Err(CompareError::SizeMismatch {
            golden: golden.dimensions(),
            actual: actual.dimensions(),
        });
    }
    let (width, height) = golden.dimensions();
    let flip_image = |img: &RgbaImage| {
        let rgb: Vec<u8> = img
            .as_raw()
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        nv_flip::FlipImageRgb8::with_data(width, height, &rgb)
    };
    let map = nv_flip::flip(
        flip_image(golden),
        flip_image(actual),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    let mean = nv_flip::FlipPool::from_image(&map).mean();
    let errors = map.to_vec();
    // FlipPool's maximum starts at f32::MIN_POSITIVE, not 0.
    let max = errors.iter().copied().fold(0.0, f32::max);
    // FlipPool's own unweighted percentile indexes past its data for `p`
    // close to 1, so the nearest rank is taken here.
    let percentile_value = percentile(&errors, thresholds.percentile);
    let error_map = ImageBuffer::from_raw(width, height, errors)
        .expect("nv-flip returns width * height errors");
    Ok(ImageComparison {
        mean,
        percentile_value,
        max,
        passed: thresholds.accepts(mean, percentile_value),
        error_map,
    })
}

/// The nearest-rank `p`-percentile of `values`: the smallest value that at
/// least a fraction `p` of them do not exceed (0 for no values).
fn percentile(values: &[f32], p: f32) -> f32 {
    if values.is_empty() {
        return 0.0;
    }
    let mut sorted = values.to_vec();
    sorted.sort_unstable_by(f32::total_cmp);
    // Back to the decimal the caller wrote (0.995_f32 is 0.99500000477), so
    // that 0.995 of 76800 pixels is rank 76416, not 76417.
    let p = (f64::from(p) * 1e7).round() / 1e7;
    let rank = (p * sorted.len() as f64).ceil() as usize;
    sorted[rank.clamp(1, sorted.len()) - 1]
}

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
    std::fs::copy(&actual_path, &copy_path).map_err(|source| CompareError::Write {
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
    result
        .diff_image()
        .save_with_format(&diff_path, ImageFormat::Png)
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
