//! [`PartialFile`]: a file written under its hidden temporary name until it
//! is complete, and the process-wide list of such files that an interrupt
//! cleans up ([`remove_partial_files`]).
//!
//! Every frame and video of a run is written to `.NAME.partial` beside its
//! final name and renamed once complete, so a file under a final name is
//! always whole. A [`PartialFile`] removes its temporary when dropped
//! unpublished (the run failed). A signal does not run destructors, so each
//! partial file is also entered in a list, together with the encoder
//! processes (ffmpeg) that write one; [`remove_partial_files`] kills those
//! processes and removes those files, and the binary calls it on SIGINT and
//! SIGTERM before exiting.
//!
//! Creating, publishing and removing a temporary, and starting or reaping an
//! encoder, happen under the list's lock, and [`remove_partial_files`] closes
//! the list for good: nothing can create a partial file after the cleanup has
//! run, nor slip between its kills and its removals.

use super::RenderError;
use super::image_file::temporary_path;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus};
use std::sync::{Mutex, MutexGuard};

/// The partial files and encoder processes alive in this process.
#[derive(Default)]
struct Registry {
    /// Temporary paths of the partial files.
    files: Vec<PathBuf>,
    /// Process ids of encoders, each the leader of its own process group.
    processes: Vec<u32>,
    /// [`remove_partial_files`] has run: the process is about to exit.
    closed: bool,
}

static REGISTRY: Mutex<Registry> = Mutex::new(Registry {
    files: Vec::new(),
    processes: Vec::new(),
    closed: false,
});

fn registry() -> MutexGuard<'static, Registry> {
    REGISTRY
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Kills every encoder process (with its process group) and removes every
/// partial file of this process; returns how many files were removed. After
/// this call no partial file can be created: it is meant for a signal
/// handler that exits right after.
pub fn remove_partial_files() -> usize {
    let mut registry = registry();
    registry.closed = true;
    for &pid in &registry.processes {
        kill_group(pid);
    }
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

    /// The hidden temporary name.
    pub fn temporary(&self) -> &Path {
        &self.temporary
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

/// Takes one registration of `temporary` off the list.
fn forget(registry: &mut Registry, temporary: &Path) {
    if let Some(index) = registry.files.iter().position(|p| p == temporary) {
        registry.files.swap_remove(index);
    }
}

/// Starts `command` (an encoder such as ffmpeg) in a process group of its
/// own, registered so that an interrupt kills it, and whatever it started,
/// before removing the partial files. Reap it with [`try_reap`] or
/// [`kill_and_reap`], which take it off the list.
pub(crate) fn spawn_process(command: &mut Command) -> Result<Child, SpawnError> {
    #[cfg(unix)]
    std::os::unix::process::CommandExt::process_group(command, 0);
    let mut registry = registry();
    if registry.closed {
        return Err(SpawnError::Interrupted);
    }
    let child = command.spawn().map_err(SpawnError::Io)?;
    registry.processes.push(child.id());
    Ok(child)
}

/// Reaps `child` if it has exited. Reaping and leaving the list happen under
/// one lock, so an interrupt never signals a process id that the system may
/// already have given to another process.
pub(crate) fn try_reap(child: &mut Child) -> std::io::Result<Option<ExitStatus>> {
    let mut registry = registry();
    let status = child.try_wait()?;
    if status.is_some() {
        registry.processes.retain(|&pid| pid != child.id());
    }
    Ok(status)
}

/// Kills `child` and its process group, and reaps it (nothing when it is
/// reaped already).
pub(crate) fn kill_and_reap(child: &mut Child) {
    let mut registry = registry();
    if registry.processes.contains(&child.id()) {
        kill_group(child.id());
        let _ = child.kill();
        let _ = child.wait();
        registry.processes.retain(|&pid| pid != child.id());
    }
}

/// Why an encoder process could not be started.
#[derive(Debug)]
pub(crate) enum SpawnError {
    /// The run is being interrupted.
    Interrupted,
    /// The operating system refused.
    Io(std::io::Error),
}

/// Sends SIGKILL to the process group led by `pid`.
fn kill_group(pid: u32) {
    #[cfg(unix)]
    if let Ok(pid) = libc::pid_t::try_from(pid) {
        // SAFETY: kill(2) has no memory-safety preconditions; a negative
        // pid names the process group.
        unsafe { libc::kill(-pid, libc::SIGKILL) };
    }
    #[cfg(not(unix))]
    let _ = pid;
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

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
