//! The validator: turns the raw scene document into the typed settings of
//! [`Scene`], reporting every problem at its file position (or flag) and
//! dotted key.
//!
//! It is the only code that reads [`RawScene`]; it returns the typed scene
//! together with the resolved raw form (every default written out), which is
//! what `scene.toml` of a run holds.
//!
//! Every check a scene value can fail is made here, once, at the key it
//! concerns; the simulation trusts the result. It works in two stages: the
//! settings (`Scene::load`: every section, mesh files read once), and,
//! when a run is about to start and its memory was checked, the bodies'
//! meshes built and checked as a whole (`meshed_bodies.rs`:
//! [`SceneConfig::meshed_bodies`]). Only what needs the built simulation
//! (its starting energy) or the machine is checked after, by the commands'
//! preflight.

use super::SceneError;
use super::folder_name::folder_name_problem;
use super::raw_scene::RawScene;
use super::scene_config::{BodyConfig, MeshConfig, Scene, SceneConfig};
use super::scene_document::SceneDocument;
use super::scene_error::num;
use crate::math::Vector;

/// Turns a [`RawScene`] into a [`Scene`] plus the resolved raw form,
/// reporting each problem at its key.
pub(crate) struct SceneValidator<'d, 'a> {
    doc: &'d SceneDocument<'a>,
    /// Put before every key in messages: `bodies[1].` while validating a body.
    prefix: String,
}

type VResult<T> = std::result::Result<T, SceneError>;

mod bodies;
mod effects;
mod mesh;
mod meshed_bodies;
mod obstacles;
mod render;
mod time_solver;

/// The widest ground barrier `effects.ground.a`, in multiples of the
/// scene's size (the bodies' bounding box diagonal plus the gap they start
/// at above the ground).
pub const MAX_BARRIER_WIDTH_TO_SCENE: f64 = 100.0;

/// The most solves per step `solver.friction_iterations` may ask for.
const MAX_FRICTION_ITERATIONS: usize = 100;
/// The most halvings of a step `solver.max_subdivisions` may ask for
/// (`dt / 2^10`: a thousand times more steps where every level fails).
const MAX_SUBDIVISIONS: usize = 10;

impl<'d, 'a> SceneValidator<'d, 'a> {
    /// A validator whose messages point into `doc`.
    pub fn new(doc: &'d SceneDocument<'a>) -> Self {
        Self {
            doc,
            prefix: String::new(),
        }
    }

    /// A validator for the keys under `prefix` (e.g. `bodies[1].`).
    fn under(&self, prefix: String) -> Self {
        Self {
            doc: self.doc,
            prefix,
        }
    }

    /// The typed scene and its resolved raw form.
    pub fn scene(&self, raw: &RawScene) -> VResult<(Scene, RawScene)> {
        match raw.dimension {
            2 => self.scene_d::<2>(raw).map(|(c, r)| (Scene::Two(c), r)),
            3 => self.scene_d::<3>(raw).map(|(c, r)| (Scene::Three(c), r)),
            d => Err(self.err("dimension", format!("must be 2 or 3, got {d}"))),
        }
    }

    /// An error at `key` (after the current prefix), pointing into the file.
    fn err(&self, key: &str, reason: impl Into<String>) -> SceneError {
        self.doc.error(&format!("{}{key}", self.prefix), reason)
    }

