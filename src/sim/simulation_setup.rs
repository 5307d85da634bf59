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

use super::simulation::PinnedVertex;
use super::{Body, Effects, PinMotion, PinRegion, SimError, Simulation, SimulationSettings};
use crate::assembly::SparseHessian;
use crate::contact::{
    CandidateFinder, CollisionMesh, ContactStencil, StencilKind, SurfaceCrossing,
    first_contained_body, first_surface_crossing,
};
use crate::energy::{
    BodyElasticity, ContactBarrier, ContactSettings, EnergyTerm, Friction, FrictionSettings,
    Gravity, GroundBarrier, Inertia,
};
use crate::material::Material;
use crate::math::Vector;
use crate::mesh::Mesh;
use crate::solver::SolverMethod;
use std::sync::Arc;

/// Friction's default velocity threshold `eps_v`, per second, as a fraction
/// of the bodies' bounding-box diagonal.
pub const DEFAULT_FRICTION_VELOCITY: f64 = 1e-3;

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
        let pins: Vec<Option<PinRegion<D>>> = bodies.iter().map(|b| b.pinned).collect();
        let body_velocities: Vec<Vector<D>> = bodies.iter().map(|b| b.velocity).collect();
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
        for p in &pinned {
            velocities[p.vertex] = motions[p.motion].velocity_of(&p.rest, 0.0);
        }
        let mut effect_terms: Vec<Box<dyn EnergyTerm<D>>> = Vec::new();
        if let Some(g) = effects.gravity {
            effect_terms.push(Box::new(Gravity::new(masses.clone(), g)));
        }
        let ground = match effects.ground {
            Some(ground) => Some(ground_barrier(
                ground,
                &masses,
                &positions,
                &velocities,
                effects.gravity,
            )?),
            None => None,
        };
        let contact = match effects.contact {
            Some(contact) => Some(contact_barrier(
                &mesh, &owner, &masses, &positions, contact,
            )?),
            None => None,
        };
        let friction = friction_term(&effects, &positions, settings.solver.friction_velocity)?;
        let hessian =
            SparseHessian::new(&mesh, free_index).map_err(|e| SimError::SetupFailure {
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
        })
    }
}

/// The ground's barrier for the bodies' vertices at `positions` (none on or
/// below the plane) with their `masses` and `velocities`.
fn ground_barrier<const D: usize>(
    ground: super::Ground,
    masses: &[f64],
    positions: &[Vector<D>],
    velocities: &[Vector<D>],
    gravity: Option<Vector<D>>,
) -> Result<GroundBarrier, SimError> {
    if !(ground.activation_distance > 0.0 && ground.activation_distance.is_finite()) {
        return Err(invalid(
            "a",
            format!(
                "the barrier width must be positive, got {}",
                ground.activation_distance
            ),
        ));
    }
    if let Some(kappa) = ground.stiffness
        && !(kappa > 0.0 && kappa.is_finite())
    {
        return Err(invalid(
            "kappa",
            format!("must be positive and finite, got {kappa}"),
        ));
    }
    let barrier = GroundBarrier::for_bodies(
        ground.height,
        ground.activation_distance,
        ground.stiffness,
        masses,
        positions,
        velocities,
        gravity,
    );
    if let Some((vertex, height)) = barrier.first_vertex_below(positions) {
        return Err(SimError::BelowGround {
            vertex,
            height,
            ground: ground.height,
        });
    }
    Ok(barrier)
}

/// The friction term, if the ground or the contact has a coefficient above
/// 0 (and exists): with the velocity threshold given, or 1e-3 times the
/// bounding-box diagonal of the bodies at `positions` per second.
fn friction_term<const D: usize>(
    effects: &Effects<D>,
    positions: &[Vector<D>],
    velocity_threshold: Option<f64>,
) -> Result<Option<Friction<D>>, SimError> {
    let contact = effects.contact.map_or(0.0, |c| c.friction);
    let ground = effects.ground.map_or(0.0, |g| g.friction);
    for (key, mu) in [("contact", contact), ("ground", ground)] {
        if !(mu >= 0.0 && mu.is_finite()) {
            return Err(invalid(
                key,
                format!("the friction coefficient must be 0 or more and finite, got {mu}"),
            ));
        }
    }
    if contact == 0.0 && ground == 0.0 {
        return Ok(None);
    }
    let velocity_threshold = velocity_threshold
        .unwrap_or_else(|| DEFAULT_FRICTION_VELOCITY * bounding_box_diagonal(positions));
    Ok(Some(Friction::new(FrictionSettings {
        contact,
        ground,
        velocity_threshold,
    })))
}

/// The diagonal of the axis-aligned box around `positions`.
fn bounding_box_diagonal<const D: usize>(positions: &[Vector<D>]) -> f64 {
    let (low, high) = positions.iter().fold(
        (
            Vector::<D>::repeat(f64::INFINITY),
            Vector::<D>::repeat(f64::NEG_INFINITY),
        ),
        |(low, high), x| (low.inf(x), high.sup(x)),
    );
    (high - low).norm()
}

