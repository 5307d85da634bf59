//! The validator: turns the raw scene document into the typed settings of
//! [`Scene`], reporting every problem at its file position (or flag) and
//! dotted key.
//!
//! It is the only code that reads [`RawScene`]; it returns the typed scene
//! together with the resolved raw form (every default written out), which is
//! what `scene.toml` of a run holds.

use super::SceneError;
use super::material_model::build_material;
use super::raw_scene::{
    FieldName, Generator, Method, RawCamera, RawEffects, RawGround, RawMaterial, RawMesh,
    RawRender, RawScene, RawSolver, RawTime,
};
use super::scene_config::{
    BoxMesh, DEFAULT_BACKGROUND, DEFAULT_BARRIER_WIDTH, DEFAULT_COLOUR, DEFAULT_DENSITY,
    DEFAULT_FOV, DEFAULT_FPS, DEFAULT_FRAMES, DEFAULT_GRADIENT_DESCENT_ITERATIONS,
    DEFAULT_GRADIENT_DESCENT_STEP, DEFAULT_NEWTON_ITERATIONS, DEFAULT_RESOLUTION, DEFAULT_SUBSTEPS,
    DEFAULT_TOLERANCE, FieldChoice, MAX_RESOLUTION, MaterialConfig, Scene, SceneConfig, TimeConfig,
};
use super::scene_document::SceneDocument;
use crate::material::{LameParameters, YoungPoisson};
use crate::math::{UP_AXIS, Vector};
use crate::render::{Camera, Colouring, RenderSettings};
use crate::sim::{Effects, ElementField, Ground, PinRegion};
use crate::solver::{SolverMethod, SolverSettings};

/// Turns a [`RawScene`] into a [`Scene`] plus the resolved raw form,
/// reporting each problem at its key.
pub(crate) struct SceneValidator<'d, 'a> {
    doc: &'d SceneDocument<'a>,
}

type VResult<T> = std::result::Result<T, SceneError>;

impl<'d, 'a> SceneValidator<'d, 'a> {
    /// A validator whose messages point into `doc`.
    pub fn new(doc: &'d SceneDocument<'a>) -> Self {
        Self { doc }
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
        self.doc.error(key, reason)
    }

