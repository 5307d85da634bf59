//! The validator: turns the raw scene document into the typed settings of
//! [`Scene`], reporting every problem at its file position (or flag) and
//! dotted key.
//!
//! It is the only code that reads [`RawScene`]; it returns the typed scene
//! together with the resolved raw form (every default written out), which is
//! what `scene.toml` of a run holds.

use super::SceneError;
use super::folder_name::folder_name_problem;
use super::raw_scene::{
    FieldName, Generator, Method, ProjectionName, RawBody, RawCamera, RawContact, RawEffects,
    RawGround, RawMaterial, RawMesh, RawPinned, RawPinnedList, RawRender, RawRotate, RawScene,
    RawSolver, RawTime,
};
use super::scene_config::{
    BodyConfig, BoxMesh, DEFAULT_BACKGROUND, DEFAULT_BARRIER_WIDTH, DEFAULT_COLOUR,
    DEFAULT_DENSITY, DEFAULT_FOV, DEFAULT_FPS, DEFAULT_FRAMES, DEFAULT_GRADIENT_DESCENT_ITERATIONS,
    DEFAULT_GRADIENT_DESCENT_STEP, DEFAULT_NEWTON_ITERATIONS, DEFAULT_RELATIVE_TOLERANCE,
    DEFAULT_RESOLUTION, DEFAULT_SUBSTEPS, FieldChoice, FileMesh, MAX_CELLS, MAX_FRAMES,
    MAX_IMAGE_BYTES, MAX_RESOLUTION, MAX_STEPS, MAX_SUBSTEPS, MaterialConfig, MeshConfig,
    RecordedFile, Scene, SceneConfig, TimeConfig, image_bytes,
};
use super::scene_document::SceneDocument;
use super::scene_error::{approx, num, nums};
use crate::energy::ElementField;
use crate::material::{LameParameters, YoungPoisson};
use crate::math::{UP_AXIS, Vector, Vector3};
use crate::mesh_io::{ImportOptions, MeshFileFingerprint, load_mesh, mesh_file_fingerprint};
use crate::render::{Camera, Colouring, RenderSettings};
use crate::sim::{Contact, DEFAULT_FRICTION_VELOCITY, Effects, Ground, PinMotion, PinRegion};
use crate::solver::{Projection, SolverMethod, SolverSettings};
use std::path::{Path, PathBuf};

/// Turns a [`RawScene`] into a [`Scene`] plus the resolved raw form,
/// reporting each problem at its key.
pub(crate) struct SceneValidator<'d, 'a> {
    doc: &'d SceneDocument<'a>,
    /// Put before every key in messages: `bodies[1].` while validating a body.
    prefix: String,
}

type VResult<T> = std::result::Result<T, SceneError>;

