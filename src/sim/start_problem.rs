//! Whether the bodies and obstacles of a scene can start in contact: no two
//! surface primitives closer than the contact distance `d_hat` (crossing
//! surfaces among them), and no body wholly inside another or an obstacle.
//!
//! The scene validator asks [`start_problem`] once, on the built meshes,
//! and reports a [`StartProblem`] at the scene key of the body or obstacle
//! it names; [`Simulation::with_bodies`](super::Simulation::with_bodies)
//! trusts that the check was made and builds the contact barrier without
//! repeating it.

use super::contact_setup::contact_distance;
use super::{Body, Effects, SimError};
use crate::contact::{
    CandidateFinder, CollisionMesh, ContactStencil, ObstacleSurface, StencilKind, SurfaceCrossing,
    first_contained_body, first_surface_crossing,
};
use crate::mesh::Mesh;
use std::borrow::Cow;

/// A body or an obstacle of a scene, by its index in the scene's list.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Collider {
    /// `bodies[i]` (the one body of a `[mesh]` scene is body 0).
    Body(usize),
    /// `obstacles[k]`.
    Obstacle(usize),
}

impl std::fmt::Display for Collider {
    /// `body 3`, or `obstacle 1 (obstacles[1])`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Collider::Body(b) => write!(f, "body {b}"),
            Collider::Obstacle(k) => write!(f, "obstacle {k} (obstacles[{k}])"),
        }
    }
}

/// Why the bodies and obstacles cannot start as placed (bad input).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StartProblem {
    /// Two surface primitives start closer than the contact distance (or
    /// crossing): colliders that start intersecting or touching.
    #[error(
        "{} start {distance:.3e} apart ({first} and {second}), closer than the contact \
         distance d_hat = {activation:.3e}: contact needs every pair of surface primitives \
         farther apart than d_hat at the start (move the bodies apart, or lower \
         effects.contact.distance)",
        pair_label(.colliders)
    )]
    TooClose {
        /// The two colliders, in scene order (the same one twice when a
        /// body's own surface crosses or folds).
        colliders: [Collider; 2],
        /// The first primitive ("vertex 12"; simulation vertex numbers).
        first: String,
        /// The second primitive ("triangle (3, 4, 7)").
        second: String,
        /// Their distance (0 where they cross).
        distance: f64,
        /// `d_hat`.
        activation: f64,
    },
    /// A body starts wholly inside another body or an obstacle, or an
    /// obstacle inside a body (no surfaces cross, but one encloses the other).
    #[error(
        "{inner} starts inside {outer} (its surface vertex {vertex} is enclosed by the surface \
         of {outer}): contact needs them apart at the start; move {inner} out"
    )]
    Inside {
        /// The enclosed collider.
        inner: Collider,
        /// The enclosing one.
        outer: Collider,
        /// A surface vertex of the enclosed one (a simulation vertex number).
        vertex: usize,
    },
}

/// "body 0 and body 1", "body 0 and obstacle 1 (obstacles[1])", or "parts
/// of body 0 ..." when both are one body.
fn pair_label(colliders: &[Collider; 2]) -> String {
    let [a, b] = *colliders;
    if a == b {
        format!("parts of {a} (its surface self-intersects or folds within d_hat)")
    } else {
        format!("{} and {}", a.min(b), a.max(b))
    }
}

/// The bodies' meshes joined into one (vertices and elements in body
/// order), borrowed when there is one body.
pub(super) fn joined_mesh<const D: usize>(
    bodies: &[Body<D>],
) -> Result<Cow<'_, Mesh<D>>, SimError> {
    if let [body] = bodies {
        return Ok(Cow::Borrowed(&body.mesh));
    }
    let mut positions = Vec::new();
    let mut simplices = Vec::new();
    for body in bodies {
        let offset = positions.len();
        positions.extend_from_slice(body.mesh.rest_positions());
        simplices.extend(
            body.mesh
                .simplices()
                .map(|s| s.iter().map(|v| v + offset).collect::<Vec<_>>()),
        );
    }
    Mesh::new(positions, simplices)
        .map(Cow::Owned)
        .map_err(|e| SimError::SetupFailure {
            reason: e.to_string(),
        })
}

