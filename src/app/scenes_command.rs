//! `elasto scenes` and `elasto scenes show NAME`.

use super::AppError;
use super::cli::{ScenesAction, ScenesArgs};
use crate::scene::{BUILTIN_SCENES, SceneError, builtin_scene};

/// Runs `elasto scenes`, returning the text it prints.
pub fn scenes(args: &ScenesArgs) -> Result<String, AppError> {
    match &args.action {
        None => {
            let width = BUILTIN_SCENES
                .iter()
                .map(|s| s.name.len())
                .max()
                .unwrap_or(0);
            Ok(BUILTIN_SCENES
                .iter()
                .map(|s| format!("{:width$}  {}\n", s.name, s.description))
                .collect())
        }
        Some(ScenesAction::Show { name }) => match builtin_scene(name) {
            Some(scene) => Ok(scene.toml.to_owned()),
            None => Err(AppError::Scene(SceneError::NotFound {
                name: name.clone(),
                available: BUILTIN_SCENES
                    .iter()
                    .map(|s| s.name)
                    .collect::<Vec<_>>()
                    .join(", "),
            })),
        },
    }
}