/// The contact term of the bodies (vertex `v` of body `owner[v]`) at their
/// rest positions, refused when two surface primitives start closer than
/// `d_hat` (bodies that start intersecting or touching).
fn contact_barrier<const D: usize>(
    mesh: &Mesh<D>,
    owner: &[usize],
    masses: &[f64],
    positions: &[Vector<D>],
    contact: super::Contact,
) -> Result<ContactBarrier<D>, SimError> {
    let diagonal = bounding_box_diagonal(positions);
    let distance = contact.distance.unwrap_or(1e-3 * diagonal);
    if !(distance > 0.0 && distance.is_finite()) {
        return Err(invalid(
            "contact",
            format!("the contact distance must be positive and finite, got {distance}"),
        ));
    }
    if let Some(kappa) = contact.stiffness
        && !(kappa > 0.0 && kappa.is_finite())
    {
        return Err(invalid(
            "contact",
            format!("the contact stiffness must be positive and finite, got {kappa}"),
        ));
    }
    let collision_mesh = CollisionMesh::new(mesh, owner);
    if let Some(crossing) = first_surface_crossing(&collision_mesh, positions, contact.self_contact)
    {
        let edge = |e: usize| collision_mesh.edges()[e];
        let (first, second, a, b) = match crossing {
            SurfaceCrossing::Edges(a, b) => {
                let (ea, eb) = (edge(a), edge(b));
                (
                    format!("edge ({}, {})", ea[0], ea[1]),
                    format!("edge ({}, {})", eb[0], eb[1]),
                    owner[ea[0]],
                    owner[eb[0]],
                )
            }
            SurfaceCrossing::EdgeThroughFace { edge: e, face } => {
                let (ea, f) = (edge(e), collision_mesh.faces()[face]);
                (
                    format!("edge ({}, {})", ea[0], ea[1]),
                    format!("triangle ({}, {}, {})", f[0], f[1], f[2]),
                    owner[ea[0]],
                    owner[f[0]],
                )
            }
        };
        return Err(SimError::ContactAtStart {
            bodies: bodies_label(a, b),
            first,
            second,
            distance: 0.0,
            activation: distance,
        });
    }
    let mut stencils = Vec::new();
    CandidateFinder::default().find(
        &collision_mesh,
        positions,
        None,
        distance,
        contact.self_contact,
        &mut stencils,
    );
    let closest = stencils
        .iter()
        .map(|s| (s, s.distance_squared(positions)))
        .filter(|(_, d2)| *d2 < distance * distance)
        .min_by(|a, b| a.1.total_cmp(&b.1));
    if let Some((stencil, d2)) = closest {
        return Err(contact_at_start(
            stencil,
            d2.max(0.0).sqrt(),
            distance,
            owner,
        ));
    }
    if let Some(c) = first_contained_body(&collision_mesh, positions) {
        return Err(SimError::BodyInsideBody {
            inner: c.inner,
            outer: c.outer,
            vertex: c.vertex,
        });
    }
    let settings = ContactSettings {
        activation_distance: distance,
        stiffness: contact.stiffness,
        self_contact: contact.self_contact,
    };
    Ok(ContactBarrier::new(
        collision_mesh,
        settings,
        masses,
        diagonal,
        positions,
    ))
}

/// The error for a stencil that starts within `d_hat`, naming its bodies and primitives.
fn contact_at_start(
    stencil: &ContactStencil,
    distance: f64,
    activation: f64,
    owner: &[usize],
) -> SimError {
    let v = stencil.vertices;
    let (first, second, body_a, body_b) = match stencil.kind {
        StencilKind::PointEdge => (
            format!("vertex {}", v[0]),
            format!("edge ({}, {})", v[1], v[2]),
            owner[v[0]],
            owner[v[1]],
        ),
        StencilKind::PointTriangle => (
            format!("vertex {}", v[0]),
            format!("triangle ({}, {}, {})", v[1], v[2], v[3]),
            owner[v[0]],
            owner[v[1]],
        ),
        StencilKind::EdgeEdge => (
            format!("edge ({}, {})", v[0], v[1]),
            format!("edge ({}, {})", v[2], v[3]),
            owner[v[0]],
            owner[v[2]],
        ),
    };
    SimError::ContactAtStart {
        bodies: bodies_label(body_a, body_b),
        first,
        second,
        distance,
        activation,
    }
}

/// "body 0 and body 1", or "parts of body 0 ..." when both are one body.
fn bodies_label(a: usize, b: usize) -> String {
    if a == b {
        format!("parts of body {a} (its surface self-intersects or folds within d_hat)")
    } else {
        format!("body {} and body {}", a.min(b), a.max(b))
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
