//! `sweep-run.json`: what a run folder holds, and the completion marker that makes a sweep resumable.
//!
//! The sweep writes the record when a run starts (`"status": "running"`) and
//! again when it ends (`"ok"` or `"failed"`), each time to a hidden
//! temporary file renamed over the old one, so the file is always whole.
//! A record with `"status": "ok"` is the run's completion marker: it is
//! written last, after every output of the run. A second sweep with the same
//! arguments skips a completed run; a record whose `identity` (the fully
//! resolved scene and the output flags) differs from the planned run's is an
//! error, so a folder never mixes two runs.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The file name of a run's record, in its folder.
pub const RUN_RECORD_FILE: &str = "sweep-run.json";

/// How a run ended (or that it has not).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RunStatus {
    /// Started and not finished (or the sweep was killed).
    Running,
    /// Finished with exit code 0: every output is complete.
    Ok,
    /// Finished with a non-zero exit code, or killed.
    Failed,
}

/// What makes two runs the same: the resolved scene and the output flags.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct RunIdentity {
    /// The fully resolved scene (every default filled in, every override applied).
    pub resolved_scene: String,
    /// The flags passed to `elasto run` besides the scene and overrides
    /// (`--no-render`, `--video …`, `--strict`).
    pub run_flags: Vec<String>,
}

/// The record of one run, `sweep-run.json` in its folder.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// The run's index in the sweep.
    pub index: usize,
    /// Each varied key and its value (TOML text).
    pub values: Vec<(String, String)>,
    /// What the run is.
    pub identity: RunIdentity,
    /// How it ended.
    pub status: RunStatus,
    /// The exit code of `elasto run` (none while running, or when killed by a signal).
    pub exit_code: Option<i32>,
    /// Why it failed: the error line of `elasto run`, or the signal.
    pub reason: Option<String>,
    /// Wall time of the run in seconds (0 while running).
    pub wall_seconds: f64,
}

/// A record that cannot be read or written.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// Reading or writing failed.
    #[error("cannot {action} {}: {source}", path.display())]
    Io {
        /// `read` or `write`.
        action: &'static str,
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The file is not a run record.
    #[error("{} is not a sweep run record: {reason}", path.display())]
    Malformed {
        /// The file.
        path: PathBuf,
        /// What serde reported.
        reason: String,
    },
}

impl RunRecord {
    /// Reads the record of the run folder `dir`; `Ok(None)` when it has none.
    pub fn read(dir: &Path) -> Result<Option<Self>, RecordError> {
        let path = dir.join(RUN_RECORD_FILE);
        let text = match std::fs::read_to_string(&path) {
            Ok(text) => text,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(source) => {
                return Err(RecordError::Io {
                    action: "read",
                    path,
                    source,
                });
            }
        };
        serde_json::from_str(&text)
            .map(Some)
            .map_err(|e| RecordError::Malformed {
                path,
                reason: e.to_string(),
            })
    }

    /// Writes the record into the run folder `dir`, whole or not at all.
    pub fn write(&self, dir: &Path) -> Result<(), RecordError> {
        let text = serde_json::to_string_pretty(self).expect("a run record serialises");
        write_atomically(&dir.join(RUN_RECORD_FILE), text.as_bytes()).map_err(|(path, source)| {
            RecordError::Io {
                action: "write",
                path,
                source,
            }
        })
    }
}

/// Writes `bytes` to a hidden temporary file beside `path`, then renames it
/// to `path`: readers see the old file or the whole new one, never a part.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), (PathBuf, std::io::Error)> {
    use std::io::Write;
    let name = path
        .file_name()
        .map_or_else(|| "file".into(), |n| n.to_string_lossy().into_owned());
    let temporary = path.with_file_name(format!(".{name}.partial"));
    let result = (|| {
        let mut file = std::fs::File::create(&temporary)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        std::fs::rename(&temporary, path)
    })();
    result.map_err(|source| {
        let _ = std::fs::remove_file(&temporary);
        (path.to_owned(), source)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_round_trip_and_absence_is_none() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(RunRecord::read(dir.path()).unwrap(), None);
        let record = RunRecord {
            index: 3,
            values: vec![("material.young".into(), "300".into())],
            identity: RunIdentity {
                resolved_scene: "name = \"x\"\n".into(),
                run_flags: vec!["--no-render".into()],
            },
            status: RunStatus::Ok,
            exit_code: Some(0),
            reason: None,
            wall_seconds: 1.25,
        };
        record.write(dir.path()).unwrap();
        assert_eq!(RunRecord::read(dir.path()).unwrap(), Some(record));
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, [RUN_RECORD_FILE], "no temporary left behind");
        std::fs::write(dir.path().join(RUN_RECORD_FILE), "{ not json").unwrap();
        let err = RunRecord::read(dir.path()).unwrap_err();
        assert!(
            err.to_string().contains("is not a sweep run record"),
            "{err}"
        );
    }
}
