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
//!
//! **Spare files.** A run with `--force` replaces an earlier run's frames.
//! Deleting 300 files and creating 300 new ones is not free: on ext4
//! without a journal, each new file's inode is searched for past every inode
//! freed in the last few seconds to minutes, which cost a re-run of the
//! default scene more CPU time than encoding its PNGs. So the earlier
//! frames are not deleted but hidden as spares ([`keep_as_spare`]:
//! `.frame_0042.png.spare`, entered in the list), and a partial file in the
//! same folder takes a spare's inode — renamed to the temporary and
//! truncated — instead of a new one. Only a regular file with one link
//! becomes a spare (truncating a hard link would change the other name's
//! contents). The spares left when the run ends are removed
//! ([`SpareFiles`]), and by [`remove_partial_files`] on an interrupt; one
//! left by a killed process is taken again by the next `--force` run.

use super::RenderError;
use super::image_file::{hidden_path, temporary_path};
use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// The partial files alive in this process.
#[derive(Default)]
struct Registry {
    /// Temporary paths of the partial files.
    files: Vec<PathBuf>,
    /// Hidden files of an earlier run whose inodes the next partial files
    /// in their folders take (see the module documentation).
    spares: Vec<PathBuf>,
    /// [`remove_partial_files`] has run: the process is about to exit.
    closed: bool,
}

static REGISTRY: Mutex<Registry> = Mutex::new(Registry {
    files: Vec::new(),
    spares: Vec::new(),
    closed: false,
});

fn registry() -> MutexGuard<'static, Registry> {
    REGISTRY
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Removes every partial file of this process (and the spares); returns how
/// many partial files were removed. After
/// this call no partial file can be created: it is meant for a signal
/// handler that exits right after.
pub fn remove_partial_files() -> usize {
    let mut registry = registry();
    registry.closed = true;
    for spare in registry.spares.drain(..) {
        let _ = std::fs::remove_file(spare);
    }
    registry
        .files
        .iter()
        .filter(|path| std::fs::remove_file(path).is_ok())
        .count()
}

/// Hides `path`, a file of an earlier run that this run replaces, as a spare
/// whose inode the next partial file in its folder takes (see the module
/// documentation); a file that is not a regular file with a single link, or
/// that cannot be renamed, is removed instead. `path` may be a spare already
/// (left by a killed run).
pub(crate) fn keep_as_spare(path: &Path) -> std::io::Result<()> {
    let meta = std::fs::symlink_metadata(path)?;
    #[cfg(unix)]
    let single_link = std::os::unix::fs::MetadataExt::nlink(&meta) == 1;
    #[cfg(not(unix))]
    let single_link = false;
    if !(meta.is_file() && single_link) {
        return std::fs::remove_file(path);
    }
    let is_spare = path
        .file_name()
        .is_some_and(|n| n.to_string_lossy().ends_with(".spare"));
    let spare = if is_spare {
        path.to_owned()
    } else {
        let spare = hidden_path(path, "spare");
        if std::fs::rename(path, &spare).is_err() {
            return std::fs::remove_file(path);
        }
        spare
    };
    registry().spares.push(spare);
    Ok(())
}

/// Takes a spare in `folder` off the list.
fn take_spare(registry: &mut Registry, folder: Option<&Path>) -> Option<PathBuf> {
    let index = registry
        .spares
        .iter()
        .rposition(|spare| spare.parent() == folder)?;
    Some(registry.spares.swap_remove(index))
}

/// Removes, when dropped, the spares still waiting under its folder: the
/// earlier run's files that this run did not reuse.
#[must_use = "dropping it removes the spares at once"]
pub struct SpareFiles {
    folder: PathBuf,
}

impl SpareFiles {
    /// Watches the spares under `folder`.
    pub fn under(folder: &Path) -> Self {
        Self {
            folder: folder.to_owned(),
        }
    }
}

impl Drop for SpareFiles {
    fn drop(&mut self) {
        let mut registry = registry();
        registry.spares.retain(|spare| {
            let ours = spare.starts_with(&self.folder);
            if ours {
                let _ = std::fs::remove_file(spare);
            }
            !ours
        });
    }
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

    /// Writes `bytes` as the whole temporary file. A spare is written over
    /// and then cut to their length: truncating it first would free all
    /// its blocks, and on a file system mounted with `discard` (this
    /// project's machines' ext4) every block freed waits for the disk to
    /// discard it, about a millisecond per frame; written over, a file
    /// frees at most the blocks past its new end.
    pub fn write_whole(&self, bytes: &[u8]) -> Result<(), RenderError> {
        let io = |source| RenderError::Io {
            path: self.path.clone(),
            source,
        };
        let mut file = self.open(false)?;
        let old_length = file.metadata().map_err(io)?.len();
        file.write_all(bytes).map_err(io)?;
        if old_length > bytes.len() as u64 {
            file.set_len(bytes.len() as u64).map_err(io)?;
        }
        Ok(())
    }

