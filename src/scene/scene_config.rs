//! The validated scene: typed settings with every default filled in.
//!
//! These are plain structs; [`Scene::load`] fills them from a scene file
//! through the validator (`scene_validator.rs`), which is the only code that
//! reads the raw TOML document. Each field's documentation states its
//! default (the scene file's default, which is also the type's `Default`)
//! and its unit.

use crate::energy::ElementField;
use crate::integrator::IntegratorKind;
use crate::material::Material;
use crate::material::{MaterialModel, YoungPoisson};
use crate::math::{UP_AXIS, Vector};
use crate::mesh_io::ImportReport;
use crate::render::RenderSettings;
use crate::sim::{Effects, Ground, PinRegion, SimulationSettings};
use crate::solver::SolverSettings;

pub use super::mesh_config::{BoxMesh, FileMesh, MeshConfig, RecordedFile};

/// Default output frames per second.
pub const DEFAULT_FPS: f64 = 30.0;
/// Default substeps per frame.
pub const DEFAULT_SUBSTEPS: usize = 10;
/// Default number of output frames.
pub const DEFAULT_FRAMES: usize = 300;
/// Default density, mass per unit rest volume (area in 2D).
pub const DEFAULT_DENSITY: f64 = 1.0;
/// The default of `solver.tolerance` (on `|dx|_inf / dt`, length/s) per
/// unit of the bodies' bounding-box diagonal `L` at rest: a scene without
/// the key converges at `1e-3 L` per second (IPC's rule, whose factor is
/// `1e-2`). Chosen by an `elasto study` of the solver's error against time
/// (`docs/physics.md`): on the contact scenes, the most sensitive, it leaves
/// a trajectory error near `6e-4 L` (under a pixel at 1000 pixels across),
/// half a percent of backward Euler's own error at their step, where
/// `1e-2` left `1e-2 L`; `1e-4` cost 20% more Newton iterations for an
/// error nobody sees.
pub const DEFAULT_RELATIVE_TOLERANCE: f64 = 1e-3;
/// Default iteration cap per step for Newton.
pub const DEFAULT_NEWTON_ITERATIONS: usize = 50;
/// Default iteration cap per step for gradient descent.
pub const DEFAULT_GRADIENT_DESCENT_ITERATIONS: usize = 10_000;
/// Default gradient-descent step (the report's value).
pub const DEFAULT_GRADIENT_DESCENT_STEP: f64 = 1e-6;
/// Default ground barrier activation distance, length units.
pub const DEFAULT_BARRIER_WIDTH: f64 = 0.1;
/// Default image size in pixels.
pub const DEFAULT_RESOLUTION: [u32; 2] = [1280, 720];
/// Default flat colour (linear RGB).
pub const DEFAULT_COLOUR: [f64; 3] = [0.8, 0.3, 0.2];
/// Default background colour (linear RGB).
pub const DEFAULT_BACKGROUND: [f64; 3] = [0.95, 0.95, 0.95];
/// Default 3D camera vertical field of view, degrees.
pub const DEFAULT_FOV: f64 = 35.0;
/// Largest accepted image side, pixels.
pub const MAX_RESOLUTION: u32 = 16384;
/// Largest image, in bytes of its read-back buffer (see [`image_bytes`]): the
/// renderer's device never allows a larger buffer (WebGL2-level limits,
/// lowered further by some adapters, which `run` checks before simulating).
pub const MAX_IMAGE_BYTES: u64 = 256 << 20;
/// Largest number of output frames.
pub const MAX_FRAMES: usize = 1_000_000;
/// Largest number of steps per frame.
pub const MAX_SUBSTEPS: usize = 1_000_000;
/// Largest number of time steps in a run, `(frames - 1) * substeps`.
pub const MAX_STEPS: u64 = 1_000_000_000;
/// Largest number of mesh cells (product of `mesh.cells`).
pub const MAX_CELLS: usize = 50_000_000;
/// Longest scene name, in bytes (it names a folder).
pub const MAX_NAME_BYTES: usize = 255;

/// Bytes of the buffer an image of `width` x `height` pixels is read back
/// through: RGBA8 rows padded to 256 bytes (wgpu's copy alignment).
pub fn image_bytes(width: u32, height: u32) -> u64 {
    let row = (u64::from(width) * 4).div_ceil(256) * 256;
    row * u64::from(height)
}

