//! Scene files: TOML description of a simulation, validated into typed settings.
//!
//! A scene is read once, before any work starts: the TOML text (a file or a
//! built-in scene) is parsed, command-line overrides (`--set key.path=value`,
//! `--frames`, `--resolution`) are applied to the parsed table, serde turns it
//! into raw structs that deny unknown keys, and the validator turns those into
//! a [`Scene`] of typed settings with every default filled in (the settings
//! in `scene_config.rs`, the validator in `scene_validator.rs`; the render
//! settings are the renderer's own [`RenderSettings`](crate::render::RenderSettings)). Every error names the source file
//! (or the flag), the dotted key and, for values in the file, the line:
//!
//! ```text
//! scenes/mine.toml:12:9: `material.poisson`: must lie in (-1, 0.5), got 0.5
//! --set time.frames=0 (in built-in scene `report-drop-2d`): `time.frames`: must be at least 1, got 0
//! ```
//!
//! Effects are listed explicitly: a scene without `[effects.gravity]` has no
//! gravity term at all, and likewise for the ground and pinned vertices.

mod folder_name;
mod mesh_config;
mod raw_scene;
mod scene_config;
mod scene_document;
mod scene_error;
mod scene_loading;
mod scene_override;
mod scene_source;
mod scene_validator;

pub use folder_name::folder_name_problem;
pub use scene_config::{
    BodyConfig, BoxMesh, DEFAULT_BACKGROUND, DEFAULT_BARRIER_WIDTH, DEFAULT_COLOUR,
    DEFAULT_DENSITY, DEFAULT_FOV, DEFAULT_FPS, DEFAULT_FRAMES, DEFAULT_GRADIENT_DESCENT_ITERATIONS,
    DEFAULT_GRADIENT_DESCENT_STEP, DEFAULT_NEWTON_ITERATIONS, DEFAULT_RELATIVE_TOLERANCE,
    DEFAULT_RESOLUTION, DEFAULT_SUBSTEPS, FieldChoice, FileMesh, MAX_CELLS, MAX_FRAMES,
    MAX_IMAGE_BYTES, MAX_NAME_BYTES, MAX_RESOLUTION, MAX_STEPS, MAX_SUBSTEPS, MaterialConfig,
    MeshConfig, RecordedFile, Scene, SceneConfig, TimeConfig, image_bytes,
};
pub use scene_error::{Diagnostic, Origin, SceneError, approx, num};
pub use scene_override::{KeyPart, SceneOverride};
pub use scene_source::{BUILTIN_SCENES, BuiltinScene, DEFAULT_SCENE, SceneSource, builtin_scene};
