//! The contact-related terms of a simulation: the ground barrier, the contact barrier over bodies and obstacles, and friction; each refused when the scene starts in contact.

use super::{Effects, SimError};
use crate::contact::{
    CandidateFinder, CollisionMesh, ContactStencil, ObstacleSurface, StencilKind, SurfaceCrossing,
    first_contained_body, first_surface_crossing,
};
use crate::energy::{ContactBarrier, ContactSettings, Friction, FrictionSettings, GroundBarrier};
use crate::math::Vector;
use crate::mesh::Mesh;

/// Friction's default velocity threshold `eps_v`, per second, as a fraction
/// of the bodies' bounding-box diagonal.
pub const DEFAULT_FRICTION_VELOCITY: f64 = 1e-3;

fn invalid(key: &'static str, reason: impl Into<String>) -> SimError {
    SimError::InvalidSetting {
        key,
        reason: reason.into(),
    }
}

/// What collides: the bodies' mesh, every simulation vertex's body
/// (obstacle `k` is body `body_count + k`, its points after the bodies'
/// vertices) and the obstacles' surfaces.
pub(super) struct Colliding<'a, const D: usize> {
    pub mesh: &'a Mesh<D>,
    pub owner: &'a [usize],
    pub body_count: usize,
    pub obstacles: Vec<ObstacleSurface<'a, D>>,
}

/// The ground's barrier for the bodies' vertices at `positions` (none on or
/// below the plane) with their `masses` and `velocities`.
pub(super) fn ground_barrier<const D: usize>(
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
pub(super) fn friction_term<const D: usize>(
    effects: &Effects<D>,
    positions: &[Vector<D>],
    velocity_threshold: Option<f64>,
) -> Result<Option<Friction<D>>, SimError> {
    let contact = effects.contact.map_or(0.0, |c| c.friction);
    let ground = effects.ground.map_or(0.0, |g| g.friction);
    let obstacles = effects.obstacles.iter().filter_map(|o| o.friction);
    for (key, mu) in [("contact", contact), ("ground", ground)]
        .into_iter()
        .chain(obstacles.clone().map(|mu| ("obstacles", mu)))
    {
        if !(mu >= 0.0 && mu.is_finite()) {
            return Err(invalid(
                key,
                format!("the friction coefficient must be 0 or more and finite, got {mu}"),
            ));
        }
    }
    let obstacle_friction = effects.contact.is_some() && obstacles.clone().any(|mu| mu > 0.0);
    if contact == 0.0 && ground == 0.0 && !obstacle_friction {
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

/// The contact term of the bodies and obstacles at their rest `positions`
/// (the bodies' vertices first, `body_vertices` of them, with `masses`),
/// refused when two surface primitives start closer than `d_hat` (bodies
/// or an obstacle and a body that start intersecting or touching).
pub(super) fn contact_barrier<const D: usize>(
    colliding: Colliding<D>,
    masses: &[f64],
    positions: &[Vector<D>],
    body_vertices: usize,
    contact: super::Contact,
) -> Result<ContactBarrier<D>, SimError> {
    let Colliding {
        mesh,
        owner,
        body_count,
        obstacles,
    } = colliding;
    let diagonal = bounding_box_diagonal(&positions[..body_vertices]);
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
    let collision_mesh =
        CollisionMesh::with_obstacles(mesh, &owner[..mesh.vertex_count()], &obstacles);
    let bodies_label = |a: usize, b: usize| bodies_label(a, b, body_count);
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
            body_count,
        ));
    }
    if let Some(c) = first_contained_body(&collision_mesh, positions) {
        return Err(SimError::BodyInsideBody {
            inner: body_name(c.inner, body_count),
            outer: body_name(c.outer, body_count),
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
    body_count: usize,
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
        bodies: bodies_label(body_a, body_b, body_count),
        first,
        second,
        distance,
        activation,
    }
}

/// "body 0 and body 1", "body 0 and obstacle 1" (obstacle `k` is body
/// `body_count + k`), or "parts of body 0 ..." when both are one body.
fn bodies_label(a: usize, b: usize, body_count: usize) -> String {
    if a == b {
        format!("parts of body {a} (its surface self-intersects or folds within d_hat)")
    } else {
        format!(
            "{} and {}",
            body_name(a.min(b), body_count),
            body_name(a.max(b), body_count)
        )
    }
}

/// "body 3", or "obstacle 1 (obstacles[1])" for body `body_count + 1`.
fn body_name(body: usize, body_count: usize) -> String {
    match body.checked_sub(body_count) {
        Some(k) => format!("obstacle {k} (obstacles[{k}])"),
        None => format!("body {body}"),
    }
}
