//! The validator's second stage, on the built meshes: each body's mesh is
//! built here, once, and handed to the simulation, after the checks that
//! need it: the masses against `dt²` times the stiffness, some vertex left
//! free by the pinned regions together, nothing starting in contact
//! (crossing or closer than `d_hat`, or one collider inside another, asked
//! of [`crate::sim::start_problem`] and reported at the key of the body or
//! obstacle it names), and a given ground stiffness against the automatic
//! one ([`crate::sim::automatic_ground_stiffness`]).
//!
//! It runs after the first stage (`Scene::load`) and after the run checked
//! that the meshes fit in this machine's memory, so nothing large is built
//! for a scene that cannot run.

use super::{SceneValidator, VResult};
use crate::energy::GROUND_STIFFNESS_RATIO;
use crate::math::Vector;
use crate::mesh::Mesh;
use crate::scene::scene_config::{BodyConfig, SceneConfig};
use crate::scene::scene_error::{approx, num};
use crate::sim::{
    Body, Collider, Effects, StartProblem, automatic_ground_stiffness, start_problem,
};

/// The largest ratio of `dt²` times a vertex's elastic stiffness to its
/// lumped mass that a scene may have. The first step's system matrix is
/// `M + dt² K`: beyond about 1e15 the masses are below the round-off of the
/// stiffness in double precision and the matrix is singular (a free body's
/// rigid motions are carried by `M` alone); well before that, at 1e12 and
/// up, the round-off of the elastic forces (`1e-16 × K x`) outweighs gravity
/// and inertia and Newton stalls at its iteration cap (measured: Neo-Hookean
/// fails from about 1e13 on the report's box, where `young = 1e16`). The
/// shipped scenes reach at most 1e4 (see docs/scene-reference.md).
pub const MAX_STIFFNESS_TO_MASS: f64 = 1e12;

impl SceneValidator<'_, '_> {
    /// The bodies of `config` with their meshes built, as the simulation
    /// takes them, each problem reported at its key.
    pub fn meshed_bodies<const D: usize>(&self, config: &SceneConfig<D>) -> VResult<Vec<Body<D>>> {
        let mut bodies = Vec::with_capacity(config.bodies.len());
        for body in &config.bodies {
            let mesh = body.mesh.build().map_err(|source| {
                self.err(
                    &format!("{}mesh", body.key_prefix),
                    format!("cannot be meshed: {source}"),
                )
            })?;
            self.mass_against_stiffness(body, &mesh, config.time.dt)?;
            bodies.push(Body {
                mesh,
                material: body.material.material,
                density: body.material.density,
                velocity: body.initial_velocity,
                pinned: body.pinned,
            });
        }
        self.something_free(&bodies, &config.effects)?;
        self.start_apart(&bodies, config)?;
        self.ground_stiffness(&bodies, &config.effects)?;
        Ok(bodies)
    }

    /// A body's masses must not be lost beside its stiffness in the first
    /// step's system: for every vertex, `dt² k / m` at most
    /// [`MAX_STIFFNESS_TO_MASS`], where `k = Σ (λ + 2μ) V |∇N|²` over its
    /// elements (the diagonal of the linear-elastic stiffness at rest, `∇N`
    /// the gradient of the vertex's shape function) and `m` its lumped mass.
    fn mass_against_stiffness<const D: usize>(
        &self,
        body: &BodyConfig<D>,
        mesh: &Mesh<D>,
        dt: f64,
    ) -> VResult<()> {
        let material = &body.material.material;
        let (mu, lambda) = (
            material.parameter("mu").unwrap_or(0.0),
            material.parameter("lambda").unwrap_or(0.0),
        );
        let modulus = lambda + 2.0 * mu;
        let density = body.material.density;
        let mut stiffness = vec![0.0; mesh.vertex_count()];
        for (simplex, rest) in mesh.simplices().zip(mesh.rest_elements()) {
            let mut first = Vector::<D>::zeros();
            for (j, &vertex) in simplex.iter().enumerate().skip(1) {
                let gradient = rest.dm_inv.row(j - 1).transpose();
                first -= gradient;
                stiffness[vertex] += modulus * rest.volume * gradient.norm_squared();
            }
            stiffness[simplex[0]] += modulus * rest.volume * first.norm_squared();
        }
        let masses = mesh.lumped_masses(density);
        let (vertex, ratio) = stiffness
            .iter()
            .zip(&masses)
            .map(|(k, m)| dt * dt * k / m)
            .enumerate()
            .fold((0, 0.0), |worst, (v, r)| {
                if r > worst.1 || r.is_nan() {
                    (v, r)
                } else {
                    worst
                }
            });
        if ratio <= MAX_STIFFNESS_TO_MASS {
            return Ok(());
        }
        let prefix = &body.key_prefix;
        // Named at the key the user changed last, when it is one of these.
        let candidates = [
            format!("{prefix}material.young"),
            format!("{prefix}material.density"),
            format!("{prefix}material.mu"),
            format!("{prefix}material.lambda"),
            "time.dt".to_owned(),
            "time.substeps".to_owned(),
            "time.fps".to_owned(),
        ];
        let key = self
            .doc
            .overrides()
            .iter()
            .rev()
            .map(|o| o.key())
            .find(|key| candidates.contains(key))
            .unwrap_or_else(|| candidates[0].clone());
        let shrink = MAX_STIFFNESS_TO_MASS / ratio;
        Err(self.err(
            &key,
            format!(
                "the masses are lost beside the stiffness: dt² (λ + 2μ) / mass reaches {} at \
                 vertex {vertex} of {}(λ + 2μ = {}, density {}, dt = {} s), more than the {} up \
                 to which the first step's system holds the masses in double precision; lower \
                 the stiffness or raise the density by a factor of at least {}, or take a step \
                 of at most {} s (more time.substeps)",
                approx(ratio),
                if prefix.is_empty() {
                    "the body ".to_owned()
                } else {
                    format!("{} ", prefix.trim_end_matches('.'))
                },
                approx(modulus),
                num(density),
                approx(dt),
                num(MAX_STIFFNESS_TO_MASS),
                approx(1.0 / shrink),
                approx(dt * shrink.sqrt()),
            ),
        ))
    }

