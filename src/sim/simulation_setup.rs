//! Building a simulation: checking the settings, eliminating pinned vertices, and making the list of energy terms the scene's effects ask for.
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
use super::{Body, Effects, PinMotion, PinRegion, SimError, Simulation, SimulationSettings};
use crate::assembly::SparseHessian;
use crate::contact::ObstacleSurface;
use crate::energy::{BodyElasticity, EnergyTerm, Gravity, Inertia};
use crate::material::Material;
use crate::math::Vector;
use crate::mesh::Mesh;
use crate::solver::SolverMethod;
use std::sync::Arc;

fn invalid(key: &'static str, reason: impl Into<String>) -> SimError {
    SimError::InvalidSetting {
        key,
        reason: reason.into(),
    }
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
    pub fn with_bodies(
        bodies: Vec<Body<D>>,
        effects: Effects<D>,
        settings: SimulationSettings,
    ) -> Result<Self, SimError> {
        if bodies.is_empty() {
            return Err(invalid("bodies", "a simulation needs at least one body"));
        }
        for body in &bodies {
            let density = body.density;
            if !(density > 0.0 && density.is_finite()) {
                return Err(invalid(
                    "density",
                    format!("must be positive and finite, got {density}"),
                ));
            }
        }
        if !(settings.dt > 0.0 && settings.dt.is_finite()) {
            return Err(invalid(
                "dt",
                format!("must be positive and finite, got {}", settings.dt),
            ));
        }
        if !(settings.solver.tolerance > 0.0) {
            return Err(invalid(
                "tolerance",
                format!("must be positive, got {}", settings.solver.tolerance),
            ));
        }
        if settings.solver.max_iterations == 0 {
            return Err(invalid("max_iterations", "must be at least 1"));
        }
        if let SolverMethod::GradientDescent { step } = settings.solver.method
            && !(step > 0.0 && step.is_finite())
        {
            return Err(invalid(
                "step",
                format!("must be positive and finite, got {step}"),
            ));
        }
        if settings.solver.friction_iterations == 0 {
            return Err(invalid("friction_iterations", "must be at least 1"));
        }
        if let Some(v) = settings.solver.friction_velocity
            && !(v > 0.0 && v.is_finite())
        {
            return Err(invalid(
                "friction_velocity",
                format!("must be positive and finite, got {v}"),
            ));
        }
        for (label, region) in pin_labels(&effects, &bodies) {
            check_motion(&label, &region.motion)?;
        }
        // Per vertex: its body's index; masses and rest positions in body order.
        let mut owner = Vec::new();
        let mut masses = Vec::new();
        let mut positions = Vec::new();
        let mut simplices = Vec::new();
        for (b, body) in bodies.iter().enumerate() {
            let offset = positions.len();
            if let Some(region) = &body.pinned
                && !body
                    .mesh
                    .rest_positions()
                    .iter()
                    .any(|x| region.contains(x))
            {
                return Err(invalid(
                    "pinned",
                    format!("the pinned region of body {b} holds no vertex of it"),
                ));
            }
            owner.extend(std::iter::repeat_n(b, body.mesh.vertex_count()));
            masses.extend(body.mesh.lumped_masses(body.density));
            positions.extend_from_slice(body.mesh.rest_positions());
            simplices.extend(
                body.mesh
                    .simplices()
                    .map(|s| s.iter().map(|v| v + offset).collect::<Vec<_>>()),
            );
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
            let mesh = Arc::new(Mesh::new(positions.clone(), simplices).map_err(|e| {
                SimError::SetupFailure {
                    reason: e.to_string(),
                }
            })?);
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
        if let Some(i) = effects
            .pinned
            .iter()
            .position(|r| !positions.iter().any(|x| r.contains(x)))
        {
            return Err(invalid(
                "pinned",
                format!("the pinned region effects.pinned[{i}] holds no vertex"),
            ));
        }
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
        if free_count == 0 {
            return Err(invalid(
                "pinned",
                "every vertex is pinned: nothing can move",
            ));
        }
        // Free vertices start with their body's velocity, pinned ones with
        // their path's.
        let mut velocities: Vec<Vector<D>> = (0..positions.len())
            .map(|v| body_velocities[owner[v]])
            .collect();
        // The obstacles' points after the bodies' vertices, each pinned to
        // its obstacle's path, massless.
        let mut free_index = free_index;
        if !effects.obstacles.is_empty() && effects.contact.is_none() {
            return Err(invalid(
                "obstacles",
                "obstacles take part in contact: the scene needs [effects.contact]",
            ));
        }
        let mut obstacle_surfaces = Vec::with_capacity(effects.obstacles.len());
        for (k, obstacle) in effects.obstacles.iter().enumerate() {
            check_motion(&format!("obstacles[{k}]"), &obstacle.motion)?;
            if obstacle.motion.release.is_some() {
                return Err(invalid(
                    "obstacles",
                    format!("obstacles[{k}]: an obstacle cannot be released"),
                ));
            }
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
            )?),
            None => None,
        };
        let contact = match effects.contact {
            Some(contact) => {
                let colliding = Colliding {
                    mesh: &mesh,
                    owner: &owner,
                    body_count,
                    obstacles: obstacle_surfaces,
                };
                Some(contact_barrier(
                    colliding,
                    &masses[..n],
                    &positions,
                    n,
                    contact,
                )?)
            }
            None => None,
        };
        let friction = friction_term(&effects, &positions[..n], settings.solver.friction_velocity)?;
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

/// Each pinned region with its name for messages: `effects.pinned[i]`, then
/// `the pinned region of body b`.
fn pin_labels<const D: usize>(
    effects: &Effects<D>,
    bodies: &[Body<D>],
) -> Vec<(String, PinRegion<D>)> {
    let own = effects
        .pinned
        .iter()
        .enumerate()
        .map(|(i, r)| (format!("effects.pinned[{i}]"), *r));
    let of_bodies = bodies.iter().enumerate().filter_map(|(b, body)| {
        body.pinned
            .map(|r| (format!("the pinned region of body {b}"), r))
    });
    own.chain(of_bodies).collect()
}

/// A motion's numbers must be finite, its axis a unit vector, `until >= 0`
/// and `release > 0`.
fn check_motion<const D: usize>(label: &str, motion: &PinMotion<D>) -> Result<(), SimError> {
    let finite = motion.velocity.iter().all(|v| v.is_finite())
        && motion.angular_velocity.is_finite()
        && motion.center.iter().all(|v| v.is_finite());
    if !finite {
        return Err(invalid(
            "pinned",
            format!("{label}: velocity, angular velocity and centre must be finite"),
        ));
    }
    if D == 3 && motion.angular_velocity != 0.0 && (motion.axis.norm() - 1.0).abs() > 1e-12 {
        return Err(invalid(
            "pinned",
            format!(
                "{label}: the rotation axis must be a unit vector, got {:?}",
                motion.axis.as_slice()
            ),
        ));
    }
    if let Some(until) = motion.until
        && !(until >= 0.0 && until.is_finite())
    {
        return Err(invalid(
            "pinned",
            format!("{label}: `until` must be a finite time >= 0, got {until}"),
        ));
    }
    if let Some(release) = motion.release
        && !(release > 0.0 && release.is_finite())
    {
        return Err(invalid(
            "pinned",
            format!("{label}: `release` must be a finite time > 0, got {release}"),
        ));
    }
    Ok(())
}
