//! The contact-related terms of a simulation: the ground barrier, the contact barrier over bodies and obstacles, and friction.
//!
//! Their settings come validated (the scene validator checks every value
//! and, on the built meshes, that nothing starts on the ground or in
//! contact: `start_problem.rs`); these builders trust them.

use super::Effects;
use crate::contact::{CollisionMesh, ObstacleSurface};
use crate::energy::{ContactBarrier, ContactSettings, Friction, FrictionSettings, GroundBarrier};
use crate::math::Vector;
use crate::mesh::Mesh;

/// Friction's default velocity threshold `eps_v`, per second, as a fraction
/// of the bodies' bounding-box diagonal.
pub const DEFAULT_FRICTION_VELOCITY: f64 = 1e-3;

/// What collides: the bodies' mesh, every simulation vertex's body
/// (obstacle `k` is body `b + k` for `b` bodies, its points after the
/// bodies' vertices) and the obstacles' surfaces.
pub(super) struct Colliding<'a, const D: usize> {
    pub mesh: &'a Mesh<D>,
    pub owner: &'a [usize],
    pub obstacles: Vec<ObstacleSurface<'a, D>>,
}

/// The ground's barrier for the bodies' vertices at `positions` (none on or
/// below the plane: the validator refuses such a scene) with their `masses`
/// and `velocities`.
pub(super) fn ground_barrier<const D: usize>(
    ground: super::Ground,
    masses: &[f64],
    positions: &[Vector<D>],
    velocities: &[Vector<D>],
    gravity: Option<Vector<D>>,
) -> GroundBarrier {
    let barrier = GroundBarrier::for_bodies(
        ground.height,
        ground.activation_distance,
        ground.stiffness,
        masses,
        positions,
        velocities,
        gravity,
    );
    debug_assert!(
        barrier.first_vertex_below(positions).is_none(),
        "a vertex starts on or below the ground: the scene validator lets no such scene through"
    );
    barrier
}

/// The friction term, if the ground or the contact has a coefficient above
/// 0 (and exists): with the velocity threshold given, or 1e-3 times the
/// bounding-box diagonal of the bodies at `positions` per second.
pub(super) fn friction_term<const D: usize>(
    effects: &Effects<D>,
    positions: &[Vector<D>],
    velocity_threshold: Option<f64>,
) -> Option<Friction<D>> {
    let contact = effects.contact.map_or(0.0, |c| c.friction);
    let ground = effects.ground.map_or(0.0, |g| g.friction);
    let obstacle_friction = effects.contact.is_some()
        && effects
            .obstacles
            .iter()
            .any(|o| o.friction.is_some_and(|mu| mu > 0.0));
    if contact == 0.0 && ground == 0.0 && !obstacle_friction {
        return None;
    }
    let velocity_threshold = velocity_threshold
        .unwrap_or_else(|| DEFAULT_FRICTION_VELOCITY * bounding_box_diagonal(positions));
    Some(Friction::new(FrictionSettings {
        contact,
        ground,
        velocity_threshold,
    }))
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

/// The contact distance `d_hat`: the scene's, or 1e-3 times the bounding
/// box diagonal of the bodies' vertices at `positions`.
pub(super) fn contact_distance<const D: usize>(
    contact: super::Contact,
    positions: &[Vector<D>],
) -> f64 {
    contact
        .distance
        .unwrap_or_else(|| 1e-3 * bounding_box_diagonal(positions))
}

/// The contact term of the bodies and obstacles at their rest `positions`
/// (the bodies' vertices first, `body_vertices` of them, with `masses`),
/// which start apart (the validator asks [`super::start_problem`]).
pub(super) fn contact_barrier<const D: usize>(
    colliding: Colliding<D>,
    masses: &[f64],
    positions: &[Vector<D>],
    body_vertices: usize,
    contact: super::Contact,
) -> ContactBarrier<D> {
    let Colliding {
        mesh,
        owner,
        obstacles,
    } = colliding;
    let diagonal = bounding_box_diagonal(&positions[..body_vertices]);
    let collision_mesh =
        CollisionMesh::with_obstacles(mesh, &owner[..mesh.vertex_count()], &obstacles);
    let settings = ContactSettings {
        activation_distance: contact_distance(contact, &positions[..body_vertices]),
        stiffness: contact.stiffness,
        self_contact: contact.self_contact,
    };
    ContactBarrier::new(collision_mesh, settings, masses, diagonal, positions)
}
