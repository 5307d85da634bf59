//! Building a simulation: joining the bodies' meshes, eliminating pinned vertices, and making the list of energy terms the scene's effects ask for.
//!
//! The input is trusted: the scene validator has checked every setting at
//! its key, and on the built meshes that the pinned regions hold vertices
//! but not all of them and that nothing starts on the ground or in contact
//! ([`super::start_problem`]). A value out of range here is a programming
//! error (a `debug_assert!`), and the [`SimError`] returned is a genuine
//! setup failure (the sparse analysis).
//!
//! Elasticity is always a term; gravity and the ground barrier exist only
//! when the scene asks for them (an absent effect has no term, so it costs
//! nothing). Pinned vertices are eliminated from the unknowns here, once;
//! each keeps its rest position and the index of the motion it follows
//! (the effects' regions first, then the bodies'), and starts with its
//! path's velocity.
//! The integrator gets the initial acceleration `a_0 = -M^{-1} grad U(x_0)`
//! here (Newmark needs it; the other schemes ignore it).

use super::contact_setup::{Colliding, contact_barrier, friction_term, ground_barrier};
use super::simulation::PinnedVertex;
use super::start_problem::joined_mesh;
use super::{Body, Effects, PinMotion, PinRegion, SimError, Simulation, SimulationSettings};
use crate::assembly::SparseHessian;
use crate::contact::ObstacleSurface;
use crate::energy::{BodyElasticity, EnergyTerm, Gravity, GroundBarrier, Inertia};
use crate::material::Material;
use crate::math::Vector;
use crate::mesh::Mesh;
use std::sync::Arc;

/// Which pinned region holds a body's vertex at rest.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Holder {
    /// `effects.pinned[i]`.
    Effect(usize),
    /// The body's own region.
    Own,
}

/// The region that holds the vertex at rest position `x` of a body pinned
/// by `own`: the first of the effects' `regions` that contains it, else the
/// body's own; `None` for a free vertex.
fn holder<const D: usize>(
    regions: &[PinRegion<D>],
    own: Option<PinRegion<D>>,
    x: &Vector<D>,
) -> Option<Holder> {
    match regions.iter().position(|r| r.contains(x)) {
        Some(i) => Some(Holder::Effect(i)),
        None => own.filter(|r| r.contains(x)).map(|_| Holder::Own),
    }
}

/// The stiffness the ground's default rule gives `bodies` under `effects`,
/// as [`Simulation::with_bodies`] computes it for them (at rest, pinned
/// vertices moving with their paths); `None` without a ground. The scene
/// validator holds a given `effects.ground.kappa` against it.
pub fn automatic_ground_stiffness<const D: usize>(
    bodies: &[Body<D>],
    effects: &Effects<D>,
) -> Option<f64> {
    let ground = effects.ground?;
    let mut masses = Vec::new();
    let mut positions = Vec::new();
    let mut velocities = Vec::new();
    for body in bodies {
        masses.extend(body.mesh.lumped_masses(body.density));
        for x in body.mesh.rest_positions() {
            let motion = match holder(&effects.pinned, body.pinned, x) {
                Some(Holder::Effect(i)) => Some(effects.pinned[i].motion),
                Some(Holder::Own) => body.pinned.map(|r| r.motion),
                None => None,
            };
            positions.push(*x);
            velocities.push(motion.map_or(body.velocity, |m| m.velocity_of(x, 0.0)));
        }
    }
    Some(GroundBarrier::default_stiffness(
        ground.height,
        ground.activation_distance,
        &masses,
        &positions,
        &velocities,
        effects.gravity,
    ))
}

/// `a_0 = -M^{-1} grad U(x_0)` on free vertices, zero on pinned ones: the
/// acceleration of the initial state under every potential term.
fn initial_acceleration<const D: usize>(
    elasticity: &dyn EnergyTerm<D>,
    effect_terms: &[&dyn EnergyTerm<D>],
    masses: &[f64],
    free_index: &[Option<usize>],
    positions: &[Vector<D>],
) -> Vec<Vector<D>> {
    let mut gradient = vec![Vector::<D>::zeros(); positions.len()];
    elasticity.add_gradient(positions, 1.0, &mut gradient);
    for term in effect_terms {
        term.add_gradient(positions, 1.0, &mut gradient);
    }
    gradient
        .iter()
        .zip(masses)
        .zip(free_index)
        .map(|((g, m), free)| match free {
            Some(_) if *m > 0.0 => -g / *m,
            _ => Vector::<D>::zeros(),
        })
        .collect()
}

impl<const D: usize> Simulation<D> {
    /// Builds a simulation of `mesh` made of `material` with `density` (mass per
    /// unit rest volume), starting at rest positions with `initial_velocity`.
    pub fn new(
        mesh: Mesh<D>,
        material: Material,
        density: f64,
        effects: Effects<D>,
        settings: SimulationSettings,
        initial_velocity: Vector<D>,
    ) -> Result<Self, SimError> {
        let body = Body {
            mesh,
            material,
            density,
            velocity: initial_velocity,
            pinned: None,
        };
        Self::with_bodies(vec![body], effects, settings)
    }

