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
use crate::energy::{BodyElasticity, EnergyTerm, Gravity, Inertia};
use crate::material::Material;
use crate::math::Vector;
use crate::mesh::Mesh;
use std::sync::Arc;

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
        let motion_of = |v: usize, x: &Vector<D>| {
            effects
                .pinned
                .iter()
                .position(|r| r.contains(x))
                .or_else(|| {
                    body_motion[owner[v]].filter(|_| pins[owner[v]].is_some_and(|r| r.contains(x)))
                })
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
