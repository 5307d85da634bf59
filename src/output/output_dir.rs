//! The run's output folder: refused when it holds anything unless forced.

use super::folder_lock::FolderLock;
use super::owned_names::{OWNED_FILES, OWNED_FOLDERS, ours_at_top, ours_inside};
use super::{OutputError, RunFolder};
use crate::encode::write_whole_file;
use std::path::{Path, PathBuf};

/// An output folder that is ready to be written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OutputDir {
    path: PathBuf,
}

impl OutputDir {
    /// Checks `path` without touching anything: it must not be a symbolic
    /// link, and it must not exist, be an empty folder, or (with `force`)
    /// be a folder in which nothing elasto replaces or clears is a symbolic
    /// link, and nothing else sits where this run writes one of `writes`
    /// (top-level names: `scene.toml`, `frames`, `video.png`, ...).
    pub fn check(path: &Path, force: bool, writes: &[&str]) -> Result<Self, OutputError> {
        // The folder itself a link (to a folder, or dangling): writing into
        // it would write, and with --force delete, where the link points.
        if path.is_symlink() {
            return Err(OutputError::Symlink {
                path: path.to_owned(),
            });
        }
        if path.exists() {
            if !path.is_dir() {
                return Err(OutputError::NotADirectory {
                    path: path.to_owned(),
                });
            }
            let mut entries =
                std::fs::read_dir(path).map_err(OutputError::io("read folder", path))?;
            if entries.next().is_some() {
                if !force {
                    return Err(OutputError::NotEmpty {
                        path: path.to_owned(),
                    });
                }
                check_entries(path, writes)?;
            }
        }
        Ok(Self {
            path: path.to_owned(),
        })
    }

    /// Creates the folder and removes the outputs of an earlier run in it
    /// (only files elasto writes: `scene.toml`, `stats.csv`, `video.*`,
    /// `frames/frame_*.png`, `meshes/frame_*.vtu`, `meshes/frames.pvd`,
    /// `surfaces/surface_*.obj|ply`, `surfaces/obstacles_*.obj|ply`), so
    /// that a shorter run leaves no stale frames. Anything else is kept.
    /// [`OutputDir::check`] has made sure that none of these is a link.
    /// For outputs written whole at the end (a study's); a run that writes
    /// as it goes uses [`OutputDir::begin_run`], which keeps the earlier
    /// run until the new one is complete.
    ///
    /// The folder is locked first (an exclusive advisory lock on the folder
    /// itself, so no file is left behind): a second elasto preparing the
    /// same folder while the returned [`FolderLock`] lives is refused with
    /// [`OutputError::InUse`] before it removes anything. Keep the lock for
    /// as long as the run writes.
    pub fn prepare(&self) -> Result<FolderLock, OutputError> {
        let lock = self.create_and_lock()?;
        self.remove_outputs()?;
        Ok(lock)
    }

    /// Creates and locks the folder for a run (see [`OutputDir::prepare`]
    /// for the lock) and says where the run writes: when the folder holds an
    /// earlier run's outputs, into a staging folder whose files replace
    /// them once the run is complete ([`RunFolder::complete`]); otherwise in
    /// place. Either way a completed run leaves exactly its own outputs.
    pub fn begin_run(&self) -> Result<RunFolder, OutputError> {
        let lock = self.create_and_lock()?;
        let replaces = self.holds_a_run()?;
        if !replaces {
            self.remove_outputs()?;
        }
        RunFolder::new(&self.path, lock, replaces)
    }

    fn create_and_lock(&self) -> Result<FolderLock, OutputError> {
        std::fs::create_dir_all(&self.path)
            .map_err(OutputError::io("create folder", &self.path))?;
        FolderLock::take(&self.path)
    }

    /// Whether the folder holds a complete output of an earlier run: one of
    /// the top-level files, or a frame, mesh or surface.
    fn holds_a_run(&self) -> Result<bool, OutputError> {
        if OWNED_FILES
            .iter()
            .any(|name| self.path.join(name).is_file())
        {
            return Ok(true);
        }
        for folder in OWNED_FOLDERS {
            let folder = self.path.join(folder);
            if !folder.is_dir() {
                continue;
            }
            let entries =
                std::fs::read_dir(&folder).map_err(OutputError::io("read folder", &folder))?;
            for entry in entries {
                let entry = entry.map_err(OutputError::io("read folder", &folder))?;
                let name = entry.file_name().to_string_lossy().into_owned();
                if ours_inside(&name) && !name.starts_with('.') {
                    return Ok(true);
                }
            }
        }
        Ok(false)
    }

