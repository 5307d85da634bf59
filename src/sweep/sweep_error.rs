//! Errors of planning a sweep: a bad `--vary`, a bad sweep file, mismatched zip lengths.

use std::path::PathBuf;

/// Errors of parsing and expanding the varied parameters of a sweep (all are
/// bad input: exit code 2, nothing simulated).
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// A `--vary` argument (or a `[vary]` entry of a sweep file) is malformed.
    #[error("invalid `{flag}`: {reason}")]
    BadVary {
        /// The argument as the user typed it, e.g. `--vary material.young=`.
        flag: String,
        /// What is wrong.
        reason: String,
    },
    /// `--zip` pairs lists of different lengths.
    #[error("--zip pairs the lists value by value, so they must have the same length: {lengths}")]
    ZipLengths {
        /// Each key with its number of values, e.g. `material.young: 3, time.substeps: 2`.
        lengths: String,
    },
    /// The same key is varied twice.
    #[error("`{key}` is varied twice (give all its values in one --vary)")]
    DuplicateKey {
        /// The dotted key.
        key: String,
    },
    /// The product of the lists is larger than a sweep may be.
    #[error("the sweep has {runs} runs, more than the {max} a sweep may have")]
    TooManyRuns {
        /// The number of runs asked for.
        runs: u128,
        /// The limit ([`MAX_RUNS`](super::MAX_RUNS)).
        max: usize,
    },
    /// The sweep file could not be read.
    #[error("cannot read sweep file {path}")]
    ReadFile {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The sweep file is malformed.
    #[error("{path}: {reason}")]
    BadFile {
        /// The file.
        path: PathBuf,
        /// What is wrong (with the key and, for TOML syntax, the line).
        reason: String,
    },
}
