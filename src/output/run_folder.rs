//! A run's output folder while the run writes: an earlier run there stays
//! whole until the new one is complete.
//!
//! `elasto run --force` into a folder that holds an earlier run's outputs
//! writes the new run into a hidden staging folder inside it
//! ([`STAGING_FOLDER`], `.elasto-rerun/`). Only when the run is complete
//! ([`RunFolder::complete`]) is each new file renamed over the earlier one
//! and every earlier output the new run did not write (frames beyond its
//! last, meshes or videos it was not asked for) removed, so the folder then
//! holds exactly the new run's outputs. Until then the earlier run is not
//! touched:
//!
//! * a run that fails (a solver failure at step 0, `--strict` stopping it,
//!   a full disk) removes its staging folder when its [`RunFolder`] is
//!   dropped;
//! * an interrupted one (SIGINT, SIGTERM, SIGHUP) through
//!   [`abandon_staged_runs`], which the binary's signal handler calls:
//!   destructors do not run then;
//! * a killed one (SIGKILL, a power cut) leaves the staging folder, which
//!   the next run into the folder removes before it writes.
//!
//! Completing takes the same process-wide lock as abandoning: a signal that
//! arrives while the files are being moved waits until they all are (a few
//! thousand renames within one folder), and once abandoned a run can no
//! longer complete. A run into a folder without an earlier run writes in
//! place, as before: what it wrote before a failure or an interrupt stays.

use super::OutputError;
use super::folder_lock::FolderLock;
use super::owned_names::{OWNED_FILES, OWNED_FOLDERS, STAGING_FOLDER, ours_inside};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// The staging folders of the runs of this process that have not completed.
static STAGED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn staged() -> MutexGuard<'static, Vec<PathBuf>> {
    STAGED
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Removes the staging folder of every run of this process that replaces
/// an earlier run and has not completed, and returns the output folders
/// whose earlier run is thereby kept as it was. Meant for a signal handler
/// that exits right after: from this call on no run of the process can
/// complete (the lock it takes is never released), and one completing now
/// finishes first.
pub fn abandon_staged_runs() -> Vec<PathBuf> {
    let guard = staged();
    let mut kept = Vec::new();
    for staging in guard.iter() {
        // The run may still create a file meanwhile; a second pass takes it.
        if std::fs::remove_dir_all(staging).is_err() {
            let _ = std::fs::remove_dir_all(staging);
        }
        if let Some(folder) = staging.parent() {
            kept.push(folder.to_owned());
        }
    }
    std::mem::forget(guard);
    kept
}

/// The output folder of a run being written, locked against a second
/// writer; see the module documentation.
#[derive(Debug)]
pub struct RunFolder {
    /// The output folder.
    path: PathBuf,
    /// Where the run writes: the staging folder, or `path` itself when no
    /// earlier run is there to keep.
    writing: PathBuf,
    /// Whether the outputs are written to the staging folder and not yet
    /// moved into place.
    staged: bool,
    /// The lock on `path`, released after the staging folder is gone.
    _lock: FolderLock,
}

impl RunFolder {
    /// A run writing into `path` (locked as `lock`); into a fresh staging
    /// folder when `replaces` (an earlier run is there).
    pub(super) fn new(path: &Path, lock: FolderLock, replaces: bool) -> Result<Self, OutputError> {
        let staging = path.join(STAGING_FOLDER);
        remove_staging(&staging)?;
        let writing = if replaces {
            std::fs::create_dir(&staging).map_err(OutputError::io("create folder", &staging))?;
            staged().push(staging.clone());
            staging
        } else {
            path.to_owned()
        };
        Ok(Self {
            path: path.to_owned(),
            writing,
            staged: replaces,
            _lock: lock,
        })
    }

    /// The output folder (where the outputs are once the run is complete).
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The folder the run writes into now.
    pub fn writing_path(&self) -> &Path {
        &self.writing
    }

    /// Whether an earlier run is kept until this one completes.
    pub fn replaces_earlier_run(&self) -> bool {
        self.staged
    }

    /// Where the run writes the output `name` (`stats.csv`, `frames`, ...).
    pub fn join(&self, name: impl AsRef<Path>) -> PathBuf {
        self.writing.join(name)
    }