    /// The pinned regions together (`[[effects.pinned]]` and the bodies'
    /// own) must leave some vertex free; each alone was checked to hold
    /// some vertex and not all of them in the first stage.
    fn something_free<const D: usize>(
        &self,
        bodies: &[Body<D>],
        effects: &Effects<D>,
    ) -> VResult<()> {
        let all_pinned = bodies.iter().all(|body| {
            body.mesh.rest_positions().iter().all(|x| {
                effects.pinned.iter().any(|r| r.contains(x))
                    || body.pinned.is_some_and(|r| r.contains(x))
            })
        });
        if !all_pinned {
            return Ok(());
        }
        let key = if bodies.iter().any(|b| b.pinned.is_some()) {
            "bodies"
        } else {
            "effects.pinned"
        };
        Err(self.err(
            key,
            "the pinned regions together hold every mesh vertex: nothing could move; narrow \
             them to the vertices to hold",
        ))
    }

    /// Nothing may start in contact: reported at the obstacle's key when an
    /// obstacle is involved, at the body's `mesh` when its own surface
    /// crosses or folds within `d_hat`, else at `effects.contact` (two
    /// bodies within `d_hat`) or the enclosed body (`bodies[i]`).
    fn start_apart<const D: usize>(
        &self,
        bodies: &[Body<D>],
        config: &SceneConfig<D>,
    ) -> VResult<()> {
        let problem = start_problem(bodies, &config.effects)
            .map_err(|e| self.err("bodies", format!("cannot be joined into one mesh: {e}")))?;
        let Some(problem) = problem else {
            return Ok(());
        };
        let pair = match &problem {
            StartProblem::TooClose { colliders, .. } => *colliders,
            StartProblem::Inside { inner, outer, .. } => [*inner, *outer],
        };
        let obstacle = pair.iter().find_map(|c| match c {
            Collider::Obstacle(k) => Some(*k),
            Collider::Body(_) => None,
        });
        let prefix = |b: usize| config.bodies[b].key_prefix.as_str();
        let key = match (&problem, pair, obstacle) {
            (_, _, Some(k)) => format!("obstacles[{k}]"),
            (_, [Collider::Body(a), Collider::Body(b)], None) if a == b => {
                format!("{}mesh", prefix(a))
            }
            (StartProblem::Inside { .. }, [Collider::Body(inner), _], None) => {
                prefix(inner).trim_end_matches('.').to_owned()
            }
            _ => "effects.contact".to_owned(),
        };
        Err(self.err(&key, problem.to_string()))
    }

    /// A ground stiffness given in the scene must lie within
    /// [`GROUND_STIFFNESS_RATIO`] of the automatic one for these bodies.
    fn ground_stiffness<const D: usize>(
        &self,
        bodies: &[Body<D>],
        effects: &Effects<D>,
    ) -> VResult<()> {
        let Some(kappa) = effects.ground.and_then(|g| g.stiffness) else {
            return Ok(());
        };
        let Some(automatic) = automatic_ground_stiffness(bodies, effects) else {
            return Ok(());
        };
        let [low, high] = GROUND_STIFFNESS_RATIO.map(|r| r * automatic);
        if kappa >= low && kappa <= high {
            return Ok(());
        }
        Err(self.err(
            "effects.ground.kappa",
            format!(
                "must lie in [{}, {}] for this scene, 1e-6 to 1e6 times the automatic \
                 stiffness {} (stiffer, the body freezes at the barrier's edge; softer, it \
                 comes within round-off of the ground); got {}",
                approx(low),
                approx(high),
                approx(automatic),
                num(kappa)
            ),
        ))
    }
}
