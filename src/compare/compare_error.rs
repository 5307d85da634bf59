//! [`CompareError`]: what stops a comparison before any verdict.

use std::io;
use std::path::PathBuf;

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
    /// Two images given to [`compare_images`](super::compare_images) differ in size.
    #[error("image sizes differ: golden {}x{}, actual {}x{}", golden.0, golden.1, actual.0, actual.1)]
    SizeMismatch {
        /// Golden image size.
        golden: (u32, u32),
        /// Actual image size.
        actual: (u32, u32),
    },
}