    /// Creates (or truncates) the temporary file: a spare in its folder
    /// renamed, when there is one, so that no new inode is needed.
    pub fn create(&self) -> Result<File, RenderError> {
        self.open(true)
    }

    /// Creates the temporary file, or takes a spare in its folder, renamed
    /// (so that no new inode is needed), truncated with `truncate`.
    fn open(&self, truncate: bool) -> Result<File, RenderError> {
        let mut registry = registry();
        if registry.closed {
            return Err(RenderError::Interrupted);
        }
        if let Some(spare) = take_spare(&mut registry, self.temporary.parent())
            && std::fs::rename(&spare, &self.temporary).is_ok()
            && let Ok(file) = open_existing(&self.temporary, truncate)
        {
            return Ok(file);
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
/// temporary (see [`PartialFile`]): the final name holds the earlier file or
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

/// Opens the file at `path` for writing, truncated with `truncate`,
/// without creating it and without following a link.
fn open_existing(path: &Path, truncate: bool) -> std::io::Result<File> {
    let mut options = std::fs::OpenOptions::new();
    options.write(true).truncate(truncate);
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::custom_flags(&mut options, libc::O_NOFOLLOW);
    options.open(path)
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

    /// The names in `folder`, sorted.
    fn names(folder: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(folder)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[cfg(unix)]
    #[test]
    fn a_partial_file_takes_a_spare_in_its_own_folder_and_the_rest_go() {
        use std::os::unix::fs::MetadataExt;
        let dir = tempfile::tempdir().unwrap();
        let (frames, other) = (dir.path().join("frames"), dir.path().join("other"));
        std::fs::create_dir(&frames).unwrap();
        std::fs::create_dir(&other).unwrap();
        let old = frames.join("frame_0007.png");
        std::fs::write(&old, b"an earlier, longer frame").unwrap();
        let old_inode = std::fs::metadata(&old).unwrap().ino();
        let linked = frames.join("frame_0008.png");
        std::fs::write(&linked, b"linked").unwrap();
        std::fs::hard_link(&linked, dir.path().join("kept.png")).unwrap();

        let spares = SpareFiles::under(dir.path());
        keep_as_spare(&old).unwrap();
        keep_as_spare(&linked).unwrap();
        // The single-link file is hidden; the linked one is only unlinked here.
        assert_eq!(names(&frames), [".frame_0007.png.spare"]);
        assert_eq!(
            std::fs::read(dir.path().join("kept.png")).unwrap(),
            b"linked"
        );

        // A file in another folder does not take it.
        let elsewhere = PartialFile::new(&other.join("frame_0000.png")).unwrap();
        elsewhere.create().unwrap().write_all(b"x").unwrap();
        elsewhere.publish().unwrap();
        assert_eq!(names(&frames), [".frame_0007.png.spare"]);

        let new = frames.join("frame_0000.png");
        let partial = PartialFile::new(&new).unwrap();
        partial.create().unwrap().write_all(b"new").unwrap();
        partial.publish().unwrap();
        assert_eq!(std::fs::read(&new).unwrap(), b"new", "truncated, rewritten");
        assert_eq!(std::fs::metadata(&new).unwrap().ino(), old_inode);
        assert_eq!(names(&frames), ["frame_0000.png"]);

        // The spares left over go when the guard does.
        std::fs::write(frames.join("frame_0001.png"), b"old").unwrap();
        keep_as_spare(&frames.join("frame_0001.png")).unwrap();
        assert_eq!(names(&frames), [".frame_0001.png.spare", "frame_0000.png"]);
        drop(spares);
        assert_eq!(names(&frames), ["frame_0000.png"]);
        assert!(!registry().spares.iter().any(|p| p.starts_with(dir.path())));
    }

    #[cfg(unix)]
    #[test]
    fn a_file_written_whole_over_a_spare_takes_its_inode_and_its_own_length() {
        use std::os::unix::fs::MetadataExt;
        let dir = tempfile::tempdir().unwrap();
        let spares = SpareFiles::under(dir.path());
        for (old, new) in [
            (&b"an earlier, longer frame"[..], &b"short"[..]),
            (&b"tiny"[..], &b"a frame longer than the spare"[..]),
        ] {
            let earlier = dir.path().join("frame_0003.png");
            std::fs::write(&earlier, old).unwrap();
            let inode = std::fs::metadata(&earlier).unwrap().ino();
            keep_as_spare(&earlier).unwrap();
            let path = dir.path().join("frame_0000.png");
            let partial = PartialFile::new(&path).unwrap();
            partial.write_whole(new).unwrap();
            partial.publish().unwrap();
            assert_eq!(std::fs::read(&path).unwrap(), new, "no tail of the spare");
            assert_eq!(std::fs::metadata(&path).unwrap().ino(), inode);
        }
        // Without a spare, a new file.
        let path = dir.path().join("frame_0001.png");
        let partial = PartialFile::new(&path).unwrap();
        partial.write_whole(b"new").unwrap();
        partial.publish().unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
        drop(spares);
        assert_eq!(names(dir.path()), ["frame_0000.png", "frame_0001.png"]);
    }
}