    /// Writes a whole file of the run through a hidden temporary file: a
    /// failed write leaves no partial file under `name`.
    pub fn write(&self, name: &str, contents: &str) -> Result<PathBuf, OutputError> {
        let path = self.join(name);
        crate::encode::write_whole_file(&path, contents.as_bytes())
            .map_err(OutputError::io("write", &path))?;
        Ok(path)
    }

    /// The run is complete: its outputs replace the earlier run's, which
    /// are removed where the new run wrote nothing of the same name. The
    /// lock is kept until the value is dropped.
    pub fn complete(&mut self) -> Result<(), OutputError> {
        if !self.staged {
            return Ok(());
        }
        let mut guard = staged();
        let moved = move_into_place(&self.writing, &self.path)?;
        remove_earlier_outputs(&self.path, &moved)?;
        remove_staging(&self.writing)?;
        guard.retain(|staging| staging != &self.writing);
        self.staged = false;
        Ok(())
    }
}

impl Drop for RunFolder {
    /// Not complete: the new run's outputs go, the earlier run stays.
    fn drop(&mut self) {
        if self.staged {
            let mut guard = staged();
            let _ = std::fs::remove_dir_all(&self.writing);
            guard.retain(|staging| staging != &self.writing);
        }
    }
}

/// Removes a staging folder left by a killed run (never through a link:
/// [`super::OutputDir::check`] has refused one).
fn remove_staging(staging: &Path) -> Result<(), OutputError> {
    match std::fs::symlink_metadata(staging) {
        Ok(meta) if meta.is_dir() => {
            std::fs::remove_dir_all(staging).map_err(OutputError::io("remove", staging))
        }
        Ok(_) => std::fs::remove_file(staging).map_err(OutputError::io("remove", staging)),
        Err(_) => Ok(()),
    }
}

/// Renames every file under `from` (its top level and one level of
/// sub-folders) to the same place under `to`; returns the relative paths.
fn move_into_place(from: &Path, to: &Path) -> Result<BTreeSet<PathBuf>, OutputError> {
    let mut moved = BTreeSet::new();
    for (entry, is_dir) in listing(from)? {
        let source = from.join(&entry);
        let target = to.join(&entry);
        if !is_dir {
            std::fs::rename(&source, &target).map_err(OutputError::io("move", &target))?;
            moved.insert(PathBuf::from(&entry));
            continue;
        }
        std::fs::create_dir_all(&target).map_err(OutputError::io("create folder", &target))?;
        for (inner, inner_is_dir) in listing(&source)? {
            if inner_is_dir {
                continue;
            }
            let destination = target.join(&inner);
            std::fs::rename(source.join(&inner), &destination)
                .map_err(OutputError::io("move", &destination))?;
            moved.insert(Path::new(&entry).join(inner));
        }
    }
    Ok(moved)
}

/// The names in `folder`, each with whether it is a folder.
fn listing(folder: &Path) -> Result<Vec<(String, bool)>, OutputError> {
    let entries = std::fs::read_dir(folder)
        .and_then(|entries| entries.collect::<Result<Vec<_>, _>>())
        .map_err(OutputError::io("read folder", folder))?;
    Ok(entries
        .into_iter()
        .map(|entry| {
            let is_dir = entry.file_type().is_ok_and(|kind| kind.is_dir());
            (entry.file_name().to_string_lossy().into_owned(), is_dir)
        })
        .collect())
}

/// Removes the earlier run's outputs that are not among `replaced`.
fn remove_earlier_outputs(folder: &Path, replaced: &BTreeSet<PathBuf>) -> Result<(), OutputError> {
    let remove = |relative: PathBuf| -> Result<(), OutputError> {
        let path = folder.join(&relative);
        if !replaced.contains(&relative) && path.is_file() {
            std::fs::remove_file(&path).map_err(OutputError::io("remove", &path))?;
        }
        Ok(())
    };
    for name in OWNED_FILES {
        remove(PathBuf::from(name))?;
    }
    for sub in OWNED_FOLDERS {
        let sub_folder = folder.join(sub);
        if !sub_folder.is_dir() {
            continue;
        }
        for (name, is_dir) in listing(&sub_folder)? {
            if !is_dir && ours_inside(&name) {
                remove(Path::new(sub).join(name))?;
            }
        }
    }
    Ok(())
}
