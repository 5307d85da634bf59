//! The run's output folder: refused when it holds anything unless forced.

use super::OutputError;
use std::path::{Path, PathBuf};

/// Names of the files and folders a run writes at the top of its folder.
const OWNED_FILES: &[&str] = &[
    "scene.toml",
    "stats.csv",
    "video.png",
    "video.mp4",
    "video.gif",
];
/// Sub-folders whose `frame_*` files and `frames.pvd` a run writes.
const OWNED_FOLDERS: &[&str] = &["frames", "meshes"];

/// An output folder that is ready to be written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OutputDir {
    path: PathBuf,
}

impl OutputDir {
    /// Checks `path` without touching anything: it must not exist, be an
    /// empty folder, or (with `force`) be a folder.
    pub fn check(path: &Path, force: bool) -> Result<Self, OutputError> {
        if path.exists() {
            if !path.is_dir() {
                return Err(OutputError::NotADirectory {
                    path: path.to_owned(),
                });
            }
            let mut entries =
                std::fs::read_dir(path).map_err(OutputError::io("read folder", path))?;
            if entries.next().is_some() && !force {
                return Err(OutputError::NotEmpty {
                    path: path.to_owned(),
                });
            }
        }
        Ok(Self {
            path: path.to_owned(),
        })
    }

    /// Creates the folder and removes the outputs of an earlier run in it
    /// (only files elasto writes: `scene.toml`, `stats.csv`, `video.*`,
    /// `frames/frame_*.png`, `meshes/frame_*.vtu`, `meshes/frames.pvd`), so
    /// that a shorter run leaves no stale frames. Anything else is kept.
    pub fn prepare(&self) -> Result<(), OutputError> {
        std::fs::create_dir_all(&self.path)
            .map_err(OutputError::io("create folder", &self.path))?;
        for name in OWNED_FILES {
            remove_if_file(&self.path.join(name))?;
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
                let ours = (name.starts_with("frame_")
                    && (name.ends_with(".png") || name.ends_with(".vtu")))
                    || name == "frames.pvd";
                if ours {
                    remove_if_file(&entry.path())?;
                }
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

    /// Writes a whole file inside the folder.
    pub fn write(&self, name: &str, contents: &str) -> Result<PathBuf, OutputError> {
        let path = self.join(name);
        std::fs::write(&path, contents).map_err(OutputError::io("write", &path))?;
        Ok(path)
    }
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
        assert!(OutputDir::check(&tmp.path().join("new"), false).is_ok());
        assert!(OutputDir::check(tmp.path(), false).is_ok());
    }

    #[test]
    fn non_empty_folder_is_refused_without_force_and_kept_with_it() {
        let tmp = tempfile::tempdir().unwrap();
        std::fs::write(tmp.path().join("notes.txt"), "mine").unwrap();
        std::fs::write(tmp.path().join("stats.csv"), "old").unwrap();
        std::fs::create_dir(tmp.path().join("frames")).unwrap();
        std::fs::write(tmp.path().join("frames/frame_0009.png"), "old").unwrap();
        std::fs::write(tmp.path().join("frames/keep.png"), "mine").unwrap();
        let err = OutputDir::check(tmp.path(), false).unwrap_err();
        assert!(matches!(err, OutputError::NotEmpty { .. }));
        assert!(err.to_string().contains(&tmp.path().display().to_string()));

        let dir = OutputDir::check(tmp.path(), true).unwrap();
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
            OutputDir::check(&file, true),
            Err(OutputError::NotADirectory { .. })
        ));
    }
}
