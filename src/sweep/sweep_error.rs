//! Errors of planning a sweep: a bad `--vary`, a bad sweep file, mismatched zip lengths.

use super::{RecordError, TableError};
use crate::input_file::InputFileError;
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
    #[error("cannot read sweep file {path}: {source}")]
    ReadFile {
        /// The file.
        path: PathBuf,
        /// Why: the OS refused, it is not a regular file, or it is too large.
        source: InputFileError,
    },
    /// The sweep file is malformed.
    #[error("{path}: {reason}")]
    BadFile {
        /// The file.
        path: PathBuf,
        /// What is wrong (with the key and, for TOML syntax, the line).
        reason: String,
    },
    /// A run folder holds a run with other parameters.
    #[error(
        "{} holds a run with other parameters ({what}); use another --out, remove the folder, \
         or give --force to redo every run",
        folder.display()
    )]
    ChangedRun {
        /// The run folder.
        folder: PathBuf,
        /// What differs.
        what: String,
    },
    /// A run folder exists, is not empty and was not made by a sweep.
    #[error(
        "{} exists and was not made by elasto sweep (it has no {}); remove it or give --force",
        folder.display(),
        super::RUN_RECORD_FILE
    )]
    ForeignFolder {
        /// The run folder.
        folder: PathBuf,
    },
    /// The sweep's folder holds files, but nothing a sweep writes.
    #[error(
        "the sweep folder {} is not empty and was not made by elasto sweep (it has no sweep.json and no run folder with {}); choose another folder with --out, or give --force to write the sweep's files in it",
        folder.display(),
        super::RUN_RECORD_FILE
    )]
    NotASweepFolder {
        /// The folder.
        folder: PathBuf,
    },
    /// A flag's value is out of range.
    #[error("`{flag}`: {reason}")]
    BadFlag {
        /// The flag and its value as typed.
        flag: String,
        /// What is wrong.
        reason: String,
    },
    /// A run record could not be read or written.
    #[error(transparent)]
    Record(#[from] RecordError),
    /// `sweep.csv` or `sweep.json` could not be written.
    #[error(transparent)]
    Table(#[from] TableError),
    /// The contact sheet or the comparison video could not be made.
    #[error("cannot write {}: {reason}", path.display())]
    Image {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// A folder could not be made.
    #[error("cannot create {}: {source}", path.display())]
    Io {
        /// The folder.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// `--collect` on a folder with no run of this sweep (missing, empty, or
    /// holding the runs of other `--vary` values), or with runs of other
    /// values while some of this sweep's are missing.
    #[error(
        "{}: {reason}; nothing was written (run the sweep, or its shards, first, with the same \
         scene, --vary and --set)",
        folder.display()
    )]
    NothingToCollect {
        /// The sweep's folder.
        folder: PathBuf,
        /// What is there instead.
        reason: String,
    },
    /// Some runs failed (the others completed; see `sweep.csv`).
    #[error("{failed} of {total} runs failed (see {})", table.display())]
    RunsFailed {
        /// Failed runs.
        failed: usize,
        /// Runs of this sweep (or shard).
        total: usize,
        /// Where the reasons are.
        table: PathBuf,
    },
}

impl SweepError {
    /// 2 for bad input (nothing was run), 1 for a failure while working.
    pub fn exit_code(&self) -> i32 {
        match self {
            SweepError::Record(_)
            | SweepError::Table(_)
            | SweepError::Image { .. }
            | SweepError::Io { .. }
            | SweepError::RunsFailed { .. } => 1,
            _ => 2,
        }
    }
}
