//! Loading a scene: the file (or built-in text) parsed with the `--set`
//! overrides applied, then validated into a [`Scene`], the only way a
//! [`Scene`] is made; and its bodies meshed and checked as a whole
//! ([`SceneConfig::meshed_bodies`]), the only way a run gets them. Apart from the settings' types (`scene_config.rs`) so
//! that they do not import the validator that builds them.

use super::scene_document::SceneDocument;
use super::scene_validator::SceneValidator;
use super::{Scene, SceneConfig, SceneError, SceneOverride, SceneSource};
use crate::sim::Body;

impl Scene {
    /// Parses `source`, applies `overrides` and validates the result.
    pub fn load(source: &SceneSource, overrides: &[SceneOverride]) -> Result<Scene, SceneError> {
        Self::load_resolved(source, overrides).map(|(scene, _)| scene)
    }

    /// Like [`Scene::load`], also returning the resolved scene as TOML: every
    /// default filled in and every override applied, so that running the
    /// returned text reproduces this scene exactly.
    pub fn load_resolved(
        source: &SceneSource,
        overrides: &[SceneOverride],
    ) -> Result<(Scene, String), SceneError> {
        let document = SceneDocument::parse(source, overrides)?;
        let raw = document.deserialize()?;
        let (scene, resolved) = SceneValidator::new(&document).scene(&raw)?;
        let text = toml::to_string(&resolved).expect("a resolved scene serialises");
        Ok((scene, text))
    }

    /// An error at `key` of the scene `source` with `overrides`, located
    /// (file line, or flag) exactly as the validator reports one: for
    /// problems found after validation, e.g. against this machine's memory
    /// or graphics adapter, or when the simulation is built.
    pub fn key_error(
        source: &SceneSource,
        overrides: &[SceneOverride],
        key: &str,
        reason: impl Into<String>,
    ) -> SceneError {
        match SceneDocument::parse(source, overrides) {
            Ok(document) => document.error(key, reason),
            Err(error) => error,
        }
    }
}

impl<const D: usize> SceneConfig<D> {
    /// The bodies of this scene (loaded from `source` with `overrides`)
    /// with their meshes built, as [`Simulation::with_bodies`] takes them:
    /// the validator's second stage, refusing at its key a body whose
    /// masses are lost beside its stiffness, pinned regions that hold every
    /// vertex together, and bodies or obstacles that start in contact.
    /// Call it after checking that the meshes fit in memory.
    ///
    /// [`Simulation::with_bodies`]: crate::sim::Simulation::with_bodies
    pub fn meshed_bodies(
        &self,
        source: &SceneSource,
        overrides: &[SceneOverride],
    ) -> Result<Vec<Body<D>>, SceneError> {
        let document = SceneDocument::parse(source, overrides)?;
        SceneValidator::new(&document).meshed_bodies(self)
    }
}