    /// Removes the outputs of an earlier run (see [`OutputDir::prepare`]).
    fn remove_outputs(&self) -> Result<(), OutputError> {
        for name in OWNED_FILES {
            remove_if_file(&self.path.join(name))?;
        }
        for folder in OWNED_FOLDERS {
            let folder = self.path.join(folder);
            if !folder.is_dir() {
                continue;
            }
            let entries = std::fs::read_dir(&folder)
                .and_then(|entries| entries.collect::<Result<Vec<_>, _>>())
                .map_err(OutputError::io("read folder", &folder))?;
            for entry in entries {
                let name = entry.file_name().to_string_lossy().into_owned();
                if !ours_inside(&name) || name.ends_with(".partial") {
                    continue;
                }
                remove_if_file(&entry.path())?;
            }
        }
        Ok(())
    }

    /// The folder.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// A path inside the folder.
    pub fn join(&self, name: impl AsRef<Path>) -> PathBuf {
        self.path.join(name)
    }

    /// Writes a whole file inside the folder, through a hidden temporary
    /// file: a failed write leaves no partial file under `name`.
    pub fn write(&self, name: &str, contents: &str) -> Result<PathBuf, OutputError> {
        let path = self.join(name);
        write_whole_file(&path, contents.as_bytes()).map_err(OutputError::io("write", &path))?;
        Ok(path)
    }
}

/// Refuses links among the entries elasto replaces or clears, and anything
/// that is not a file (or not a folder) where this run writes one.
fn check_entries(path: &Path, writes: &[&str]) -> Result<(), OutputError> {
    let kind = |meta: &std::fs::Metadata| {
        if meta.is_dir() {
            "a folder"
        } else if meta.is_file() {
            "a file"
        } else {
            "a special file"
        }
    };
    let entries = std::fs::read_dir(path).map_err(OutputError::io("read folder", path))?;
    for entry in entries {
        let entry = entry.map_err(OutputError::io("read folder", path))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if !ours_at_top(&name) {
            continue;
        }
        let entry_path = entry.path();
        let meta = std::fs::symlink_metadata(&entry_path)
            .map_err(OutputError::io("inspect", &entry_path))?;
        if meta.file_type().is_symlink() {
            return Err(OutputError::Symlink { path: entry_path });
        }
        let folder = OWNED_FOLDERS.contains(&name.as_str());
        if writes.contains(&name.as_str()) && meta.is_dir() != folder {
            return Err(OutputError::InTheWay {
                path: entry_path,
                found: kind(&meta),
                expected: if folder {
                    "a folder of frames"
                } else {
                    "a file"
                },
            });
        }
        if folder && meta.is_dir() {
            let inner = std::fs::read_dir(&entry_path)
                .map_err(OutputError::io("read folder", &entry_path))?;
            for item in inner {
                let item = item.map_err(OutputError::io("read folder", &entry_path))?;
                let item_name = item.file_name().to_string_lossy().into_owned();
                if !ours_inside(&item_name) {
                    continue;
                }
                let item_path = item.path();
                let meta = std::fs::symlink_metadata(&item_path)
                    .map_err(OutputError::io("inspect", &item_path))?;
                if meta.file_type().is_symlink() {
                    return Err(OutputError::Symlink { path: item_path });
                }
                if writes.contains(&name.as_str()) && !meta.is_file() {
                    return Err(OutputError::InTheWay {
                        path: item_path,
                        found: kind(&meta),
                        expected: "a file",
                    });
                }
            }
        }
    }
    Ok(())
}