/// The material and its density (`[material]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaterialConfig {
    /// Model and its parameters (required in a scene file; `Default`:
    /// St. Venant-Kirchhoff with E = 300 and nu = 0.3, the report's).
    pub material: Material,
    /// Mass per unit rest volume (area in 2D), in mass/length^3 (default: 1).
    pub density: f64,
}

impl Default for MaterialConfig {
    fn default() -> Self {
        Self {
            // The report's St. Venant-Kirchhoff with E = 300, nu = 0.3.
            material: MaterialModel::StVenantKirchhoff.with_lame(
                YoungPoisson {
                    young: 300.0,
                    poisson: 0.3,
                }
                .into(),
            ),
            density: DEFAULT_DENSITY,
        }
    }
}

impl MaterialConfig {
    /// The model's scene-file name (`stvk`, `neo-hookean`, `stable-neo-hookean`, ...).
    pub fn model_name(&self) -> &'static str {
        self.material.model().name()
    }
}

/// One body: its mesh, material, initial velocity and pinned region
/// (`[mesh]` and `[material]`, or one `[[bodies]]` entry).
#[derive(Debug, Clone, PartialEq)]
pub struct BodyConfig<const D: usize> {
    /// The body's rest mesh (default: a unit box of one cell).
    pub mesh: MeshConfig<D>,
    /// Initial velocity of every vertex, in length/s (default: zero).
    pub initial_velocity: Vector<D>,
    /// Material (default: [`MaterialConfig::default`]).
    pub material: MaterialConfig,
    /// The body's vertices inside this box at rest are pinned (`bodies.pinned`;
    /// default: none; a single-body scene pins with `[effects.pinned]`).
    pub pinned: Option<PinRegion<D>>,
    /// The prefix of this body's scene keys, for messages: empty for
    /// `[mesh]` and `[material]`, `bodies[1].` for the second `[[bodies]]`
    /// entry (default: empty).
    pub key_prefix: String,
}

impl<const D: usize> Default for BodyConfig<D> {
    fn default() -> Self {
        Self {
            mesh: MeshConfig::default(),
            initial_velocity: Vector::<D>::zeros(),
            material: MaterialConfig::default(),
            pinned: None,
            key_prefix: String::new(),
        }
    }
}

/// Output frames and the time step (`[time]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeConfig {
    /// Output frames per second, in 1/s (default: 30).
    pub fps: f64,
    /// Steps per output frame (default: 10).
    pub substeps: usize,
    /// Step length `1 / (fps * substeps)`, in seconds (default: 1/300).
    pub dt: f64,
    /// Number of output frames; frame `i` is the state at time `i / fps`
    /// (frame 0 is the initial state) (default: 300).
    pub frames: usize,
    /// The time integrator (default: backward Euler).
    pub integrator: IntegratorKind,
}

impl Default for TimeConfig {
    fn default() -> Self {
        Self {
            fps: DEFAULT_FPS,
            substeps: DEFAULT_SUBSTEPS,
            dt: 1.0 / (DEFAULT_FPS * DEFAULT_SUBSTEPS as f64),
            frames: DEFAULT_FRAMES,
            integrator: IntegratorKind::default(),
        }
    }
}

/// What colours the rendered triangles (`render.field`): which per-element
/// field the simulation hands to the renderer, or none.
/// (default: the strain energy density).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FieldChoice {
    /// A per-element scalar through the colour map.
    Scalar(ElementField),
    /// One flat colour.
    Flat,
}

impl Default for FieldChoice {
    fn default() -> Self {
        FieldChoice::Scalar(ElementField::EnergyDensity)
    }
}

impl FieldChoice {
    /// The scene-file name of the field.
    pub fn name(&self) -> &'static str {
        match self {
            FieldChoice::Scalar(ElementField::EnergyDensity) => "energy-density",
            FieldChoice::Scalar(ElementField::VonMises) => "von-mises",
            FieldChoice::Scalar(ElementField::VolumeRatio) => "volume-ratio",
            FieldChoice::Flat => "flat",
        }
    }

    /// The legend title.
    pub fn label(&self) -> &'static str {
        match self {
            FieldChoice::Scalar(ElementField::EnergyDensity) => "strain energy density",
            FieldChoice::Scalar(ElementField::VonMises) => "von Mises stress",
            FieldChoice::Scalar(ElementField::VolumeRatio) => "volume ratio J",
            FieldChoice::Flat => "",
        }
    }

    /// The element field saved with meshes and used for colouring
    /// (energy density when the render is flat).
    pub fn element_field(&self) -> ElementField {
        match self {
            FieldChoice::Scalar(f) => *f,
            FieldChoice::Flat => ElementField::EnergyDensity,
        }
    }
}

