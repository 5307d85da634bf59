//! Where a scene's text comes from: a file or a built-in scene embedded in the binary.

use super::SceneError;
use crate::input_file::{MAX_SETTINGS_FILE_BYTES, read_regular_text_file};
use std::path::{Path, PathBuf};

/// A built-in scene: its name, a one-line description and its TOML text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BuiltinScene {
    /// Name, e.g. `report-drop-2d`.
    pub name: &'static str,
    /// One-line description.
    pub description: &'static str,
    /// The TOML text (the same as `scenes/NAME.toml`).
    pub toml: &'static str,
}

/// The built-in scenes, embedded from `scenes/*.toml`. The first is the default.
pub const BUILTIN_SCENES: &[BuiltinScene] = &[
    BuiltinScene {
        name: "report-drop-2d",
        description: "2D box of 5x5 cells dropped from 10 units onto the ground (the report's example)",
        toml: include_str!("../../scenes/report-drop-2d.toml"),
    },
    BuiltinScene {
        name: "drop-3d",
        description: "3D Neo-Hookean cube of 4x4x4 cells dropped onto the ground",
        toml: include_str!("../../scenes/drop-3d.toml"),
    },
    BuiltinScene {
        name: "hanging-bar-2d",
        description: "soft 2D bar pinned at its top end, hanging down, bouncing and swinging",
        toml: include_str!("../../scenes/hanging-bar-2d.toml"),
    },
    BuiltinScene {
        name: "hanging-bar-3d",
        description: "soft 3D bar pinned at its top end, hanging down, bouncing and swinging",
        toml: include_str!("../../scenes/hanging-bar-3d.toml"),
    },
    BuiltinScene {
        name: "bunny-drop",
        description: "the shipped bunny-like tetrahedral mesh (scenes/meshes/bunny.msh) dropped onto the ground",
        toml: include_str!("../../scenes/bunny-drop.toml"),
    },
    BuiltinScene {
        name: "two-bodies",
        description: "a stiff ring dropped onto a soft ball resting on the ground (shipped meshes): contact between bodies",
        toml: include_str!("../../scenes/two-bodies.toml"),
    },
];

/// The scene used when none is named.
pub const DEFAULT_SCENE: &str = "report-drop-2d";

/// Looks up a built-in scene by name.
pub fn builtin_scene(name: &str) -> Option<&'static BuiltinScene> {
    BUILTIN_SCENES.iter().find(|s| s.name == name)
}

/// The text of a scene and what to call it in messages.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SceneSource {
    /// How messages name the source: the file path, or `built-in scene NAME`.
    pub label: String,
    /// The name the scene gets when it sets none: the file stem or the built-in name.
    pub default_name: String,
    /// The file, when the scene came from one.
    pub path: Option<PathBuf>,
    /// The TOML text.
    pub text: String,
}

impl SceneSource {
    /// Reads a scene file.
    pub fn from_file(path: &Path) -> Result<Self, SceneError> {
        let text = read_regular_text_file(path, MAX_SETTINGS_FILE_BYTES).map_err(|source| {
            SceneError::Read {
                path: path.to_owned(),
                source,
            }
        })?;
        let default_name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "scene".into());
        Ok(Self {
            label: path.display().to_string(),
            default_name,
            path: Some(path.to_owned()),
            text,
        })
    }

    /// A built-in scene.
    pub fn from_builtin(scene: &BuiltinScene) -> Self {
        Self {
            label: format!("built-in scene `{}`", scene.name),
            default_name: scene.name.to_owned(),
            path: None,
            text: scene.toml.to_owned(),
        }
    }

    /// Resolves a command-line scene argument: an existing file, else a
    /// built-in name; `None` is the default scene.
    pub fn resolve(argument: Option<&str>) -> Result<Self, SceneError> {
        let Some(argument) = argument else {
            return Ok(Self::from_builtin(
                builtin_scene(DEFAULT_SCENE).expect("the default scene is built in"),
            ));
        };
        let path = Path::new(argument);
        if path.is_file() {
            return Self::from_file(path);
        }
        if let Some(scene) = builtin_scene(argument) {
            return Ok(Self::from_builtin(scene));
        }
        if path.exists() {
            // A directory or other non-file: let the read report why.
            return Self::from_file(path);
        }
        Err(SceneError::NotFound {
            name: argument.to_owned(),
            available: BUILTIN_SCENES
                .iter()
                .map(|s| s.name)
                .collect::<Vec<_>>()
                .join(", "),
        })
    }
}
