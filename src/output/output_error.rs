//! Errors of writing outputs: each names the file or folder.

use std::path::PathBuf;

/// A failure to create, clear or write an output.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The output folder exists, is not empty, and overwriting was not asked for.
    #[error(
        "the output folder {path} already exists and is not empty; pass --force to replace elasto's files in it, or choose another folder with --out"
    )]
    NotEmpty {
        /// The folder.
        path: PathBuf,
    },
    /// The output path exists and is not a folder.
    #[error("the output path {path} exists and is not a folder")]
    NotADirectory {
        /// The path.
        path: PathBuf,
    },
    /// A file or folder elasto would replace or clear is a symbolic link:
    /// writing through it could touch files outside the output folder.
    #[error(
        "{path} is a symbolic link; elasto never deletes or writes through links in its output folder: remove the link or choose another folder with --out"
    )]
    Symlink {
        /// The link.
        path: PathBuf,
    },
    /// Something else sits where the run writes a file or a folder.
    #[error(
        "{path} is {found}, where this run writes {expected}; move it away or choose another folder with --out"
    )]
    InTheWay {
        /// The path.
        path: PathBuf,
        /// What is there ("a file", "a folder").
        found: &'static str,
        /// What the run writes there ("the folder of frames", ...).
        expected: &'static str,
    },
    /// Another elasto process is writing into the folder now.
    #[error(
        "another elasto is writing into the output folder {path} now; wait for it to finish, or choose another folder with --out"
    )]
    InUse {
        /// The folder.
        path: PathBuf,
    },
    /// An I/O operation on a file or folder failed.
    #[error("cannot {action} {path}")]
    Io {
        /// What was being done ("write", "create folder", ...).
        action: &'static str,
        /// The file or folder.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
}

impl OutputError {
    /// Wraps an I/O error with the action and path.
    pub fn io(
        action: &'static str,
        path: impl Into<PathBuf>,
    ) -> impl FnOnce(std::io::Error) -> Self {
        let path = path.into();
        move |source| OutputError::Io {
            action,
            path,
            source,
        }
    }
}