    fn scene_d<const D: usize>(&self, raw: &RawScene) -> VResult<(SceneConfig<D>, RawScene)> {
        let name = match &raw.name {
            Some(n) if n.trim().is_empty() => return Err(self.err("name", "must not be empty")),
            Some(n) => n.clone(),
            None => self.doc.source().default_name.clone(),
        };
        let (mesh, initial_velocity, raw_mesh) = self.mesh::<D>(&raw.mesh)?;
        let (material, raw_material) = self.material(&raw.material)?;
        let (time, raw_time) = self.time(&raw.time)?;
        let (solver, raw_solver) = self.solver(&raw.solver)?;
        let (effects, raw_effects) = self.effects::<D>(&raw.effects, &mesh)?;
        let ground_height = effects.ground.map(|g| g.height);
        let (field, render, raw_render) = self.render::<D>(&raw.render, ground_height)?;
        let config = SceneConfig {
            name: name.clone(),
            mesh,
            initial_velocity,
            material,
            time,
            solver,
            effects,
            field,
            render,
        };
        let resolved = RawScene {
            name: Some(name),
            dimension: D as u64,
            mesh: raw_mesh,
            material: raw_material,
            time: raw_time,
            solver: raw_solver,
            effects: raw_effects,
            render: raw_render,
        };
        Ok((config, resolved))
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
            return Err(self.err(key, format!("components must be finite, got {bad}")));
        }
        Ok(Vector::<D>::from_fn(|i, _| v[i]))
    }

    fn positive(&self, key: &str, x: f64) -> VResult<f64> {
        if x.is_finite() && x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(key, format!("must be a finite number > 0, got {x}")))
        }
    }

    fn count(&self, key: &str, n: u64) -> VResult<usize> {
        if n == 0 {
            return Err(self.err(key, "must be at least 1, got 0"));
        }
        usize::try_from(n).map_err(|_| self.err(key, format!("{n} is too large")))
    }

    fn mesh<const D: usize>(&self, raw: &RawMesh) -> VResult<(BoxMesh<D>, Vector<D>, RawMesh)> {
        let Generator::Box = raw.generator.unwrap_or_default();
        let size = self.vector::<D>("mesh.size", &raw.size)?;
        if let Some(bad) = size.iter().find(|s| **s <= 0.0) {
            return Err(self.err("mesh.size", format!("every extent must be > 0, got {bad}")));
        }
        if raw.cells.len() != D {
            return Err(self.err(
                "mesh.cells",
                format!(
                    "needs {D} components (dimension = {D}), got {}",
                    raw.cells.len()
                ),
            ));
        }
        let mut cells = [0usize; D];
        for (c, &n) in cells.iter_mut().zip(&raw.cells) {
            *c = self.count("mesh.cells", n)?;
        }
        let elements = cells.iter().try_fold(1usize, |acc, &c| acc.checked_mul(c));
        if elements.is_none_or(|n| n > 50_000_000) {
            return Err(self.err(
                "mesh.cells",
                format!("{:?} makes too many cells", raw.cells),
            ));
        }
        let offset = match &raw.offset {
            Some(v) => self.vector::<D>("mesh.offset", v)?,
            None => Vector::<D>::zeros(),
        };
        let velocity = match &raw.velocity {
            Some(v) => self.vector::<D>("mesh.velocity", v)?,
            None => Vector::<D>::zeros(),
        };
        let resolved = RawMesh {
            generator: Some(Generator::Box),
            size: size.iter().copied().collect(),
            cells: raw.cells.clone(),
            offset: Some(offset.iter().copied().collect()),
            velocity: Some(velocity.iter().copied().collect()),
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

    fn material(&self, raw: &RawMaterial) -> VResult<(MaterialConfig, RawMaterial)> {
        let lame = match (raw.young, raw.poisson, raw.mu, raw.lambda) {
            (Some(young), Some(poisson), None, None) => {
                self.positive("material.young", young)?;
                if !(poisson > -1.0 && poisson < 0.5) {
                    return Err(self.err(
                        "material.poisson",
                        format!("must lie in (-1, 0.5), got {poisson}"),
                    ));
                }
                LameParameters::from(YoungPoisson { young, poisson })
            }
            (None, None, Some(mu), Some(lambda)) => {
                self.positive("material.mu", mu)?;
                if !(lambda.is_finite() && 3.0 * lambda + 2.0 * mu > 0.0) {
                    return Err(self.err(
                        "material.lambda",
                        format!("must be finite with 3 lambda + 2 mu > 0 (a positive bulk modulus), got {lambda}"),
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
        let material = build_material(raw.model, lame);
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
            (Some(n), None) => self.count("time.substeps", n)?,
            (substeps, Some(dt)) => {
                let dt = self.positive("time.dt", dt)?;
                let exact = 1.0 / (fps * dt);
                let nearest = exact.round().max(1.0);
                if (exact - nearest).abs() > 1e-3 * nearest {
                    return Err(self.err(
                        "time.dt",
                        format!(
                            "{dt} s does not split a frame of 1/{fps} s into whole steps ({exact:.4} steps); \
                             use e.g. dt = {:.6e} ({nearest} steps) or give `substeps`",
                            1.0 / (fps * nearest)
                        ),
                    ));
                }
                let from_dt = nearest as usize;
                if let Some(n) = substeps.filter(|&n| n as usize != from_dt) {
                    return Err(self.err(
                        "time.dt",
                        format!("dt = {dt} s means {from_dt} steps per frame at {fps} fps, but substeps = {n}"),
                    ));
                }
                from_dt
            }
        };
        let frames = match (raw.frames, raw.duration) {
            (Some(_), Some(_)) => {
                return Err(self.err("time.duration", "give `frames` or `duration`, not both"));
            }
            (Some(n), None) => self.count("time.frames", n)?,
            (None, Some(d)) => {
                let d = self.positive("time.duration", d)?;
                let n = (d * fps).round();
                if n < 1.0 {
                    return Err(self.err(
                        "time.duration",
                        format!("{d} s is less than one frame at {fps} fps"),
                    ));
                }
                n as usize
            }
            (None, None) => DEFAULT_FRAMES,
        };
        let dt = 1.0 / (fps * substeps as f64);
        let resolved = RawTime {
            fps: Some(fps),
            substeps: Some(substeps as u64),
            dt: None,
            frames: Some(frames as u64),
            duration: None,
        };
        Ok((
            TimeConfig {
                fps,
                substeps,
                dt,
                frames,
            },
            resolved,
        ))
    }

    fn solver(&self, raw: &RawSolver) -> VResult<(SolverSettings, RawSolver)> {
        let method = raw.method.unwrap_or_default();
        let tolerance = self.positive(
            "solver.tolerance",
            raw.tolerance.unwrap_or(DEFAULT_TOLERANCE),
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
        let max_iterations = match raw.max_iterations {
            Some(n) => self.count("solver.max_iterations", n)?,
            None => default_iterations,
        };
        let resolved = RawSolver {
            method: Some(method),
            tolerance: Some(tolerance),
            max_iterations: Some(max_iterations as u64),
            step,
        };
        Ok((
            SolverSettings {
                method: method_settings,
                tolerance,
                max_iterations,
            },
            resolved,
        ))
    }

    fn effects<const D: usize>(
        &self,
        raw: &RawEffects,
        mesh: &BoxMesh<D>,
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
                    format!("must be finite, got {height}"),
                ));
            }
            let a = self.positive("effects.ground.a", g.a.unwrap_or(DEFAULT_BARRIER_WIDTH))?;
            let kappa = match g.kappa {
                Some(k) => Some(self.positive("effects.ground.kappa", k)?),
                None => None,
            };
            let bottom = mesh.offset[UP_AXIS];
            if bottom <= height {
                return Err(self.err(
                    "mesh.offset",
                    format!(
                        "the mesh starts at height {bottom}, on or below the ground at {height} \
                         (effects.ground.height); raise mesh.offset[{UP_AXIS}]"
                    ),
                ));
            }
            effects.ground = Some(Ground {
                height,
                activation_distance: a,
                stiffness: kappa,
            });
            resolved.ground = Some(RawGround {
                height: Some(height),
                a: Some(a),
                kappa,
            });
        }
        if let Some(p) = &raw.pinned {
            let min = self.vector::<D>("effects.pinned.min", &p.min)?;
            let max = self.vector::<D>("effects.pinned.max", &p.max)?;
            if let Some(axis) = (0..D).find(|&a| min[a] > max[a]) {
                return Err(self.err(
                    "effects.pinned.max",
                    format!(
                        "is below effects.pinned.min along axis {axis} ({} < {})",
                        max[axis], min[axis]
                    ),
                ));
            }
            // A vertex is pinned when it lies in the box (inclusive) at rest; the
            // grid is a tensor product, so some vertex is caught exactly when
            // every axis has a grid coordinate inside [min, max].
            let catches =
                (0..D).all(|a| mesh.axis_coordinates(a).any(|x| min[a] <= x && x <= max[a]));
            if !catches {
                return Err(self.err(
                    "effects.pinned",
                    "the region from `min` to `max` contains no mesh vertex at rest; widen it to catch the vertices to hold",
                ));
            }
            effects.pinned = Some(PinRegion { min, max });
            resolved.pinned = Some(p.clone());
        }
        Ok((effects, resolved))
    }

    fn colour(&self, key: &str, v: Option<&Vec<f64>>, default: [f64; 3]) -> VResult<[f64; 3]> {
        let Some(v) = v else { return Ok(default) };
        if v.len() != 3 || v.iter().any(|c| !(0.0..=1.0).contains(c)) {
            return Err(self.err(
                key,
                format!("must be 3 components in [0, 1] (linear RGB), got {v:?}"),
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
                    r.len() == 2 && r.iter().all(|&p| (1..=MAX_RESOLUTION as u64).contains(&p));
                if !ok {
                    return Err(self.err(
                        "render.resolution",
                        format!("must be [width, height] in pixels, each 1..={MAX_RESOLUTION}, got {r:?}"),
                    ));
                }
                [r[0] as u32, r[1] as u32]
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
                        format!("must be [low, high] with low < high, got {r:?}"),
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
            resolution: Some(resolution.iter().map(|&p| p as u64).collect()),
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
            let center = f32s(self.vector::<D>("render.camera.center", center)?);
            let height = raw
                .height
                .ok_or_else(|| self.err("render.camera.height", "is required for a 2D camera"))?;
            let height = self.positive("render.camera.height", height)?;
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
            let eye = f32s(self.vector::<D>("render.camera.eye", eye)?);
            let target = raw
                .target
                .as_ref()
                .ok_or_else(|| self.err("render.camera.target", "is required for a 3D camera"))?;
            let target = f32s(self.vector::<D>("render.camera.target", target)?);
            if eye == target {
                return Err(self.err("render.camera.target", "must differ from `eye`"));
            }
            let fov = raw.fov.unwrap_or(DEFAULT_FOV);
            if !(fov > 0.0 && fov < 180.0) {
                return Err(self.err(
                    "render.camera.fov",
                    format!("must lie in (0, 180) degrees, got {fov}"),
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