    /// Builds a simulation of several bodies: their meshes are concatenated
    /// (vertices and elements in body order) into the simulation's mesh;
    /// each has its material, density, initial velocity and pinned region,
    /// and all share the effects (which pin vertices of any body).
    ///
    /// The input is trusted, as the scene validator hands it over
    /// ([`crate::scene::SceneConfig::meshed_bodies`]): settings in range,
    /// pinned regions that hold some vertex but leave one free, nothing on
    /// or below the ground, and nothing in contact at the start
    /// ([`super::start_problem`]). The error is a failure of setting up the
    /// solver.
    pub fn with_bodies(
        bodies: Vec<Body<D>>,
        effects: Effects<D>,
        settings: SimulationSettings,
    ) -> Result<Self, SimError> {
        debug_assert!(!bodies.is_empty(), "a simulation needs at least one body");
        debug_assert!(
            settings.dt > 0.0 && settings.solver.tolerance > 0.0,
            "the scene validator refuses a step or tolerance that is not positive"
        );
        // Per vertex: its body's index; masses and rest positions in body order.
        let mut owner = Vec::new();
        let mut masses = Vec::new();
        let mut positions = Vec::new();
        for (b, body) in bodies.iter().enumerate() {
            owner.extend(std::iter::repeat_n(b, body.mesh.vertex_count()));
            masses.extend(body.mesh.lumped_masses(body.density));
            positions.extend_from_slice(body.mesh.rest_positions());
        }
        let body_vertices = positions.len();
        let pins: Vec<Option<PinRegion<D>>> = bodies.iter().map(|b| b.pinned).collect();
        let body_velocities: Vec<Vector<D>> = bodies.iter().map(|b| b.velocity).collect();
        let body_count = bodies.len();
        let (mesh, elasticity) = if bodies.len() == 1 {
            let body = bodies.into_iter().next().expect("one body");
            let mesh = Arc::new(body.mesh);
            let elasticity = BodyElasticity::single(mesh.clone(), body.material);
            (mesh, elasticity)
        } else {
            let mesh = Arc::new(joined_mesh(&bodies)?.into_owned());
            let parts = bodies
                .iter()
                .map(|b| (Arc::new(b.mesh.clone()), b.material))
                .collect();
            let elasticity = BodyElasticity::bodies(parts).map_err(|e| SimError::SetupFailure {
                reason: e.to_string(),
            })?;
            (mesh, elasticity)
        };
        // The motions: the effects' regions first, then each body's.
        let mut motions: Vec<PinMotion<D>> = effects.pinned.iter().map(|r| r.motion).collect();
        let body_motion: Vec<Option<usize>> = pins
            .iter()
            .map(|p| {
                p.map(|r| {
                    motions.push(r.motion);
                    motions.len() - 1
                })
            })
            .collect();
        // A vertex follows the first region (in that order) that holds it at rest.
        let motion_of = |v: usize, x: &Vector<D>| match holder(&effects.pinned, pins[owner[v]], x)?
        {
            Holder::Effect(i) => Some(i),
            Holder::Own => body_motion[owner[v]],
        };
        let mut free_count = 0;
        let mut pinned = Vec::new();
        let free_index: Vec<Option<usize>> = positions
            .iter()
            .enumerate()
            .map(|(v, x)| match motion_of(v, x) {
                Some(motion) => {
                    pinned.push(PinnedVertex {
                        vertex: v,
                        rest: *x,
                        motion,
                    });
                    None
                }
                None => {
                    free_count += 1;
                    Some(free_count - 1)
                }
            })
            .collect();
        debug_assert!(
            free_count > 0,
            "the validator refuses a scene with every vertex pinned"
        );
        // Free vertices start with their body's velocity, pinned ones with
        // their path's.
        let mut velocities: Vec<Vector<D>> = (0..positions.len())
            .map(|v| body_velocities[owner[v]])
            .collect();
        // The obstacles' points after the bodies' vertices, each pinned to
        // its obstacle's path, massless.
        let mut free_index = free_index;
        debug_assert!(
            effects.obstacles.is_empty() || effects.contact.is_some(),
            "obstacles take part in contact: the validator asks for [effects.contact]"
        );
        let mut obstacle_surfaces = Vec::with_capacity(effects.obstacles.len());
        for (k, obstacle) in effects.obstacles.iter().enumerate() {
            debug_assert!(
                obstacle.motion.release.is_none(),
                "an obstacle is never released"
            );
            motions.push(obstacle.motion);
            let offset = positions.len();
            for x in obstacle.surface.points() {
                pinned.push(PinnedVertex {
                    vertex: positions.len(),
                    rest: *x,
                    motion: motions.len() - 1,
                });
                positions.push(*x);
                velocities.push(Vector::<D>::zeros());
                masses.push(0.0);
                owner.push(body_count + k);
                free_index.push(None);
            }
            obstacle_surfaces.push(ObstacleSurface {
                surface: &obstacle.surface,
                offset,
                friction: obstacle.friction,
            });
        }
        for p in &pinned {
            velocities[p.vertex] = motions[p.motion].velocity_of(&p.rest, 0.0);
        }
        let mut effect_terms: Vec<Box<dyn EnergyTerm<D>>> = Vec::new();
        if let Some(g) = effects.gravity {
            effect_terms.push(Box::new(Gravity::new(masses.clone(), g)));
        }
        let n = body_vertices;
        let ground = match effects.ground {
            Some(ground) => Some(ground_barrier(
                ground,
                &masses[..n],
                &positions[..n],
                &velocities[..n],
                effects.gravity,
            )),
            None => None,
        };
        let contact = match effects.contact {
            Some(contact) => {
                let colliding = Colliding {
                    mesh: &mesh,
                    owner: &owner,
                    obstacles: obstacle_surfaces,
                };
                Some(contact_barrier(
                    colliding,
                    &masses[..n],
                    &positions,
                    n,
                    contact,
                ))
            }
            None => None,
        };
        let friction = friction_term(&effects, &positions[..n], settings.solver.friction_velocity);
        let hessian = SparseHessian::with_unattached_vertices(&mesh, &positions[n..], free_index)
            .map_err(|e| SimError::SetupFailure {
            reason: e.to_string(),
        })?;
        let mut integrator = settings.integrator.build(positions.len());
        let mut potentials: Vec<&dyn EnergyTerm<D>> =
            effect_terms.iter().map(|t| t.as_ref()).collect();
        if let Some(ground) = &ground {
            potentials.push(ground);
        }
        if let Some(contact) = &contact {
            potentials.push(contact);
        }
        integrator.set_initial_acceleration(&initial_acceleration(
            &elasticity,
            &potentials,
            &masses,
            hessian.free_index(),
            &positions,
        ));
        // An obstacle's point has no mass; the augmented Lagrangian that
        // pulls it onto its path weighs it as the bodies' mean vertex.
        let obstacle_constraint_mass = masses[..n].iter().sum::<f64>() / n.max(1) as f64;
        Ok(Self {
            inertia: Inertia::new(masses.clone()),
            elasticity,
            effect_terms,
            integrator,
            contact,
            ground,
            friction,
            friction_dissipated: 0.0,
            mesh,
            masses,
            positions,
            velocities,
            time: 0.0,
            steps: 0,
            settings,
            hessian,
            prescribed_hessian: None,
            energy_ceiling: None,
            motions,
            pinned,
            obstacle_constraint_mass,
            obstacles: effects.obstacles,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{MaterialModel, YoungPoisson};
    use crate::sim::Ground;

    /// The validator's automatic stiffness is the one the simulation
    /// computes, pinned vertices moving with their paths included (a path
    /// faster than the body raises the kinetic energy the rule counts).
    #[test]
    fn the_automatic_ground_stiffness_is_the_simulations() {
        let mesh = Mesh::axis_aligned_box(
            Vector::<2>::new(0.0, 1.0),
            Vector::<2>::new(1.0, 2.0),
            [2, 2],
        )
        .unwrap();
        let body = Body {
            mesh,
            material: MaterialModel::NeoHookean.with_lame(
                YoungPoisson {
                    young: 100.0,
                    poisson: 0.3,
                }
                .into(),
            ),
            density: 2.0,
            velocity: Vector::<2>::new(0.5, 0.0),
            pinned: None,
        };
        let fast = PinMotion {
            velocity: Vector::<2>::new(0.0, 30.0),
            ..PinMotion::default()
        };
        let region = PinRegion::new(Vector::<2>::new(-1.0, 1.9), Vector::<2>::new(2.0, 3.0));
        let effects = Effects {
            gravity: Some(Vector::<2>::new(0.0, -9.81)),
            ground: Some(Ground {
                height: 0.0,
                activation_distance: 0.1,
                stiffness: None,
                friction: 0.0,
            }),
            pinned: vec![region.moving(fast)],
            ..Effects::default()
        };
        let still = Effects {
            pinned: vec![region],
            ..effects.clone()
        };
        let bodies = vec![body];
        let automatic = automatic_ground_stiffness(&bodies, &effects).unwrap();
        let sim = Simulation::with_bodies(bodies.clone(), effects, SimulationSettings::default())
            .unwrap();
        assert_eq!(automatic, sim.ground().unwrap().automatic_stiffness());
        let at_rest = automatic_ground_stiffness(&bodies, &still).unwrap();
        assert!(automatic > 2.0 * at_rest, "{automatic} vs {at_rest}");
        assert_eq!(
            automatic_ground_stiffness(&bodies, &Effects::default()),
            None
        );
    }
}