/// A validated scene in `D` dimensions.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneConfig<const D: usize> {
    /// The scene's name, which names the default output folder `out/NAME`
    /// (default: the file stem, or the built-in scene's name).
    pub name: String,
    /// The bodies, at least one (default: one default body).
    /// They share gravity, the ground and contact (`[effects.contact]`).
    pub bodies: Vec<BodyConfig<D>>,
    /// Frames and time step.
    pub time: TimeConfig,
    /// Nonlinear solver (default: [`SolverSettings::default`]).
    pub solver: SolverSettings,
    /// Effects that exist, the obstacles (`[[obstacles]]`) among them
    /// (default: none).
    pub effects: Effects<D>,
    /// The per-element field shown by the renderer and saved with meshes
    /// (default: the strain energy density).
    pub field: FieldChoice,
    /// Rendering: the renderer's own settings, filled from `[render]` (its
    /// colouring from `render.field`, `render.range` and `render.colour`, its
    /// ground line from `[effects.ground]`).
    pub render: RenderSettings,
}

impl<const D: usize> Default for SceneConfig<D> {
    fn default() -> Self {
        Self {
            name: "scene".to_owned(),
            bodies: vec![BodyConfig::default()],
            time: TimeConfig::default(),
            solver: SolverSettings::default(),
            effects: Effects::default(),
            field: FieldChoice::default(),
            render: RenderSettings::default(),
        }
    }
}

impl<const D: usize> SceneConfig<D> {
    /// See [`Scene::changed_mesh_files`].
    pub fn changed_mesh_files(&self) -> Vec<(String, String)> {
        self.bodies
            .iter()
            .filter_map(|body| match &body.mesh {
                MeshConfig::File(f) => f
                    .change()
                    .map(|change| (format!("{}mesh.path", body.key_prefix), change)),
                MeshConfig::Box(_) => None,
            })
            .collect()
    }

    /// See [`Scene::warnings`].
    pub fn warnings(&self) -> Vec<String> {
        let mut warnings: Vec<String> = self
            .changed_mesh_files()
            .into_iter()
            .map(|(key, change)| format!("{key}: {change}"))
            .collect();
        if let Some(ground) = self.effects.ground {
            let lowest = self
                .bodies
                .iter()
                .map(|b| b.mesh.lowest(UP_AXIS))
                .fold(f64::INFINITY, f64::min);
            let gap = lowest - ground.height;
            if gap < ground.activation_distance {
                warnings.push(format!(
                    "effects.ground.a = {} is more than the gap of {} the bodies start at above \
                     the ground: the barrier pushes them up from the first step (lower `a`, or \
                     raise the mesh, to start them at rest)",
                    super::num(ground.activation_distance),
                    super::num(gap)
                ));
            }
        }
        warnings
    }

    /// Number of vertices of all bodies.
    pub fn vertex_count(&self) -> usize {
        self.bodies.iter().map(|b| b.mesh.vertex_count()).sum()
    }

    /// Number of elements of all bodies.
    pub fn element_count(&self) -> usize {
        self.bodies.iter().map(|b| b.mesh.element_count()).sum()
    }

    /// Settings of the time integrator.
    pub fn simulation_settings(&self) -> SimulationSettings {
        SimulationSettings {
            dt: self.time.dt,
            integrator: self.time.integrator,
            solver: self.solver,
        }
    }
}

/// A validated scene, 2D or 3D.
#[derive(Debug, Clone, PartialEq)]
pub enum Scene {
    /// A 2D scene (triangles).
    Two(SceneConfig<2>),
    /// A 3D scene (tetrahedra).
    Three(SceneConfig<3>),
}

macro_rules! common {
    ($self:ident, $c:ident => $e:expr) => {
        match $self {
            Scene::Two($c) => $e,
            Scene::Three($c) => $e,
        }
    };
}

