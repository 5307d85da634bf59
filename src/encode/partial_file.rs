//! [`PartialFile`]: a file written under its hidden temporary name until it
//! is complete, and the process-wide list of such files that an interrupt
//! cleans up ([`remove_partial_files`]).
//!
//! Every frame and video of a run is written to `.NAME.partial` beside its
//! final name and renamed once complete, so a file under a final name is
//! always whole. A [`PartialFile`] removes its temporary when dropped
//! unpublished (the run failed). A signal does not run destructors, so each
//! partial file is also entered in a list; [`remove_partial_files`] removes
//! those files, and the binary calls it on SIGINT and SIGTERM before
//! exiting. (Every encoder runs in the process: there is no child process to
//! stop.)
//!
//! Creating, publishing and removing a temporary happen under the list's
//! lock, and [`remove_partial_files`] closes the list for good: nothing can
//! create a partial file after the cleanup has run, nor slip between its
//! removals.

use super::RenderError;
use super::image_file::temporary_path;
use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// The partial files alive in this process.
#[derive(Default)]
struct Registry {
    /// Temporary paths of the partial files.
    files: Vec<PathBuf>,
    /// [`remove_partial_files`] has run: the process is about to exit.
    closed: bool,
}

static REGISTRY: Mutex<Registry> = Mutex::new(Registry {
    files: Vec::new(),
    closed: false,
});

fn registry() -> MutexGuard<'static, Registry> {
    REGISTRY
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Removes every partial file of this process; returns how
/// many partial files were removed. After
/// this call no partial file can be created: it is meant for a signal
/// handler that exits right after.
pub fn remove_partial_files() -> usize {
    let mut registry = registry();
    registry.closed = true;
    registry
        .files
        .iter()
        .filter(|path| std::fs::remove_file(path).is_ok())
        .count()
}

/// A file of the run being written under its hidden temporary name.
#[derive(Debug)]
pub(crate) struct PartialFile {
    /// The final name.
    path: PathBuf,
    /// The hidden temporary name, registered while this value lives (empty
    /// once published).
    temporary: PathBuf,
}

impl PartialFile {
    /// Registers the temporary of `path`; nothing is created yet.
    pub fn new(path: &Path) -> Result<Self, RenderError> {
        let temporary = temporary_path(path);
        let mut registry = registry();
        if registry.closed {
            return Err(RenderError::Interrupted);
        }
        registry.files.push(temporary.clone());
        Ok(Self {
            path: path.to_owned(),
            temporary,
        })
    }

    /// Writes `bytes` as the whole temporary file.
    pub fn write_whole(&self, bytes: &[u8]) -> Result<(), RenderError> {
        let mut file = self.create()?;
        file.write_all(bytes).map_err(|source| RenderError::Io {
            path: self.path.clone(),
            source,
        })
    }

    /// Creates (or truncates) the temporary file.
    pub fn create(&self) -> Result<File, RenderError> {
        let registry = registry();
        if registry.closed {
            return Err(RenderError::Interrupted);
        }
        File::create(&self.temporary).map_err(|source| RenderError::Io {
            path: self.path.clone(),
            source,
        })
    }

    /// Renames the complete file to its final name.
    pub fn publish(mut self) -> Result<(), RenderError> {
        let mut registry = registry();
        let result = if registry.closed {
            Err(RenderError::Interrupted)
        } else {
            std::fs::rename(&self.temporary, &self.path).map_err(|source| RenderError::Io {
                path: self.path.clone(),
                source,
            })
        };
        if result.is_err() {
            let _ = std::fs::remove_file(&self.temporary);
        }
        forget(&mut registry, &self.temporary);
        self.temporary = PathBuf::new();
        result
    }
}

impl Drop for PartialFile {
    /// Not published: the file is incomplete, remove it.
    fn drop(&mut self) {
        if self.temporary.as_os_str().is_empty() {
            return;
        }
        let mut registry = registry();
        let _ = std::fs::remove_file(&self.temporary);
        forget(&mut registry, &self.temporary);
    }
}

/// Writes `bytes` as the whole file at `path` through its registered hidden
/// temporary (see `PartialFile`): the final name holds the earlier file or
/// the whole new one, never a part, and a failed write (a full disk) leaves
/// nothing behind. For the files of a run other than frames and videos
/// (`scene.toml`, VTU meshes, surfaces, `study.md`, ...).
pub fn write_whole_file(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let as_io = |error: RenderError| match error {
        RenderError::Io { source, .. } => source,
        other => std::io::Error::new(std::io::ErrorKind::Interrupted, other.to_string()),
    };
    let partial = PartialFile::new(path).map_err(as_io)?;
    partial.write_whole(bytes).map_err(as_io)?;
    partial.publish().map_err(as_io)
}

/// Takes one registration of `temporary` off the list.
fn forget(registry: &mut Registry, temporary: &Path) {
    if let Some(index) = registry.files.iter().position(|p| p == temporary) {
        registry.files.swap_remove(index);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    #[test]
    fn a_whole_file_that_cannot_be_put_in_place_leaves_nothing_behind() {
        let dir = tempfile::tempdir().unwrap();
        let written = dir.path().join("study.md");
        write_whole_file(&written, b"# study\n").unwrap();
        assert_eq!(std::fs::read(&written).unwrap(), b"# study\n");
        // A folder where the file goes: the rename fails, the temporary goes.
        let blocked = dir.path().join("blocked.vtu");
        std::fs::create_dir_all(blocked.join("inside")).unwrap();
        assert!(write_whole_file(&blocked, b"<VTKFile/>").is_err());
        let mut names: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names, ["blocked.vtu", "study.md"], "no temporary is left");
        assert!(!registry().files.contains(&temporary_path(&blocked)));
    }

    #[test]
    fn unpublished_files_are_removed_and_published_ones_renamed() {
        let dir = tempfile::tempdir().unwrap();
        let kept = dir.path().join("kept.png");
        let dropped = dir.path().join("dropped.png");

        let partial = PartialFile::new(&kept).unwrap();
        partial.create().unwrap().write_all(b"whole").unwrap();
        assert!(dir.path().join(".kept.png.partial").exists());
        partial.publish().unwrap();

        let partial = PartialFile::new(&dropped).unwrap();
        partial.create().unwrap().write_all(b"half").unwrap();
        drop(partial);

        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["kept.png"]);
        assert_eq!(std::fs::read(&kept).unwrap(), b"whole");
        let registry = registry();
        assert!(!registry.files.iter().any(|p| p.starts_with(dir.path())));
    }
}
