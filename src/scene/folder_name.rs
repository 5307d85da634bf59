//! The rule for a name that becomes an output folder (a scene's `name`, a
//! sweep file's `name`): one plain folder name, never a path.

use super::MAX_NAME_BYTES;
use std::path::{Component, Path};

/// What is wrong with `name` as the last part of the output folder
/// `folder` (`out/NAME`, `out/sweeps/NAME`), or `None` when it is a plain
/// name: not empty, no control characters, no path separator, not `.` or
/// `..`, not absolute, at most [`MAX_NAME_BYTES`] bytes.
pub fn folder_name_problem(name: &str, folder: &str) -> Option<String> {
    if name.trim().is_empty() {
        Some("must not be empty".to_owned())
    } else if name.chars().any(char::is_control) {
        Some(format!("must not contain control characters, got {name:?}"))
    } else if name.contains(['/', '\\'])
        || !matches!(
            Path::new(name).components().collect::<Vec<_>>()[..],
            [Component::Normal(_)]
        )
    {
        Some(format!(
            "must be a plain name, not a path ({name:?} has a path separator, `.` or `..`, \
             or is absolute): it names the output folder {folder}"
        ))
    } else if name.len() > MAX_NAME_BYTES {
        Some(format!(
            "must be at most {MAX_NAME_BYTES} bytes long (it names a folder), got {}",
            name.len()
        ))
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_names_pass_and_paths_do_not() {
        assert_eq!(folder_name_problem("stiffness", "out/NAME"), None);
        for path in ["../../x", "/tmp/x", "a/b", "..", ".", "a\\b"] {
            let problem = folder_name_problem(path, "out/sweeps/NAME").unwrap();
            assert!(
                problem.contains("must be a plain name"),
                "{path}: {problem}"
            );
            assert!(problem.contains("out/sweeps/NAME"), "{problem}");
        }
        assert!(folder_name_problem(" ", "out/NAME").is_some());
        assert!(folder_name_problem("a\nb", "out/NAME").is_some());
        assert!(folder_name_problem(&"x".repeat(256), "out/NAME").is_some());
    }
}
