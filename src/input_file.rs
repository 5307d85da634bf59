//! Reading an input file (a scene, a sweep file, a mesh) whole, safely: only
//! a regular file (after following links), and no more than a stated limit.
//!
//! A named pipe, a character device (`/dev/zero`, a terminal) or a socket
//! would make a plain read block forever or never end, so the path's kind is
//! checked before the file is opened, and again on the opened file (the path
//! may have been replaced in between). The size limit is checked against the
//! file's length before any allocation and enforced while reading, so a file
//! that grows meanwhile cannot take more.

use std::io::Read;
use std::path::Path;

/// The most elasto reads from a mesh file: 2 GiB.
pub const MAX_MESH_FILE_BYTES: u64 = 2 << 30;

/// The most elasto reads from a scene or a sweep file: 64 MiB.
pub const MAX_SETTINGS_FILE_BYTES: u64 = 64 << 20;

/// Why an input file cannot be read. Its messages leave out the path: the
/// caller's error names the file ("cannot read mesh file m.msh: ...").
#[derive(Debug, thiserror::Error)]
pub enum InputFileError {
    /// The operating system refused (no such file, a directory, a link loop, ...).
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// The path names something other than a regular file.
    #[error("it is {kind}, not a regular file")]
    NotRegular {
        /// What it is ("a named pipe (FIFO)", "a character device", ...).
        kind: &'static str,
    },
    /// The file is larger than elasto reads from a file of its kind.
    #[error("it holds {size} bytes, more than the {} elasto reads from one file", size_text(*limit))]
    TooLarge {
        /// The file's size in bytes (at least this many when it grew while read).
        size: u64,
        /// The limit, in bytes.
        limit: u64,
    },
}

/// The regular file at `path`, opened, when it holds at most `limit`
/// bytes (a caller reading it must still stop at `limit`: it may grow).
pub fn open_regular_file(path: &Path, limit: u64) -> Result<std::fs::File, InputFileError> {
    check_kind(&std::fs::metadata(path)?)?;
    let file = std::fs::File::open(path)?;
    let metadata = file.metadata()?;
    check_kind(&metadata)?;
    if metadata.len() > limit {
        return Err(InputFileError::TooLarge {
            size: metadata.len(),
            limit,
        });
    }
    Ok(file)
}

/// The whole of the regular file at `path`, at most `limit` bytes.
pub fn read_regular_file(path: &Path, limit: u64) -> Result<Vec<u8>, InputFileError> {
    let file = open_regular_file(path, limit)?;
    let metadata = file.metadata()?;
    let mut bytes = Vec::with_capacity(usize::try_from(metadata.len()).unwrap_or(0));
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(InputFileError::TooLarge {
            size: bytes.len() as u64,
            limit,
        });
    }
    Ok(bytes)
}

/// The whole of the regular text file at `path`, at most `limit` bytes; text
/// that is not UTF-8 is an I/O error of kind `InvalidData`, as
/// [`std::fs::read_to_string`] gives.
pub fn read_regular_text_file(path: &Path, limit: u64) -> Result<String, InputFileError> {
    let bytes = read_regular_file(path, limit)?;
    String::from_utf8(bytes).map_err(|_| {
        InputFileError::Io(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "the file is not UTF-8 text",
        ))
    })
}

/// Refuses everything but a regular file.
fn check_kind(metadata: &std::fs::Metadata) -> Result<(), InputFileError> {
    if metadata.is_file() {
        return Ok(());
    }
    Err(InputFileError::NotRegular {
        kind: kind_name(metadata),
    })
}

/// What a non-regular file is, in words.
fn kind_name(metadata: &std::fs::Metadata) -> &'static str {
    if metadata.is_dir() {
        return "a folder";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let kind = metadata.file_type();
        if kind.is_fifo() {
            return "a named pipe (FIFO)";
        }
        if kind.is_char_device() {
            return "a character device";
        }
        if kind.is_block_device() {
            return "a block device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    "not a regular file"
}

/// `2 GiB`, `64 MiB`, or the bytes when not a whole number of MiB.
fn size_text(bytes: u64) -> String {
    const MIB: u64 = 1 << 20;
    const GIB: u64 = 1 << 30;
    if bytes >= GIB && bytes.is_multiple_of(GIB) {
        format!("{} GiB", bytes / GIB)
    } else if bytes >= MIB && bytes.is_multiple_of(MIB) {
        format!("{} MiB", bytes / MIB)
    } else {
        format!("{bytes} bytes")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_regular_file_is_read_whole() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.toml");
        std::fs::write(&path, "name = \"a\"\n").unwrap();
        assert_eq!(
            read_regular_text_file(&path, 100).unwrap(),
            "name = \"a\"\n"
        );
    }

    #[test]
    fn a_folder_is_refused_by_its_kind() {
        let dir = tempfile::tempdir().unwrap();
        let err = read_regular_file(dir.path(), 100).unwrap_err();
        assert_eq!(err.to_string(), "it is a folder, not a regular file");
    }

    #[cfg(unix)]
    #[test]
    fn a_character_device_is_refused_before_reading() {
        let err = read_regular_file(Path::new("/dev/zero"), 100).unwrap_err();
        assert_eq!(
            err.to_string(),
            "it is a character device, not a regular file"
        );
    }

    #[test]
    fn a_file_over_the_limit_is_refused_with_both_sizes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big.msh");
        std::fs::write(&path, vec![b' '; 3 << 20]).unwrap();
        let err = read_regular_file(&path, 2 << 20).unwrap_err();
        assert_eq!(
            err.to_string(),
            "it holds 3145728 bytes, more than the 2 MiB elasto reads from one file"
        );
    }

    #[test]
    fn a_missing_file_keeps_the_os_cause() {
        let err = read_regular_file(Path::new("/nonexistent/m.msh"), 100).unwrap_err();
        assert!(
            err.to_string().contains("No such file or directory"),
            "{err}"
        );
    }
}
