//! Sweep files: a study written down (scene, varied keys, shared overrides) so it can be committed and rerun.
//!
//! ```toml
//! scene = "report-drop-2d"        # a built-in name, or a scene file relative to this file
//! name = "stiffness"              # default: this file's stem
//! zip = false                     # default: the cartesian product
//! set = { "time.frames" = 60 }    # overrides for every run (like --set)
//!
//! [vary]
//! "material.young" = [100, 300, 1000, 3000]
//! "time.substeps" = "linspace(1, 10, 4)"
//! ```
//!
//! Every other top-level key is an error, so a typo is not silently ignored.

use super::SweepError;
use super::vary::{VaryAxis, axis_from_toml};
use crate::input_file::{MAX_SETTINGS_FILE_BYTES, read_regular_text_file};
use crate::scene::folder_name_problem;
use std::path::{Path, PathBuf};

/// A parsed sweep file.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepFile {
    /// The scene argument: a scene file path (relative paths resolved against
    /// the sweep file's folder when such a file exists) or a built-in name.
    pub scene: String,
    /// The sweep's name (default: the file stem).
    pub name: String,
    /// Pair the lists instead of taking their product (default: false).
    pub zip: bool,
    /// Overrides for every run, as `key=value` (TOML text), like `--set`.
    pub set: Vec<String>,
    /// The varied keys, in the file's order.
    pub axes: Vec<VaryAxis>,
}

/// Whether `path` looks like a sweep file: a TOML file with a top-level
/// `scene` or `vary` (scene files have neither), so that a sweep file that
/// lacks its `scene`, or gives it as other than a string, is told so rather
/// than read as a scene with unknown keys.
pub fn is_sweep_file(path: &Path) -> bool {
    if !path.is_file() {
        return false;
    }
    let Ok(text) = std::fs::read_to_string(path) else {
        return false;
    };
    text.parse::<toml::Table>()
        .is_ok_and(|table| table.contains_key("scene") || table.contains_key("vary"))
}

impl SweepFile {
    /// Reads and checks a sweep file.
    pub fn read(path: &Path) -> Result<Self, SweepError> {
        let text = read_regular_text_file(path, MAX_SETTINGS_FILE_BYTES).map_err(|source| {
            SweepError::ReadFile {
                path: path.to_owned(),
                source,
            }
        })?;
        Self::parse(&text, path)
    }

    /// Parses the text of the sweep file `path`.
    pub fn parse(text: &str, path: &Path) -> Result<Self, SweepError> {
        let bad = |reason: String| SweepError::BadFile {
            path: path.to_owned(),
            reason,
        };
        let table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
            bad(format!("not valid TOML: {}", e.to_string().trim_end()))
        })?;
        for key in table.keys() {
            if !["scene", "name", "zip", "set", "vary"].contains(&key.as_str()) {
                return Err(bad(format!(
                    "unknown key `{key}` (a sweep file has scene, name, zip, set and [vary])"
                )));
            }
        }
        let scene = match table.get("scene") {
            Some(toml::Value::String(scene)) => scene_argument(scene, path),
            Some(_) => return Err(bad("`scene` must be a string".into())),
            None => {
                return Err(bad(
                    "`scene` is missing (a scene file or built-in name)".into()
                ));
            }
        };
        let name = match table.get("name") {
            Some(toml::Value::String(name)) if !name.trim().is_empty() => name.clone(),
            Some(_) => return Err(bad("`name` must be a non-empty string".into())),
            None => path
                .file_stem()
                .map_or_else(|| "sweep".into(), |s| s.to_string_lossy().into_owned()),
        };
        // The name is the sweep's folder: the same rule as a scene's name.
        if let Some(problem) = folder_name_problem(&name, "out/sweeps/NAME") {
            return Err(bad(format!("`name` {problem}")));
        }
        let zip = match table.get("zip") {
            Some(toml::Value::Boolean(zip)) => *zip,
            Some(_) => return Err(bad("`zip` must be true or false".into())),
            None => false,
        };
        let set = match table.get("set") {
            Some(toml::Value::Table(set)) => in_file_order(text, "set", set)
                .into_iter()
                .map(|(key, value)| format!("{key}={value}"))
                .collect(),
            Some(_) => {
                return Err(bad(
                    "`set` must be a table of overrides, e.g. set = { \"time.frames\" = 60 }"
                        .into(),
                ));
            }
            None => Vec::new(),
        };
        let axes = match table.get("vary") {
            Some(toml::Value::Table(vary)) => in_file_order(text, "vary", vary)
                .into_iter()
                .map(|(key, value)| axis_from_toml(key, value, path))
                .collect::<Result<Vec<_>, _>>()?,
            Some(_) => return Err(bad("`vary` must be a table: [vary] KEY = [values]".into())),
            None => Vec::new(),
        };
        Ok(Self {
            scene,
            name,
            zip,
            set,
            axes,
        })
    }
}

