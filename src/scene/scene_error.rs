//! Errors of reading and validating a scene: each names the file (or flag), the key and the line.

use crate::input_file::InputFileError;
use std::fmt;
use std::path::PathBuf;

/// A number for a message: plain when it reads well (`0.3`, `300`,
/// `12.5`), short scientific otherwise (`1e-300`, `1.5e39`), never hundreds
/// of digits.
pub fn num(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-4..1e6).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A computed number for a message, to 4 significant digits in the same
/// two forms as [`num`]: `465.3`, `0.003333`, `4.653e8`.
pub fn approx(x: f64) -> String {
    let trim = |t: String| -> String {
        if t.contains('.') {
            t.trim_end_matches('0').trim_end_matches('.').to_owned()
        } else {
            t
        }
    };
    if x == 0.0 || !x.is_finite() {
        format!("{x}")
    } else if (1e-4..1e6).contains(&x.abs()) {
        let digits = (3 - x.abs().log10().floor() as i32).max(0) as usize;
        trim(format!("{x:.digits$}"))
    } else {
        let text = format!("{x:.3e}");
        let (mantissa, exponent) = text.split_once('e').expect("scientific form");
        format!("{}e{exponent}", trim(mantissa.to_owned()))
    }
}

/// A list of numbers for a message, e.g. `[1e-300, 0.5]`.
pub(crate) fn nums(values: &[f64]) -> String {
    let parts: Vec<String> = values.iter().map(|&x| num(x)).collect();
    format!("[{}]", parts.join(", "))
}

/// Where a bad value came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Origin {
    /// A position in the scene file (1-based line and column).
    File {
        /// Line number, from 1.
        line: usize,
        /// Column number (characters), from 1.
        column: usize,
    },
    /// A command-line override, as the user typed it (e.g. `--set time.frames=0`).
    Flag(String),
    /// The scene as a whole (e.g. a key that is missing and has no default).
    Scene,
}

/// One problem in a scene, with its origin and dotted key.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Diagnostic {
    /// The scene file's path, or `built-in scene NAME`.
    pub source: String,
    /// Where in the file, or which flag.
    pub origin: Origin,
    /// The dotted key, e.g. `material.young` (`None` for a TOML syntax error).
    pub key: Option<String>,
    /// What is wrong.
    pub reason: String,
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.origin {
            Origin::File { line, column } => write!(f, "{}:{line}:{column}: ", self.source)?,
            Origin::Flag(flag) => write!(f, "{flag} (in {}): ", self.source)?,
            Origin::Scene => write!(f, "{}: ", self.source)?,
        }
        if let Some(key) = &self.key {
            write!(f, "`{key}`: ")?;
        }
        write!(f, "{}", self.reason)
    }
}

/// Errors of finding, reading, parsing or validating a scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("cannot read scene file {path}: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// Why: the OS refused, it is not a regular file, or it is too large.
        source: InputFileError,
    },
    /// Neither a file nor a built-in scene has this name.
    #[error("no scene file or built-in scene named `{name}` (built-in scenes: {available})")]
    NotFound {
        /// What the user asked for.
        name: String,
        /// Comma-separated built-in names.
        available: String,
    },
    /// A `--set` argument is malformed (no `=`, empty key, ...).
    #[error("invalid `{flag}`: {reason}")]
    BadOverride {
        /// The flag as typed.
        flag: String,
        /// What is wrong.
        reason: String,
    },
    /// The scene is malformed or out of range.
    #[error("{0}")]
    Invalid(Box<Diagnostic>),
}

impl SceneError {
    /// The diagnostic, when this is a malformed or out-of-range scene.
    pub fn diagnostic(&self) -> Option<&Diagnostic> {
        match self {
            SceneError::Invalid(d) => Some(d),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_short() {
        assert_eq!(num(0.3), "0.3");
        assert_eq!(num(300.0), "300");
        assert_eq!(num(-12.5), "-12.5");
        assert_eq!(num(0.0), "0");
        assert_eq!(num(1e-300), "1e-300");
        assert_eq!(num(-1e300), "-1e300");
        assert_eq!(num(1.5e39), "1.5e39");
        assert_eq!(num(f64::INFINITY), "inf");
        assert_eq!(nums(&[1e-300, 0.5]), "[1e-300, 0.5]");
        assert_eq!(approx(465.2680399943009), "465.3");
        assert_eq!(approx(0.0033333333333333335), "0.003333");
        assert_eq!(approx(4.652680399943009e8), "4.653e8");
        assert_eq!(approx(0.0004652680399943009), "0.0004653");
        assert_eq!(approx(0.00004652680399943009), "4.653e-5");
        assert_eq!(approx(1.1111111111111113e-5), "1.111e-5");
        assert_eq!(approx(3e301), "3e301");
        assert_eq!(approx(30.0), "30");
    }
}