mod obstacles;

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

    fn err(&self, key: &str, reason: impl Into<String>) -> SceneError {
        self.doc.error(&format!("{}{key}", self.prefix), reason)
    }

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

    /// The bodies: `[mesh]` and `[material]` (one body), or `[[bodies]]`.
    #[allow(clippy::type_complexity)]
    fn bodies<const D: usize>(
        &self,
        raw: &RawScene,
    ) -> VResult<(
        Vec<BodyConfig<D>>,
        Option<RawMesh>,
        Option<RawMaterial>,
        Option<Vec<RawBody>>,
    )> {
        match (&raw.mesh, &raw.material, &raw.bodies) {
            (Some(mesh), Some(material), None) => {
                let (body, raw_mesh, raw_material) = self.body::<D>(mesh, material)?;
                Ok((vec![body], Some(raw_mesh), Some(raw_material), None))
            }
            (None, None, Some(list)) => {
                if list.is_empty() {
                    return Err(self.err("bodies", "needs at least one [[bodies]] entry"));
                }
                let mut bodies = Vec::with_capacity(list.len());
                let mut resolved = Vec::with_capacity(list.len());
                for (i, entry) in list.iter().enumerate() {
                    let prefix = format!("bodies[{i}].");
                    let v = self.under(prefix.clone());
                    let (mut body, mesh, material) = v.body::<D>(&entry.mesh, &entry.material)?;
                    if let Some(p) = &entry.pinned {
                        let region = v.pin_region::<D>("pinned", p)?;
                        if !body.mesh.vertices_in(&region).0 {
                            return Err(v.err(
                                "pinned",
                                "the region from `min` to `max` contains no vertex of this body \
                                 at rest; widen it to catch the vertices to hold",
                            ));
                        }
                        body.pinned = Some(region);
                    }
                    body.key_prefix = prefix;
                    bodies.push(body);
                    resolved.push(RawBody {
                        mesh,
                        material,
                        pinned: entry.pinned.clone(),
                    });
                }
                Ok((bodies, None, None, Some(resolved)))
            }
            (_, _, Some(_)) => {
                let key = if raw.mesh.is_some() {
                    "mesh"
                } else {
                    "material"
                };
                Err(self.err(
                    key,
                    "cannot be given with [[bodies]]: a scene is one body ([mesh] and \
                     [material]) or several ([[bodies]], each with its own mesh and material), \
                     not both",
                ))
            }
            (None, _, None) => Err(self.err(
                "mesh",
                "is required: give [mesh] and [material] for one body, or [[bodies]]",
            )),
            (Some(_), None, None) => Err(self.err(
                "material",
                "is required: give [mesh] and [material] for one body, or [[bodies]]",
            )),
        }
    }

    /// One body from its mesh and material tables (keys under `self.prefix`).
    fn body<const D: usize>(
        &self,
        raw_mesh: &RawMesh,
        raw_material: &RawMaterial,
    ) -> VResult<(BodyConfig<D>, RawMesh, RawMaterial)> {
        let (mesh, initial_velocity, raw_mesh) = self.mesh::<D>(raw_mesh)?;
        let (material, raw_material) = self.material(raw_material)?;
        self.mass(&mesh, material.density)?;
        Ok((
            BodyConfig {
                mesh,
                initial_velocity,
                material,
                pinned: None,
                key_prefix: String::new(),
            },
            raw_mesh,
            raw_material,
        ))
    }

    /// A pinned box `min`..`max` at `key` (`effects.pinned[i]`, `pinned`)
    /// and its motion (`velocity`, `angular_velocity`, `axis`, `center`,
    /// `until`, `release`).
    fn pin_region<const D: usize>(&self, key: &str, p: &RawPinned) -> VResult<PinRegion<D>> {
        let min = self.vector::<D>(&format!("{key}.min"), &p.min)?;
        let max = self.vector::<D>(&format!("{key}.max"), &p.max)?;
        if let Some(axis) = (0..D).find(|&a| min[a] > max[a]) {
            return Err(self.err(
                &format!("{key}.max"),
                format!(
                    "is below {key}.min along axis {axis} ({} < {})",
                    num(max[axis]),
                    num(min[axis])
                ),
            ));
        }
        let region = PinRegion::new(min, max);
        let motion = self.motion::<D>(&format!("{key}."), p, region.box_center())?;
        Ok(region.moving(motion))
    }

    /// A rigid path from the motion keys of `p` under `key` (`velocity`,
    /// `angular_velocity`, `axis`, `center`, defaulting to `center`,
    /// `until`, `release`); `key` ends with a dot or is empty.
    fn motion<const D: usize>(
        &self,
        key: &str,
        p: &RawPinned,
        center: Vector<D>,
    ) -> VResult<PinMotion<D>> {
        // The full key in messages (with `bodies[1].` or `obstacles[0].`).
        let at = format!("{}{key}", self.prefix);
        let mut motion = PinMotion::<D> {
            center,
            ..PinMotion::default()
        };
        if let Some(v) = &p.velocity {
            motion.velocity = self.vector::<D>(&format!("{key}velocity"), v)?;
        }
        if let Some(w) = p.angular_velocity {
            if !w.is_finite() {
                return Err(self.err(
                    &format!("{key}angular_velocity"),
                    format!("must be finite (rad/s), got {}", num(w)),
                ));
            }
            motion.angular_velocity = w;
        }
        let rotates = p.angular_velocity.is_some();
        for (name, given) in [("axis", p.axis.is_some()), ("center", p.center.is_some())] {
            if given && !rotates {
                return Err(self.err(
                    &format!("{key}{name}"),
                    format!("has no effect without {at}angular_velocity; give the angular velocity (rad/s) or remove it"),
                ));
            }
        }
        match (&p.axis, D) {
            (Some(_), 2) => {
                return Err(self.err(
                    &format!("{key}axis"),
                    "is a 3D key: in 2D a motion rotates in the plane \
                     (counter-clockwise for angular_velocity > 0); remove it",
                ));
            }
            (Some(a), _) => {
                let axis = self.vector::<3>(&format!("{key}axis"), a)?;
                let norm = axis.norm();
                if !(norm > 0.0 && norm.is_finite()) {
                    return Err(self.err(
                        &format!("{key}axis"),
                        format!("must be a non-zero direction, got {}", nums(a)),
                    ));
                }
                motion.axis = axis / norm;
            }
            (None, 3) if rotates => {
                return Err(self.err(
                    &format!("{key}axis"),
                    format!("is required in 3D with {at}angular_velocity: the direction to rotate about, e.g. [1, 0, 0]"),
                ));
            }
            (None, _) => motion.axis = Vector3::z(),
        }
        if let Some(c) = &p.center {
            motion.center = self.vector::<D>(&format!("{key}center"), c)?;
        }
        if let Some(until) = p.until {
            if !(until >= 0.0 && until.is_finite()) {
                return Err(self.err(
                    &format!("{key}until"),
                    format!("must be a finite time >= 0 (s), got {}", num(until)),
                ));
            }
            if p.velocity.is_none() && !rotates {
                return Err(self.err(
                    &format!("{key}until"),
                    format!("has no effect on a path that does not move; give {at}velocity or {at}angular_velocity, or remove it"),
                ));
            }
            motion.until = Some(until);
        }
        if let Some(release) = p.release {
            if !(release > 0.0 && release.is_finite()) {
                return Err(self.err(
                    &format!("{key}release"),
                    format!("must be a finite time > 0 (s), got {}", num(release)),
                ));
            }
            motion.release = Some(release);
        }
        Ok(motion)
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

    fn mesh<const D: usize>(&self, raw: &RawMesh) -> VResult<(MeshConfig<D>, Vector<D>, RawMesh)> {
        let generator = raw.generator.unwrap_or_default();
        let (used, other, hint) = match generator {
            Generator::Box => (
                "box",
                [
                    ("path", raw.path.is_some()),
                    ("scale", raw.scale.is_some()),
                    ("rotate", raw.rotate.is_some()),
                    ("translate", raw.translate.is_some()),
                    ("orient", raw.orient.is_some()),
                    ("merge_tolerance", raw.merge_tolerance.is_some()),
                    ("file_size", raw.file_size.is_some()),
                    ("file_checksum", raw.file_checksum.is_some()),
                ]
                .to_vec(),
                "file",
            ),
            Generator::File => (
                "file",
                [
                    ("size", raw.size.is_some()),
                    ("cells", raw.cells.is_some()),
                    ("offset", raw.offset.is_some()),
                ]
                .to_vec(),
                "box",
            ),
        };
        if let Some((key, _)) = other.iter().find(|(_, present)| *present) {
            return Err(self.err(
                &format!("mesh.{key}"),
                format!(
                    "is only used with generator = \"{hint}\" (this mesh is generator = \"{used}\")"
                ),
            ));
        }
        match generator {
            Generator::Box => self
                .box_mesh::<D>(raw)
                .map(|(b, v, r)| (MeshConfig::Box(b), v, r)),
            Generator::File => self
                .file_mesh::<D>(raw)
                .map(|(f, v, r)| (MeshConfig::File(Box::new(f)), v, r)),
        }
    }

    /// Where a relative mesh path points: beside the scene file, or under
    /// `scenes/` of this source tree for a built-in scene.
    fn mesh_folder(&self) -> PathBuf {
        match &self.doc.source().path {
            Some(file) => file.parent().map(Path::to_owned).unwrap_or_default(),
            None => Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes"),
        }
    }

    fn file_mesh<const D: usize>(
        &self,
        raw: &RawMesh,
    ) -> VResult<(FileMesh<D>, Vector<D>, RawMesh)> {
        let given = raw
            .path
            .as_deref()
            .ok_or_else(|| self.err("mesh.path", "is required with generator = \"file\""))?;
        if given.trim().is_empty() {
            return Err(self.err("mesh.path", "must not be empty"));
        }
        let path = self.mesh_folder().join(given);
        let path = std::path::absolute(&path).unwrap_or(path);
        let (scale, rotate, translate) = self.placement::<D>(raw)?;
        let merge_tolerance = raw.merge_tolerance.unwrap_or(0.0);
        if !(merge_tolerance.is_finite() && merge_tolerance >= 0.0) {
            return Err(self.err(
                "mesh.merge_tolerance",
                format!("must be a finite number >= 0, got {}", num(merge_tolerance)),
            ));
        }
        let orient = raw.orient.unwrap_or(true);
        let velocity = match &raw.velocity {
            Some(v) => self.vector::<D>("mesh.velocity", v)?,
            None => Vector::<D>::zeros(),
        };
        let options = ImportOptions {
            orient,
            merge_tolerance,
            scale,
            rotate,
            translate,
        };
        let recorded = RecordedFile {
            size: match raw.file_size {
                Some(size) => Some(u64::try_from(size).map_err(|_| {
                    self.err(
                        "mesh.file_size",
                        format!("must be a whole number of bytes >= 0, got {size}"),
                    )
                })?),
                None => None,
            },
            checksum: match &raw.file_checksum {
                Some(sum) if MeshFileFingerprint::is_checksum(sum) => Some(sum.clone()),
                Some(sum) => {
                    return Err(self.err(
                        "mesh.file_checksum",
                        format!(
                            "must be `xxh3:` and 16 hexadecimal digits, as a run's scene.toml \
                             records it, got {sum:?}"
                        ),
                    ));
                }
                None => None,
            },
        };
        let (mesh, report) = load_mesh::<D>(&path, &options)
            .map_err(|e| self.err("mesh.path", format!("cannot be imported: {e}")))?;
        let fingerprint = mesh_file_fingerprint(&path)
            .map_err(|e| self.err("mesh.path", format!("cannot be read: {e}")))?;
        let coordinates: Vec<f64> = mesh
            .rest_positions()
            .iter()
            .flat_map(|x| x.iter().copied().collect::<Vec<_>>())
            .collect();
        self.single_precision("mesh.translate", &coordinates, false)?;
        let resolved = RawMesh {
            generator: Some(Generator::File),
            size: None,
            cells: None,
            offset: None,
            velocity: Some(velocity.iter().copied().collect()),
            path: Some(path.display().to_string()),
            scale: Some(scale),
            rotate: Some(if D == 2 {
                RawRotate::Angle(rotate[2])
            } else {
                RawRotate::Angles(rotate.to_vec())
            }),
            translate: Some(translate.iter().copied().collect()),
            orient: Some(orient),
            merge_tolerance: Some(merge_tolerance),
            file_size: i64::try_from(fingerprint.size).ok(),
            file_checksum: Some(fingerprint.checksum.clone()),
        };
        Ok((
            FileMesh {
                path,
                options,
                mesh: std::sync::Arc::new(mesh),
                report,
                fingerprint,
                recorded,
            },
            velocity,
            resolved,
        ))
    }

    /// `mesh.scale`, `mesh.rotate` (one angle in 2D, three in 3D, degrees)
    /// and `mesh.translate` (defaults 1, none, none).
    fn placement<const D: usize>(&self, raw: &RawMesh) -> VResult<(f64, [f64; 3], Vector<D>)> {
        let scale = self.positive("mesh.scale", raw.scale.unwrap_or(1.0))?;
        let rotate = match (&raw.rotate, D) {
            (None, _) => [0.0; 3],
            (Some(RawRotate::Angle(a)), 2) if a.is_finite() => [0.0, 0.0, *a],
            (Some(RawRotate::Angles(v)), 3) if v.len() == 3 && v.iter().all(|a| a.is_finite()) => {
                [v[0], v[1], v[2]]
            }
            (Some(_), 2) => {
                return Err(self.err(
                    "mesh.rotate",
                    "is one finite angle in degrees in 2D (about the axis out of the plane)",
                ));
            }
            (Some(_), _) => {
                return Err(self.err(
                    "mesh.rotate",
                    "is three finite angles in degrees in 3D (about x, then y, then z)",
                ));
            }
        };
        let translate = match &raw.translate {
            Some(v) => self.vector::<D>("mesh.translate", v)?,
            None => Vector::<D>::zeros(),
        };
        Ok((scale, rotate, translate))
    }

    fn box_mesh<const D: usize>(&self, raw: &RawMesh) -> VResult<(BoxMesh<D>, Vector<D>, RawMesh)> {
        let required = |key: &str| {
            self.err(
                key,
                "is required with generator = \"box\" (give `size` and `cells`, or use \
                 generator = \"file\" with `path`)",
            )
        };
        let raw_size = raw.size.as_ref().ok_or_else(|| required("mesh.size"))?;
        let raw_cells = raw.cells.as_ref().ok_or_else(|| required("mesh.cells"))?;
        let size = self.vector::<D>("mesh.size", raw_size)?;
        if let Some(bad) = size.iter().find(|s| **s <= 0.0) {
            return Err(self.err(
                "mesh.size",
                format!("every extent must be > 0, got {}", num(*bad)),
            ));
        }
        if raw_cells.len() != D {
            return Err(self.err(
                "mesh.cells",
                format!(
                    "needs {D} components (dimension = {D}), got {}",
                    raw_cells.len()
                ),
            ));
        }
        let mut cells = [0usize; D];
        for (c, &n) in cells.iter_mut().zip(raw_cells) {
            *c = self.count("mesh.cells", n, MAX_CELLS)?;
        }
        let total = cells.iter().try_fold(1usize, |acc, &c| acc.checked_mul(c));
        if total.is_none_or(|n| n > MAX_CELLS) {
            return Err(self.err(
                "mesh.cells",
                format!(
                    "{:?} makes {} cells, more than the {MAX_CELLS} allowed",
                    raw_cells,
                    cells.iter().map(|&c| c as f64).product::<f64>()
                ),
            ));
        }
        let offset = match &raw.offset {
            Some(v) => self.vector::<D>("mesh.offset", v)?,
            None => Vector::<D>::zeros(),
        };
        self.box_cells::<D>(&BoxMesh {
            size,
            cells,
            offset,
        })?;
        let velocity = match &raw.velocity {
            Some(v) => self.vector::<D>("mesh.velocity", v)?,
            None => Vector::<D>::zeros(),
        };
        let resolved = RawMesh {
            generator: Some(Generator::Box),
            size: Some(size.iter().copied().collect()),
            cells: Some(raw_cells.clone()),
            offset: Some(offset.iter().copied().collect()),
            velocity: Some(velocity.iter().copied().collect()),
            ..raw.clone()
        };
        Ok((
            BoxMesh {
                size,
                cells,
                offset,
            },
            velocity,
            resolved,
        ))
    }

    /// The box generator must be able to place every cell: the corners fit
    /// the renderer's 32-bit floats, each cell spans a resolvable step of its
    /// coordinates, and its volume is a normal double.
    fn box_cells<const D: usize>(&self, mesh: &BoxMesh<D>) -> VResult<()> {
        let upper = mesh.offset + mesh.size;
        for axis in 0..D {
            if !upper[axis].is_finite() {
                return Err(self.err(
                    "mesh.size",
                    format!(
                        "offset + size along axis {axis} overflows: {} + {}",
                        num(mesh.offset[axis]),
                        num(mesh.size[axis])
                    ),
                ));
            }
        }
        self.single_precision("mesh.offset", mesh.offset.as_slice(), false)?;
        self.single_precision("mesh.size", upper.as_slice(), false)?;
        let cell: Vec<f64> = (0..D)
            .map(|a| mesh.size[a] / mesh.cells[a] as f64)
            .collect();
        for axis in 0..D {
            let magnitude = mesh.offset[axis].abs().max(upper[axis].abs());
            if !(cell[axis] >= 1e-9 * magnitude) {
                return Err(self.err(
                    "mesh.size",
                    format!(
                        "cells of {} along axis {axis} are too small to place at {} \
                         (mesh.offset): a cell must span at least 1e-9 of its coordinates \
                         in double precision",
                        num(cell[axis]),
                        num(mesh.offset[axis])
                    ),
                ));
            }
        }
        let volume: f64 = cell.iter().product();
        let diagonal: f64 = cell.iter().map(|h| h * h).sum();
        if !(volume >= f64::MIN_POSITIVE && volume.is_finite() && diagonal.is_finite()) {
            let which = if volume.is_finite() && volume < 1.0 {
                "small: their volume underflows"
            } else {
                "large: their volume overflows"
            };
            return Err(self.err(
                "mesh.size",
                format!(
                    "cells of {} are too {which} double precision; choose other length units",
                    nums(&cell)
                ),
            ));
        }
        Ok(())
    }

    /// Masses are density times element volumes: they must be normal doubles.
    fn mass<const D: usize>(&self, mesh: &MeshConfig<D>, density: f64) -> VResult<()> {
        let (element, volume) = match mesh {
            MeshConfig::Box(mesh) => (
                (0..D)
                    .map(|a| mesh.size[a] / mesh.cells[a] as f64)
                    .product::<f64>()
                    / (1..=D + 1).product::<usize>() as f64,
                mesh.size.iter().product::<f64>(),
            ),
            MeshConfig::File(f) => (
                f.mesh
                    .rest_elements()
                    .iter()
                    .map(|e| e.volume)
                    .fold(f64::INFINITY, f64::min),
                f.mesh.rest_volume(),
            ),
        };
        let total = density * volume;
        if !(density * element >= f64::MIN_POSITIVE && total.is_finite()) {
            return Err(self.err(
                "material.density",
                format!(
                    "{} times the mesh's volume gives vertex masses outside double precision \
                     (total mass {})",
                    num(density),
                    num(total)
                ),
            ));
        }
        Ok(())
    }

    fn material(&self, raw: &RawMaterial) -> VResult<(MaterialConfig, RawMaterial)> {
        let lame = match (raw.young, raw.poisson, raw.mu, raw.lambda) {
            (Some(young), Some(poisson), None, None) => {
                self.positive("material.young", young)?;
                if !(poisson > -1.0 && poisson < 0.5) {
                    return Err(self.err(
                        "material.poisson",
                        format!("must lie in (-1, 0.5), got {}", num(poisson)),
                    ));
                }
                let lame = LameParameters::from(YoungPoisson { young, poisson });
                if !(lame.mu.is_finite() && lame.lambda.is_finite()) {
                    return Err(self.err(
                        "material.young",
                        format!(
                            "{} with poisson = {} gives Lamé parameters outside double \
                             precision (mu = {}, lambda = {})",
                            num(young),
                            num(poisson),
                            num(lame.mu),
                            num(lame.lambda)
                        ),
                    ));
                }
                lame
            }
            (None, None, Some(mu), Some(lambda)) => {
                self.positive("material.mu", mu)?;
                if !(lambda.is_finite() && 3.0 * lambda + 2.0 * mu > 0.0) {
                    return Err(self.err(
                        "material.lambda",
                        format!(
                            "must be finite with 3 lambda + 2 mu > 0 (a positive bulk modulus), got {}",
                            num(lambda)
                        ),
                    ));
                }
                LameParameters { mu, lambda }
            }
            (young, poisson, mu, lambda) => {
                let (elastic, lame) = (
                    young.is_some() || poisson.is_some(),
                    mu.is_some() || lambda.is_some(),
                );
                let (key, reason) = match (elastic, lame) {
                    (true, true) => (
                        if mu.is_some() { "material.mu" } else { "material.lambda" },
                        "give either `young` and `poisson`, or `mu` and `lambda`, not both".to_owned(),
                    ),
                    (false, false) => (
                        "material",
                        "the stiffness is missing: give `young` and `poisson`, or `mu` and `lambda`".to_owned(),
                    ),
                    _ => {
                        let pairs = [("young", young, "poisson", poisson), ("poisson", poisson, "young", young)]
                            .into_iter()
                            .chain([("mu", mu, "lambda", lambda), ("lambda", lambda, "mu", mu)]);
                        let (given, missing) = pairs
                            .into_iter()
                            .find(|(_, a, _, b)| a.is_some() && b.is_none())
                            .map(|(g, _, m, _)| (g, m))
                            .expect("exactly one key of a pair is given");
                        return Err(self.err(
                            &format!("material.{missing}"),
                            format!("is required together with `{given}`"),
                        ));
                    }
                };
                return Err(self.err(key, reason));
            }
        };
        let density = self.positive("material.density", raw.density.unwrap_or(DEFAULT_DENSITY))?;
        let material = raw.model.with_lame(lame);
        let resolved = RawMaterial {
            density: Some(density),
            ..raw.clone()
        };
        Ok((MaterialConfig { material, density }, resolved))
    }

    fn time(&self, raw: &RawTime) -> VResult<(TimeConfig, RawTime)> {
        let fps = self.positive("time.fps", raw.fps.unwrap_or(DEFAULT_FPS))?;
        let substeps = match (raw.substeps, raw.dt) {
            (None, None) => DEFAULT_SUBSTEPS,
            (Some(n), None) => self.count("time.substeps", n, MAX_SUBSTEPS)?,
            (substeps, Some(dt)) => {
                let dt = self.positive("time.dt", dt)?;
                let exact = 1.0 / (fps * dt);
                let nearest = exact.round().max(1.0);
                if !(nearest <= MAX_SUBSTEPS as f64) {
                    return Err(self.err(
                        "time.dt",
                        format!(
                            "{} s makes {} steps per frame of 1/{} s, more than the \
                             {MAX_SUBSTEPS} allowed",
                            num(dt),
                            approx(exact),
                            num(fps)
                        ),
                    ));
                }
                if (exact - nearest).abs() > 1e-3 * nearest {
                    return Err(self.err(
                        "time.dt",
                        format!(
                            "{} s does not split a frame of 1/{} s into whole steps ({exact:.4} steps); \
                             use e.g. dt = {:.6e} ({nearest} steps) or give `substeps`",
                            num(dt),
                            num(fps),
                            1.0 / (fps * nearest)
                        ),
                    ));
                }
                let from_dt = nearest as usize;
                if let Some(n) = substeps.filter(|&n| n != from_dt as i64) {
                    return Err(self.err(
                        "time.dt",
                        format!(
                            "dt = {} s means {from_dt} steps per frame at {} fps, but substeps = {n}",
                            num(dt),
                            num(fps)
                        ),
                    ));
                }
                from_dt
            }
        };
        let frames = match (raw.frames, raw.duration) {
            (Some(_), Some(_)) => {
                return Err(self.err("time.duration", "give `frames` or `duration`, not both"));
            }
            (Some(n), None) => self.count("time.frames", n, MAX_FRAMES)?,
            (None, Some(d)) => {
                let d = self.positive("time.duration", d)?;
                let n = (d * fps).round();
                if n < 1.0 {
                    return Err(self.err(
                        "time.duration",
                        format!("{} s is less than one frame at {} fps", num(d), num(fps)),
                    ));
                }
                if !(n <= MAX_FRAMES as f64) {
                    return Err(self.err(
                        "time.duration",
                        format!(
                            "{} s at {} fps is {} frames, more than the {MAX_FRAMES} allowed",
                            num(d),
                            num(fps),
                            approx(n)
                        ),
                    ));
                }
                n as usize
            }
            (None, None) => DEFAULT_FRAMES,
        };
        let time_key = match (raw.dt, raw.frames, raw.duration) {
            (Some(_), _, _) => "time.dt",
            (None, Some(_), _) => "time.frames",
            (None, None, Some(_)) => "time.duration",
            _ => "time.substeps",
        };
        let steps = (frames - 1) as u64 * substeps as u64;
        if steps > MAX_STEPS {
            return Err(self.err(
                time_key,
                format!(
                    "{frames} frames of {substeps} steps make {steps} time steps, more than the \
                     {MAX_STEPS} allowed"
                ),
            ));
        }
        let dt = 1.0 / (fps * substeps as f64);
        // The solver weighs the potential by dt²: it must be a normal double.
        if !((dt * dt).is_finite() && dt * dt >= f64::MIN_POSITIVE) {
            let key = if raw.dt.is_some() {
                "time.dt"
            } else {
                "time.fps"
            };
            return Err(self.err(
                key,
                format!(
                    "gives a time step dt = 1 / (fps × substeps) = {} s whose square is outside \
                     double precision (the solver weighs forces by dt²)",
                    approx(dt)
                ),
            ));
        }
        let integrator = raw.integrator.unwrap_or_default();
        let resolved = RawTime {
            fps: Some(fps),
            substeps: Some(substeps as i64),
            dt: None,
            frames: Some(frames as i64),
            duration: None,
            integrator: Some(integrator),
        };
        Ok((
            TimeConfig {
                fps,
                substeps,
                dt,
                frames,
                integrator,
            },
            resolved,
        ))
    }

    /// `[solver]`, for bodies whose bounding box at rest has the diagonal
    /// `scene_size` (the default tolerance scales with it).
    fn solver(&self, raw: &RawSolver, scene_size: f64) -> VResult<(SolverSettings, RawSolver)> {
        let method = raw.method.unwrap_or_default();
        let tolerance = self.positive(
            "solver.tolerance",
            raw.tolerance
                .unwrap_or(DEFAULT_RELATIVE_TOLERANCE * scene_size),
        )?;
        let (method_settings, default_iterations, step) = match method {
            Method::Newton => {
                if raw.step.is_some() {
                    return Err(self.err(
                        "solver.step",
                        "is only used with method = \"gradient-descent\"",
                    ));
                }
                (SolverMethod::Newton, DEFAULT_NEWTON_ITERATIONS, None)
            }
            Method::GradientDescent => {
                let step = self.positive(
                    "solver.step",
                    raw.step.unwrap_or(DEFAULT_GRADIENT_DESCENT_STEP),
                )?;
                (
                    SolverMethod::GradientDescent { step },
                    DEFAULT_GRADIENT_DESCENT_ITERATIONS,
                    Some(step),
                )
            }
        };
        let projection = match (method, raw.projection) {
            (Method::GradientDescent, Some(_)) => {
                return Err(self.err("solver.projection", "is only used with method = \"newton\""));
            }
            (Method::GradientDescent, None) => None,
            (Method::Newton, given) => {
                Some(given.map_or(SolverSettings::default().projection, Projection::from))
            }
        };
        let max_iterations = match raw.max_iterations {
            Some(n) => self.count("solver.max_iterations", n, usize::MAX)?,
            None => default_iterations,
        };
        let max_subdivisions = match raw.max_subdivisions {
            Some(n) if (0..=MAX_SUBDIVISIONS as i64).contains(&n) => n as usize,
            Some(n) => {
                return Err(self.err(
                    "solver.max_subdivisions",
                    format!("must be a whole number from 0 to {MAX_SUBDIVISIONS}, got {n}"),
                ));
            }
            None => SolverSettings::default().max_subdivisions,
        };
        let resolved = RawSolver {
            method: Some(method),
            tolerance: Some(tolerance),
            max_iterations: Some(max_iterations as i64),
            projection: projection.map(ProjectionName::from),
            max_subdivisions: Some(max_subdivisions as i64),
            step,
            friction_velocity: None,
            friction_iterations: None,
        };
        Ok((
            SolverSettings {
                method: method_settings,
                tolerance,
                max_iterations,
                projection: projection.unwrap_or_default(),
                max_subdivisions,
                ..SolverSettings::default()
            },
            resolved,
        ))
    }

    /// `solver.friction_velocity` and `solver.friction_iterations`, in a
    /// scene with friction (a `friction` above 0 in `[effects.ground]`,
    /// `[effects.contact]` or an obstacle); refused without it, where they
    /// would do nothing.
    fn friction_solver<const D: usize>(
        &self,
        mut solver: SolverSettings,
        mut resolved: RawSolver,
        raw: &RawSolver,
        effects: &Effects<D>,
        bodies: &[BodyConfig<D>],
    ) -> VResult<(SolverSettings, RawSolver)> {
        let has_friction = effects.ground.is_some_and(|g| g.friction > 0.0)
            || effects.contact.is_some_and(|c| c.friction > 0.0)
            || effects
                .obstacles
                .iter()
                .any(|o| o.friction.is_some_and(|mu| mu > 0.0));
        if !has_friction {
            for (key, given) in [
                ("solver.friction_velocity", raw.friction_velocity.is_some()),
                (
                    "solver.friction_iterations",
                    raw.friction_iterations.is_some(),
                ),
            ] {
                if given {
                    return Err(self.err(
                        key,
                        "is only used with friction: give effects.ground.friction, \
                         effects.contact.friction or an obstacle's friction above 0",
                    ));
                }
            }
            return Ok((solver, resolved));
        }
        let velocity = match raw.friction_velocity {
            Some(v) => self.positive("solver.friction_velocity", v)?,
            None => DEFAULT_FRICTION_VELOCITY * bounding_box_diagonal(bodies),
        };
        let iterations = match raw.friction_iterations {
            Some(n) => self.count("solver.friction_iterations", n, MAX_FRICTION_ITERATIONS)?,
            None => 1,
        };
        solver.friction_velocity = Some(velocity);
        solver.friction_iterations = iterations;
        resolved.friction_velocity = Some(velocity);
        resolved.friction_iterations = Some(iterations as i64);
        Ok((solver, resolved))
    }

    /// A friction coefficient: 0 or more, finite.
    fn friction_coefficient(&self, key: &str, mu: Option<f64>) -> VResult<f64> {
        match mu {
            None => Ok(0.0),
            Some(mu) if mu >= 0.0 && mu.is_finite() => Ok(mu),
            Some(mu) => Err(self.err(
                key,
                format!("must be 0 or more and finite, got {}", num(mu)),
            )),
        }
    }

    fn effects<const D: usize>(
        &self,
        raw: &RawEffects,
        bodies: &[BodyConfig<D>],
    ) -> VResult<(Effects<D>, RawEffects)> {
        let mut effects = Effects::<D>::default();
        let mut resolved = RawEffects::default();
        if let Some(g) = &raw.gravity {
            effects.gravity =
                Some(self.vector::<D>("effects.gravity.acceleration", &g.acceleration)?);
            resolved.gravity = Some(g.clone());
        }
        if let Some(g) = &raw.ground {
            let height = g.height.unwrap_or(0.0);
            if !height.is_finite() {
                return Err(self.err(
                    "effects.ground.height",
                    format!("must be finite, got {}", num(height)),
                ));
            }
            self.single_precision("effects.ground.height", &[height], false)?;
            let a = self.positive("effects.ground.a", g.a.unwrap_or(DEFAULT_BARRIER_WIDTH))?;
            if !(1e-150..=1e150).contains(&a) {
                return Err(self.err(
                    "effects.ground.a",
                    format!(
                        "must lie in [1e-150, 1e150]: the barrier squares it, and its square \
                         must be a normal double; got {}",
                        num(a)
                    ),
                ));
            }
            let kappa = match g.kappa {
                Some(k) => Some(self.positive("effects.ground.kappa", k)?),
                None => None,
            };
            let (bottom, key) = bodies
                .iter()
                .map(|b| match &b.mesh {
                    MeshConfig::Box(m) => {
                        (m.offset[UP_AXIS], format!("{}mesh.offset", b.key_prefix))
                    }
                    MeshConfig::File(f) => (
                        f.mesh
                            .rest_positions()
                            .iter()
                            .map(|x| x[UP_AXIS])
                            .fold(f64::INFINITY, f64::min),
                        format!("{}mesh.translate", b.key_prefix),
                    ),
                })
                .fold((f64::INFINITY, String::new()), |low, b| {
                    if b.0 < low.0 { b } else { low }
                });
            if bottom <= height {
                return Err(self.err(
                    &key,
                    format!(
                        "the mesh starts at height {}, on or below the ground at {} \
                         (effects.ground.height); raise {key}[{UP_AXIS}]",
                        num(bottom),
                        num(height)
                    ),
                ));
            }
            // The barrier acts within `a` of the ground; far beyond the
            // scene's own lengths it pushes every vertex from the start with
            // a stiffness scaled to `a` (the default rule floors it by
            // `M a² / s²`), and the first step is lost to round-off.
            let scale = bounding_box_diagonal(bodies) + (bottom - height);
            if a > MAX_BARRIER_WIDTH_TO_SCENE * scale {
                return Err(self.err(
                    "effects.ground.a",
                    format!(
                        "{} is more than {} times the scene's size {} (the bodies' bounding box \
                         diagonal plus the gap they start at above the ground): the barrier \
                         would push every vertex from the start with a force that crushes the \
                         bodies and loses the first step to round-off; at most {} here (the \
                         default is {})",
                        num(a),
                        num(MAX_BARRIER_WIDTH_TO_SCENE),
                        approx(scale),
                        approx(MAX_BARRIER_WIDTH_TO_SCENE * scale),
                        num(DEFAULT_BARRIER_WIDTH)
                    ),
                ));
            }
            let friction = self.friction_coefficient("effects.ground.friction", g.friction)?;
            effects.ground = Some(Ground {
                height,
                activation_distance: a,
                stiffness: kappa,
                friction,
            });
            resolved.ground = Some(RawGround {
                height: Some(height),
                a: Some(a),
                kappa,
                friction: (friction > 0.0).then_some(friction),
            });
        }
        if let Some(c) = &raw.contact {
            let distance = match c.distance {
                Some(d) => self.positive("effects.contact.distance", d)?,
                None => 1e-3 * bounding_box_diagonal(bodies),
            };
            if !(1e-150..=1e150).contains(&distance) {
                return Err(self.err(
                    "effects.contact.distance",
                    format!(
                        "must lie in [1e-150, 1e150]: the barrier works on its square squared, \
                         which must be a normal double; got {}",
                        num(distance)
                    ),
                ));
            }
            let kappa = match c.kappa {
                Some(k) => Some(self.positive("effects.contact.kappa", k)?),
                None => None,
            };
            let self_contact = c.self_contact.unwrap_or(true);
            let friction = self.friction_coefficient("effects.contact.friction", c.friction)?;
            effects.contact = Some(Contact {
                distance: Some(distance),
                stiffness: kappa,
                self_contact,
                friction,
            });
            resolved.contact = Some(RawContact {
                distance: Some(distance),
                kappa,
                self_contact: Some(self_contact),
                friction: (friction > 0.0).then_some(friction),
            });
        }
        if let Some(list) = &raw.pinned {
            if list.regions.is_empty() {
                return Err(self.err(
                    "effects.pinned",
                    "is an empty array: give at least one [[effects.pinned]] region, or remove it",
                ));
            }
            for (i, p) in list.regions.iter().enumerate() {
                let key = if list.single_table {
                    "effects.pinned".to_owned()
                } else {
                    format!("effects.pinned[{i}]")
                };
                let region = self.pin_region::<D>(&key, p)?;
                // A vertex is pinned when it lies in the box (inclusive) at rest.
                let (mut catches, mut holds_all) = (false, true);
                for body in bodies {
                    let (c, h) = body.mesh.vertices_in(&region);
                    catches |= c;
                    holds_all &= h;
                }
                if !catches {
                    return Err(self.err(
                        &key,
                        "the region from `min` to `max` contains no mesh vertex at rest; widen it to catch the vertices to hold",
                    ));
                }
                if holds_all {
                    return Err(self.err(
                        &key,
                        "the region from `min` to `max` holds every mesh vertex: nothing could move; \
                         narrow it to the vertices to hold",
                    ));
                }
                effects.pinned.push(region);
            }
            resolved.pinned = Some(RawPinnedList {
                regions: list.regions.clone(),
                single_table: false,
            });
        }
        Ok((effects, resolved))
    }

    fn colour(&self, key: &str, v: Option<&Vec<f64>>, default: [f64; 3]) -> VResult<[f64; 3]> {
        let Some(v) = v else { return Ok(default) };
        if v.len() != 3 || v.iter().any(|c| !(0.0..=1.0).contains(c)) {
            return Err(self.err(
                key,
                format!(
                    "must be 3 components in [0, 1] (linear RGB), got {}",
                    nums(v)
                ),
            ));
        }
        Ok([v[0], v[1], v[2]])
    }

    fn render<const D: usize>(
        &self,
        raw: &RawRender,
        ground_height: Option<f64>,
    ) -> VResult<(FieldChoice, RenderSettings, RawRender)> {
        let resolution = match &raw.resolution {
            None => DEFAULT_RESOLUTION,
            Some(r) => {
                let ok =
                    r.len() == 2 && r.iter().all(|&p| (1..=MAX_RESOLUTION as i64).contains(&p));
                if !ok {
                    return Err(self.err(
                        "render.resolution",
                        format!("must be [width, height] in pixels, each 1..={MAX_RESOLUTION}, got {r:?}"),
                    ));
                }
                let [width, height] = [r[0] as u32, r[1] as u32];
                if image_bytes(width, height) > MAX_IMAGE_BYTES {
                    return Err(self.err(
                        "render.resolution",
                        format!(
                            "{width}x{height} is too large: an image is read back from the GPU \
                             in one buffer of at most {} MiB (4 bytes per pixel, rows padded \
                             to 256 bytes), this one needs {:.1} MiB",
                            MAX_IMAGE_BYTES >> 20,
                            image_bytes(width, height) as f64 / (1u64 << 20) as f64
                        ),
                    ));
                }
                [width, height]
            }
        };
        let field = match raw.field.unwrap_or_default() {
            FieldName::EnergyDensity => FieldChoice::Scalar(ElementField::EnergyDensity),
            FieldName::VonMises => FieldChoice::Scalar(ElementField::VonMises),
            FieldName::VolumeRatio => FieldChoice::Scalar(ElementField::VolumeRatio),
            FieldName::Flat => FieldChoice::Flat,
        };
        let range = match &raw.range {
            None => None,
            Some(r) => {
                if r.len() != 2 || !r.iter().all(|x| x.is_finite()) || r[0] >= r[1] {
                    return Err(self.err(
                        "render.range",
                        format!("must be [low, high] with low < high, got {}", nums(r)),
                    ));
                }
                self.single_precision("render.range", r, false)?;
                if (r[0] as f32) >= (r[1] as f32) {
                    return Err(self.err(
                        "render.range",
                        format!(
                            "{} is too narrow for the renderer's 32-bit floats: low and high \
                             round to the same value",
                            nums(r)
                        ),
                    ));
                }
                Some([r[0], r[1]])
            }
        };
        let colour = self.colour("render.colour", raw.colour.as_ref(), DEFAULT_COLOUR)?;
        let background = self.colour(
            "render.background",
            raw.background.as_ref(),
            DEFAULT_BACKGROUND,
        )?;
        let (camera, raw_camera) = match &raw.camera {
            None => (Camera::Auto, None),
            Some(c) => {
                let camera = self.camera::<D>(c)?;
                let resolved = match camera {
                    Camera::Perspective { .. } => RawCamera {
                        fov: Some(c.fov.unwrap_or(DEFAULT_FOV)),
                        ..c.clone()
                    },
                    _ => c.clone(),
                };
                (camera, Some(resolved))
            }
        };
        let colouring = match field {
            FieldChoice::Flat => Colouring::Flat(colour.map(|c| c as f32)),
            field => Colouring::Scalar {
                range: range.map(|r| r.map(|x| x as f32)),
                label: field.label(),
            },
        };
        let settings = RenderSettings {
            width: resolution[0],
            height: resolution[1],
            camera,
            colouring,
            background: background.map(|c| c as f32),
            ground_height: ground_height.map(|h| h as f32),
            draw_edges: raw.edges.unwrap_or(true),
            draw_legend: raw.legend.unwrap_or(true),
        };
        let resolved = RawRender {
            resolution: Some(resolution.iter().map(|&p| i64::from(p)).collect()),
            field: Some(raw.field.unwrap_or_default()),
            range: range.map(|r| r.to_vec()),
            colour: Some(colour.to_vec()),
            background: Some(background.to_vec()),
            edges: Some(settings.draw_edges),
            legend: Some(settings.draw_legend),
            camera: raw_camera,
        };
        Ok((field, settings, resolved))
    }

    fn camera<const D: usize>(&self, raw: &RawCamera) -> VResult<Camera> {
        let f32s = |v: Vector<D>| -> Vec<f32> { v.iter().map(|&x| x as f32).collect() };
        if D == 2 {
            for (key, present) in [
                ("eye", raw.eye.is_some()),
                ("target", raw.target.is_some()),
                ("fov", raw.fov.is_some()),
            ] {
                if present {
                    return Err(self.err(
                        &format!("render.camera.{key}"),
                        "is a 3D camera key; a 2D camera takes `center` and `height`",
                    ));
                }
            }
            let center = raw
                .center
                .as_ref()
                .ok_or_else(|| self.err("render.camera.center", "is required for a 2D camera"))?;
            let center = self.vector::<D>("render.camera.center", center)?;
            self.single_precision("render.camera.center", center.as_slice(), false)?;
            let center = f32s(center);
            let height = raw
                .height
                .ok_or_else(|| self.err("render.camera.height", "is required for a 2D camera"))?;
            let height = self.positive("render.camera.height", height)?;
            self.single_precision("render.camera.height", &[height], true)?;
            Ok(Camera::Orthographic {
                center: [center[0], center[1]],
                height: height as f32,
            })
        } else {
            for (key, present) in [
                ("center", raw.center.is_some()),
                ("height", raw.height.is_some()),
            ] {
                if present {
                    return Err(self.err(
                        &format!("render.camera.{key}"),
                        "is a 2D camera key; a 3D camera takes `eye`, `target` and `fov`",
                    ));
                }
            }
            let eye = raw
                .eye
                .as_ref()
                .ok_or_else(|| self.err("render.camera.eye", "is required for a 3D camera"))?;
            let eye = self.vector::<D>("render.camera.eye", eye)?;
            self.single_precision("render.camera.eye", eye.as_slice(), false)?;
            let eye = f32s(eye);
            let target = raw
                .target
                .as_ref()
                .ok_or_else(|| self.err("render.camera.target", "is required for a 3D camera"))?;
            let target = self.vector::<D>("render.camera.target", target)?;
            self.single_precision("render.camera.target", target.as_slice(), false)?;
            let target = f32s(target);
            if eye == target {
                return Err(self.err("render.camera.target", "must differ from `eye`"));
            }
            let distance = (0..3)
                .map(|k| f64::from(eye[k]) - f64::from(target[k]))
                .map(|d| d * d)
                .sum::<f64>()
                .sqrt();
            if !((distance as f32).is_finite()) {
                return Err(self.err(
                    "render.camera.target",
                    format!(
                        "is {} from `eye`, out of the renderer's range: images are drawn in \
                         32-bit floats, which hold magnitudes up to 3.4e38",
                        num(distance)
                    ),
                ));
            }
            let fov = raw.fov.unwrap_or(DEFAULT_FOV);
            if !(fov > 0.0 && fov < 180.0) {
                return Err(self.err(
                    "render.camera.fov",
                    format!("must lie in (0, 180) degrees, got {}", num(fov)),
                ));
            }
            Ok(Camera::Perspective {
                eye: [eye[0], eye[1], eye[2]],
                target: [target[0], target[1], target[2]],
                fov_degrees: fov as f32,
            })
        }
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