/// What keeps `bodies` (at rest) and the obstacles of `effects` from
/// starting under its contact, if anything; nothing without
/// `[effects.contact]`. The first problem found, in this order: crossing
/// surfaces, primitives within `d_hat`, a collider inside another.
pub fn start_problem<const D: usize>(
    bodies: &[Body<D>],
    effects: &Effects<D>,
) -> Result<Option<StartProblem>, SimError> {
    let Some(contact) = effects.contact else {
        return Ok(None);
    };
    let mesh = joined_mesh(bodies)?;
    // Every vertex's collider index: bodies first, obstacle `k` after them.
    let mut owner: Vec<usize> = Vec::new();
    for (b, body) in bodies.iter().enumerate() {
        owner.extend(std::iter::repeat_n(b, body.mesh.vertex_count()));
    }
    let mut positions = mesh.rest_positions().to_vec();
    let body_vertices = positions.len();
    let mut surfaces = Vec::with_capacity(effects.obstacles.len());
    for (k, obstacle) in effects.obstacles.iter().enumerate() {
        let points = obstacle.surface.points();
        surfaces.push(ObstacleSurface {
            surface: &obstacle.surface,
            offset: positions.len(),
            friction: obstacle.friction,
        });
        positions.extend_from_slice(points);
        owner.extend(std::iter::repeat_n(bodies.len() + k, points.len()));
    }
    let collider = |index: usize| match index.checked_sub(bodies.len()) {
        Some(k) => Collider::Obstacle(k),
        None => Collider::Body(index),
    };
    let distance = contact_distance(contact, &positions[..body_vertices]);
    let collision_mesh = CollisionMesh::with_obstacles(&mesh, &owner[..body_vertices], &surfaces);
    if let Some(crossing) =
        first_surface_crossing(&collision_mesh, &positions, contact.self_contact)
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
        return Ok(Some(StartProblem::TooClose {
            colliders: [collider(a), collider(b)],
            first,
            second,
            distance: 0.0,
            activation: distance,
        }));
    }
    let mut stencils = Vec::new();
    CandidateFinder::default().find(
        &collision_mesh,
        &positions,
        None,
        distance,
        contact.self_contact,
        &mut stencils,
    );
    let closest = stencils
        .iter()
        .map(|s| (s, s.distance_squared(&positions)))
        .filter(|(_, d2)| *d2 < distance * distance)
        .min_by(|a, b| a.1.total_cmp(&b.1));
    if let Some((stencil, d2)) = closest {
        let (first, second, a, b) = stencil_primitives(stencil, &owner);
        return Ok(Some(StartProblem::TooClose {
            colliders: [collider(a), collider(b)],
            first,
            second,
            distance: d2.max(0.0).sqrt(),
            activation: distance,
        }));
    }
    Ok(
        first_contained_body(&collision_mesh, &positions).map(|c| StartProblem::Inside {
            inner: collider(c.inner),
            outer: collider(c.outer),
            vertex: c.vertex,
        }),
    )
}

/// A stencil's two primitives ("vertex 3", "edge (4, 5)") and the colliders
/// (vertex owners) they belong to.
fn stencil_primitives(stencil: &ContactStencil, owner: &[usize]) -> (String, String, usize, usize) {
    let v = stencil.vertices;
    match stencil.kind {
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
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{MaterialModel, YoungPoisson};
    use crate::math::Vector;
    use crate::sim::Contact;

    fn body(low: [f64; 2], high: [f64; 2]) -> Body<2> {
        Body {
            mesh: Mesh::axis_aligned_box(low.into(), high.into(), [2, 2]).unwrap(),
            material: MaterialModel::NeoHookean.with_lame(
                YoungPoisson {
                    young: 100.0,
                    poisson: 0.3,
                }
                .into(),
            ),
            density: 1.0,
            velocity: Vector::<2>::zeros(),
            pinned: None,
        }
    }

    fn with_contact(distance: f64) -> Effects<2> {
        Effects {
            contact: Some(Contact {
                distance: Some(distance),
                stiffness: None,
                self_contact: true,
                friction: 0.0,
            }),
            ..Effects::default()
        }
    }

    #[test]
    fn bodies_apart_start_and_close_or_nested_ones_are_named() {
        let low = body([0.0, 0.0], [1.0, 1.0]);
        let apart = body([0.0, 1.5], [1.0, 2.5]);
        let close = body([0.0, 1.001], [1.0, 2.0]);
        let nested = body([0.4, 0.4], [0.6, 0.6]);
        let effects = with_contact(0.01);
        assert_eq!(
            start_problem(&[low.clone(), apart], &effects).unwrap(),
            None
        );
        let problem = start_problem(&[low.clone(), close.clone()], &effects)
            .unwrap()
            .expect("closer than d_hat");
        let StartProblem::TooClose {
            colliders,
            distance,
            ..
        } = &problem
        else {
            panic!("{problem}")
        };
        assert_eq!(*colliders, [Collider::Body(0), Collider::Body(1)]);
        assert!((distance - 1e-3).abs() < 1e-9, "{distance}");
        assert!(
            problem
                .to_string()
                .starts_with("body 0 and body 1 start 1.000e-3 apart")
        );
        let problem = start_problem(&[low.clone(), nested], &effects)
            .unwrap()
            .expect("inside");
        assert_eq!(
            problem.to_string(),
            "body 1 starts inside body 0 (its surface vertex 9 is enclosed by the surface of \
             body 0): contact needs them apart at the start; move body 1 out"
        );
        // Without contact nothing is checked.
        assert_eq!(
            start_problem(&[low, close], &Effects::default()).unwrap(),
            None
        );
    }
}