impl Scene {
    /// The scene's name.
    pub fn name(&self) -> &str {
        common!(self, c => &c.name)
    }

    /// 2 or 3.
    pub fn dimension(&self) -> usize {
        match self {
            Scene::Two(_) => 2,
            Scene::Three(_) => 3,
        }
    }

    /// Frames and time step.
    pub fn time(&self) -> &TimeConfig {
        common!(self, c => &c.time)
    }

    /// The first body's material.
    pub fn material(&self) -> &MaterialConfig {
        common!(self, c => &c.bodies[0].material)
    }

    /// Every body's material, in order.
    pub fn materials(&self) -> Vec<&MaterialConfig> {
        common!(self, c => c.bodies.iter().map(|b| &b.material).collect())
    }

    /// Number of bodies.
    pub fn body_count(&self) -> usize {
        common!(self, c => c.bodies.len())
    }

    /// Solver settings.
    pub fn solver(&self) -> &SolverSettings {
        common!(self, c => &c.solver)
    }

    /// The per-element field shown and saved.
    pub fn field(&self) -> FieldChoice {
        common!(self, c => c.field)
    }

    /// Rendering.
    pub fn render(&self) -> &RenderSettings {
        common!(self, c => &c.render)
    }

    /// Number of mesh vertices.
    pub fn vertex_count(&self) -> usize {
        common!(self, c => c.vertex_count())
    }

    /// Number of mesh elements.
    pub fn element_count(&self) -> usize {
        common!(self, c => c.element_count())
    }

    /// What importing each mesh file found (bodies with a box mesh have none).
    pub fn import_reports(&self) -> Vec<&ImportReport> {
        common!(self, c => c.bodies.iter().filter_map(|b| b.mesh.import_report()).collect())
    }

    /// What a valid scene may still do that its author did not mean, said
    /// before a run: a mesh file that differs from the size and checksum
    /// the scene recorded; a ground barrier wider than the gap the bodies
    /// start at pushes them up from the first step.
    pub fn warnings(&self) -> Vec<String> {
        common!(self, c => c.warnings())
    }

    /// The mesh files that differ from the size and checksum the scene
    /// recorded (`mesh.file_size`, `mesh.file_checksum`): each as its key
    /// (`mesh.path`, `bodies[1].mesh.path`) and what changed.
    pub fn changed_mesh_files(&self) -> Vec<(String, String)> {
        common!(self, c => c.changed_mesh_files())
    }

    /// Ground height, when there is a ground.
    pub fn ground(&self) -> Option<Ground> {
        common!(self, c => c.effects.ground)
    }

    /// One line per obstacle for `elasto check`: its facets, whether its
    /// surface is closed, its motion and its own friction.
    pub fn obstacle_lines(&self) -> Vec<String> {
        common!(self, c => c.effects.obstacles.iter().map(|o| {
            let facets = o.surface.facets().len();
            let kind = if self.dimension() == 2 { "segments" } else { "triangles" };
            let shape = if o.surface.is_closed() { "closed" } else { "open" };
            let motion = if o.motion.is_moving() {
                let until = o.motion.until.map_or(String::new(), |u| format!(" until t = {u} s"));
                format!(
                    "moving (velocity {:?}, angular velocity {} rad/s){until}",
                    o.motion.velocity.as_slice(),
                    o.motion.angular_velocity
                )
            } else {
                "still".to_owned()
            };
            let friction = o.friction.map_or(String::new(), |mu| format!(", friction mu = {mu}"));
            format!("{facets} {kind} ({shape}), {motion}{friction}")
        }).collect())
    }

    /// Names of the effects that exist (`gravity`, `ground`, `contact`,
    /// `pinned`, `obstacles`).
    pub fn effect_names(&self) -> Vec<&'static str> {
        let (g, gr, co, p) = common!(self, c => (c.effects.gravity.is_some(), c.effects.ground.is_some(), c.effects.contact.is_some(), !c.effects.pinned.is_empty()));
        let o = common!(self, c => !c.effects.obstacles.is_empty());
        [
            (g, "gravity"),
            (gr, "ground"),
            (co, "contact"),
            (p, "pinned"),
            (o, "obstacles"),
        ]
        .into_iter()
        .filter(|(on, _)| *on)
        .map(|(_, n)| n)
        .collect()
    }
}