fn remove_if_file(path: &Path) -> Result<(), OutputError> {
    if path.is_file() {
        std::fs::remove_file(path).map_err(OutputError::io("remove", path))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_and_empty_folders_are_accepted() {
        let tmp = tempfile::tempdir().unwrap();
        assert!(OutputDir::check(&tmp.path().join("new"), false, &[]).is_ok());
        assert!(OutputDir::check(tmp.path(), false, &[]).is_ok());
    }

    #[test]
    fn non_empty_folder_is_refused_without_force_and_kept_with_it() {
        let tmp = tempfile::tempdir().unwrap();
        std::fs::write(tmp.path().join("notes.txt"), "mine").unwrap();
        std::fs::write(tmp.path().join("stats.csv"), "old").unwrap();
        std::fs::create_dir(tmp.path().join("frames")).unwrap();
        std::fs::write(tmp.path().join("frames/frame_0009.png"), "old").unwrap();
        std::fs::write(tmp.path().join("frames/keep.png"), "mine").unwrap();
        let err = OutputDir::check(tmp.path(), false, &[]).unwrap_err();
        assert!(matches!(err, OutputError::NotEmpty { .. }));
        assert!(err.to_string().contains(&tmp.path().display().to_string()));

        let dir = OutputDir::check(tmp.path(), true, &["frames"]).unwrap();
        dir.prepare().unwrap();
        assert_eq!(
            std::fs::read_to_string(tmp.path().join("notes.txt")).unwrap(),
            "mine"
        );
        assert_eq!(
            std::fs::read_to_string(tmp.path().join("frames/keep.png")).unwrap(),
            "mine"
        );
        assert!(!tmp.path().join("stats.csv").exists());
        assert!(!tmp.path().join("frames/frame_0009.png").exists());
    }

    #[test]
    fn a_file_in_the_way_is_refused() {
        let tmp = tempfile::tempdir().unwrap();
        let file = tmp.path().join("out");
        std::fs::write(&file, "x").unwrap();
        assert!(matches!(
            OutputDir::check(&file, true, &[]),
            Err(OutputError::NotADirectory { .. })
        ));
    }

    #[cfg(unix)]
    #[test]
    fn links_among_elastos_files_are_refused_and_left_alone() {
        let tmp = tempfile::tempdir().unwrap();
        let elsewhere = tmp.path().join("elsewhere");
        std::fs::create_dir(&elsewhere).unwrap();
        std::fs::write(elsewhere.join("frame_0042.png"), "theirs").unwrap();
        std::fs::write(elsewhere.join("stats.csv"), "theirs").unwrap();
        let cases: &[(&str, &str)] = &[
            ("frames", "elsewhere"),
            ("meshes", "elsewhere"),
            ("stats.csv", "elsewhere/stats.csv"),
            (".video.png.partial", "elsewhere/stats.csv"),
            ("frames/frame_0001.png", "../elsewhere/frame_0042.png"),
            (
                "frames/.frame_0001.png.partial",
                "../elsewhere/frame_0042.png",
            ),
        ];
        for (link, target) in cases {
            let out = tmp.path().join("out");
            let _ = std::fs::remove_dir_all(&out);
            std::fs::create_dir_all(out.join("frames")).unwrap();
            if *link != "frames" {
                std::fs::write(out.join("frames/frame_0000.png"), "old").unwrap();
            } else {
                std::fs::remove_dir(out.join("frames")).unwrap();
            }
            let target = if target.starts_with("..") {
                PathBuf::from(target)
            } else {
                elsewhere.join(
                    target
                        .trim_start_matches("elsewhere")
                        .trim_start_matches('/'),
                )
            };
            std::os::unix::fs::symlink(&target, out.join(link)).unwrap();
            let err = OutputDir::check(&out, true, &["scene.toml", "frames"]).unwrap_err();
            assert!(matches!(err, OutputError::Symlink { .. }), "{link}: {err}");
            assert!(err.to_string().contains(link), "{err}");
            assert_eq!(
                std::fs::read_to_string(elsewhere.join("frame_0042.png")).unwrap(),
                "theirs"
            );
        }
        // A link elasto does not write to is the user's own and stays allowed.
        let out = tmp.path().join("mine");
        std::fs::create_dir(&out).unwrap();
        std::os::unix::fs::symlink(&elsewhere, out.join("notes")).unwrap();
        OutputDir::check(&out, true, &["frames"])
            .unwrap()
            .prepare()
            .unwrap();
        assert!(elsewhere.join("frame_0042.png").exists());
    }

    #[test]
    fn something_else_where_the_run_writes_is_refused() {
        let tmp = tempfile::tempdir().unwrap();
        std::fs::write(tmp.path().join("frames"), "a file").unwrap();
        let err = OutputDir::check(tmp.path(), true, &["scene.toml", "frames"]).unwrap_err();
        assert!(
            matches!(
                err,
                OutputError::InTheWay {
                    found: "a file",
                    ..
                }
            ),
            "{err}"
        );
        // A run that writes no frames does not mind.
        OutputDir::check(tmp.path(), true, &["scene.toml", "stats.csv"]).unwrap();
        std::fs::remove_file(tmp.path().join("frames")).unwrap();
        std::fs::create_dir(tmp.path().join("stats.csv")).unwrap();
        let err = OutputDir::check(tmp.path(), true, &["stats.csv"]).unwrap_err();
        assert!(
            matches!(
                err,
                OutputError::InTheWay {
                    found: "a folder",
                    ..
                }
            ),
            "{err}"
        );
    }
}
