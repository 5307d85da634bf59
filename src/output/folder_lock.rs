//! The lock a run holds on its output folder, so that two writers never
//! mix one folder.

use super::OutputError;
use std::path::Path;

/// The exclusive lock on an output folder held while a run writes into it
/// (released when dropped, or when the process ends however it ends).
#[derive(Debug)]
pub struct FolderLock {
    /// The folder, open (on Unix; elsewhere nothing is locked).
    _folder: Option<std::fs::File>,
}

impl FolderLock {
    /// Locks `path` (a folder) or says that another process holds it.
    pub(super) fn take(path: &Path) -> Result<Self, OutputError> {
        if !cfg!(unix) {
            return Ok(Self { _folder: None });
        }
        let folder = std::fs::File::open(path).map_err(OutputError::io("open folder", path))?;
        match folder.try_lock() {
            Ok(()) => Ok(Self {
                _folder: Some(folder),
            }),
            Err(std::fs::TryLockError::WouldBlock) => Err(OutputError::InUse {
                path: path.to_owned(),
            }),
            Err(std::fs::TryLockError::Error(source)) => Err(OutputError::Io {
                action: "lock folder",
                path: path.to_owned(),
                source,
            }),
        }
    }
}