    /// The scene of dimension `D`: every section in the order they depend on
    /// each other (bodies, time, solver, effects, obstacles, render).
    fn scene_d<const D: usize>(&self, raw: &RawScene) -> VResult<(SceneConfig<D>, RawScene)> {
        let name = self.name(raw.name.as_deref())?;
        let (bodies, raw_mesh, raw_material, raw_bodies) = self.bodies::<D>(raw)?;
        let (time, raw_time) = self.time(&raw.time)?;
        let (solver, raw_solver) = self.solver(&raw.solver, bounding_box_diagonal(&bodies))?;
        let (mut effects, raw_effects) = self.effects::<D>(&raw.effects, &bodies)?;
        let (obstacles, raw_obstacles) = self.obstacles::<D>(raw.obstacles.as_deref(), &effects)?;
        effects.obstacles = obstacles;
        let (solver, raw_solver) =
            self.friction_solver(solver, raw_solver, &raw.solver, &effects, &bodies)?;
        let ground_height = effects.ground.map(|g| g.height);
        let (field, render, raw_render) = self.render::<D>(&raw.render, ground_height)?;
        let config = SceneConfig {
            name: name.clone(),
            bodies,
            time,
            solver,
            effects,
            field,
            render,
        };
        let resolved = RawScene {
            name: Some(name),
            dimension: D as i64,
            mesh: raw_mesh,
            material: raw_material,
            time: raw_time,
            solver: raw_solver,
            effects: raw_effects,
            render: raw_render,
            bodies: raw_bodies,
            obstacles: raw_obstacles,
        };
        Ok((config, resolved))
    }

    /// The scene's name: it names the folder `out/NAME`, so it must be one
    /// plain folder name, never a path.
    fn name(&self, given: Option<&str>) -> VResult<String> {
        let name = given.unwrap_or(&self.doc.source().default_name);
        let problem = folder_name_problem(name, "out/NAME");
        match (problem, given) {
            (None, _) => Ok(name.to_owned()),
            (Some(reason), Some(_)) => Err(self.err("name", reason)),
            (Some(reason), None) => Err(self.err(
                "name",
                format!("the default name (the file's stem) {reason}; set `name` in the scene"),
            )),
        }
    }

    /// A vector of exactly `D` finite components.
    fn vector<const D: usize>(&self, key: &str, v: &[f64]) -> VResult<Vector<D>> {
        if v.len() != D {
            return Err(self.err(
                key,
                format!("needs {D} components (dimension = {D}), got {}", v.len()),
            ));
        }
        if let Some(bad) = v.iter().find(|x| !x.is_finite()) {
            return Err(self.err(key, format!("components must be finite, got {}", num(*bad))));
        }
        Ok(Vector::<D>::from_fn(|i, _| v[i]))
    }

    /// `x`, which must be positive and finite.
    fn positive(&self, key: &str, x: f64) -> VResult<f64> {
        if x.is_finite() && x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(key, format!("must be a finite number > 0, got {}", num(x))))
        }
    }

    /// A whole number from 1 to `max`.
    fn count(&self, key: &str, n: i64, max: usize) -> VResult<usize> {
        if n < 1 {
            return Err(self.err(key, format!("must be at least 1, got {n}")));
        }
        match usize::try_from(n) {
            Ok(n) if n <= max => Ok(n),
            _ => Err(self.err(key, format!("must be at most {max}, got {n}"))),
        }
    }

    /// Rendering works in 32-bit floats: `x` must stay finite (and, when
    /// `positive`, above zero) as one.
    fn single_precision(&self, key: &str, values: &[f64], positive: bool) -> VResult<()> {
        for &x in values {
            let single = x as f32;
            let ok = single.is_finite() && (!positive || single >= f32::MIN_POSITIVE);
            if !ok {
                let range = if positive {
                    "from 1.2e-38 to 3.4e38"
                } else {
                    "up to 3.4e38"
                };
                return Err(self.err(
                    key,
                    format!(
                        "{} is out of the renderer's range: images are drawn in 32-bit floats, \
                         which hold magnitudes {range}",
                        num(x)
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// The diagonal of the box around every body's rest mesh (boxes from their
/// offset and size, files from their vertices): the length contact's
/// default distance is a fraction of.
fn bounding_box_diagonal<const D: usize>(bodies: &[BodyConfig<D>]) -> f64 {
    let mut low = Vector::<D>::repeat(f64::INFINITY);
    let mut high = Vector::<D>::repeat(f64::NEG_INFINITY);
    for body in bodies {
        match &body.mesh {
            MeshConfig::Box(m) => {
                low = low.inf(&m.offset);
                high = high.sup(&(m.offset + m.size));
            }
            MeshConfig::File(f) => {
                for x in f.mesh.rest_positions() {
                    low = low.inf(x);
                    high = high.sup(x);
                }
            }
        }
    }
    (high - low).norm()
}