/// The entries of the top-level table `name` in the order the file writes
/// them (`toml::Table` sorts its keys; the order of the varied keys is the
/// order of the runs).
fn in_file_order<'t>(
    text: &str,
    name: &str,
    table: &'t toml::Table,
) -> Vec<(&'t String, &'t toml::Value)> {
    let mut position = std::collections::HashMap::new();
    if let Ok(root) = toml::de::DeTable::parse(text)
        && let Some((_, value)) = root.get_ref().iter().find(|(k, _)| k.get_ref() == name)
        && let toml::de::DeValue::Table(inner) = value.get_ref()
    {
        for (key, _) in inner.iter() {
            position.insert(key.get_ref().to_string(), key.span().start);
        }
    }
    let mut entries: Vec<_> = table.iter().collect();
    entries.sort_by_key(|(key, _)| position.get(key.as_str()).copied().unwrap_or(usize::MAX));
    entries
}

/// A relative scene path names a file beside the sweep file when one is
/// there; otherwise the text is passed on as is (a built-in scene name, or
/// a path the scene loader will report).
fn scene_argument(scene: &str, sweep_file: &Path) -> String {
    let relative = Path::new(scene);
    if relative.is_relative() {
        let beside: PathBuf = sweep_file.parent().unwrap_or(Path::new("")).join(relative);
        if beside.is_file() {
            return beside.display().to_string();
        }
    }
    scene.to_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sweep_file_names_scene_sets_and_axes() {
        let path = Path::new("studies/stiffness-study.toml");
        let file = SweepFile::parse(
            r#"
            scene = "report-drop-2d"
            zip = true
            set = { "time.frames" = 60, "render.range" = [0.0, 0.5] }
            [vary]
            "time.substeps" = "linspace(1, 10, 2)"
            "material.young" = [100, 300]
            "#,
            path,
        )
        .unwrap();
        assert_eq!(file.scene, "report-drop-2d");
        assert_eq!(file.name, "stiffness-study");
        assert!(file.zip);
        assert_eq!(
            file.set,
            ["time.frames=60", "render.range=[0.0, 0.5]"],
            "the file's order"
        );
        let keys: Vec<&str> = file.axes.iter().map(|a| a.key.as_str()).collect();
        assert_eq!(
            keys,
            ["time.substeps", "material.young"],
            "the file's order"
        );
        assert_eq!(file.axes[0].values[1].toml, "10");
    }

    #[test]
    fn mistakes_are_errors_naming_the_file_and_key() {
        let path = Path::new("s.toml");
        for (text, needle) in [
            ("name = \"x\"", "`scene` is missing"),
            ("scene = 3", "`scene` must be a string"),
            ("scene = \"a\"\nzipp = true", "unknown key `zipp`"),
            ("scene = \"a\"\nzip = 1", "`zip`"),
            ("scene = \"a\"\nset = 1", "`set`"),
            ("scene = \"a\"\n[vary]\nx = []", "`vary.x`"),
            ("scene = \"a\"\nvary = 2", "`vary`"),
            ("scene = ", "not valid TOML"),
        ] {
            let err = SweepFile::parse(text, path).unwrap_err().to_string();
            assert!(err.starts_with("s.toml: "), "{err}");
            assert!(err.contains(needle), "{text}: {err}");
        }
    }
}
