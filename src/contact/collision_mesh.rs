//! The collision mesh: the surface of every body of a scene, the primitives contact is made of.
//!
//! Contact acts between surface primitives only. From the simulation's mesh
//! (all bodies concatenated) the collision mesh keeps
//!
//! * in 2D the boundary edges and their vertices;
//! * in 3D the boundary triangles, their (unique) edges and their vertices;
//!
//! with the body each primitive belongs to, so that contact within a body
//! (self-contact) can be switched off, and the maps between simulation
//! vertices and surface vertices. Primitives name their corners by
//! *simulation* vertex ids, so a stencil reads positions straight from the
//! simulation's position array. The boundary is [`Mesh::boundary`], the one
//! place where elasto finds it.
//!
//! Obstacles (`sim::Obstacle`) are bodies of the collision mesh too, after
//! the bodies ([`CollisionMesh::with_obstacles`]): surfaces without volume,
//! possibly open, whose points follow the bodies' vertices in the position
//! array. They touch bodies, never each other, and may carry their own
//! friction coefficient.
//!
//! The order of every list is deterministic (the boundary's order, edges
//! sorted), so the candidate lists built from it are too.

use crate::math::Vector;
use crate::mesh::{Mesh, SurfaceMesh};

/// The surface primitives of all bodies of a simulation.
#[derive(Debug, Clone)]
pub struct CollisionMesh {
    vertices: Vec<usize>,
    surface_index: Vec<Option<usize>>,
    edges: Vec<[usize; 2]>,
    faces: Vec<[usize; 3]>,
    vertex_body: Vec<usize>,
    edge_body: Vec<usize>,
    face_body: Vec<usize>,
    edge_rest_length_squared: Vec<f64>,
    /// Bodies from this index on are obstacles (`usize::MAX`: none).
    first_obstacle: usize,
    /// Per obstacle, its friction coefficient (`None`: the contact's).
    obstacle_friction: Vec<Option<f64>>,
    /// Per body (obstacles included), whether its surface is closed.
    closed: Vec<bool>,
}

/// An obstacle's part of a collision mesh: its surface, whose point `i` is
/// simulation vertex `offset + i`, and its own friction coefficient.
#[derive(Debug, Clone, Copy)]
pub struct ObstacleSurface<'a, const D: usize> {
    /// Its facets and points.
    pub surface: &'a SurfaceMesh<D>,
    /// The simulation vertex of its point 0.
    pub offset: usize,
    /// Its friction coefficient (`None`: the contact's).
    pub friction: Option<f64>,
}

impl CollisionMesh {
    /// The collision mesh of `mesh`, whose vertex `v` belongs to body `body_of_vertex[v]`.
    ///
    /// # Panics
    /// When `body_of_vertex` does not have one entry per vertex, or `D` is neither 2 nor 3.
    pub fn new<const D: usize>(mesh: &Mesh<D>, body_of_vertex: &[usize]) -> Self {
        Self::with_obstacles(mesh, body_of_vertex, &[])
    }

    /// The collision mesh of `mesh`'s bodies (as [`Self::new`]) and of
    /// `obstacles`, whose points follow the mesh's vertices in the
    /// simulation's position array: obstacle `k` is body `b + k`, `b` the
    /// number of bodies. Obstacles touch bodies, never each other.
    ///
    /// # Panics
    /// As [`Self::new`], and when an obstacle's points do not follow the
    /// mesh's vertices and the obstacles before it.
    pub fn with_obstacles<const D: usize>(
        mesh: &Mesh<D>,
        body_of_vertex: &[usize],
        obstacles: &[ObstacleSurface<'_, D>],
    ) -> Self {
        assert_eq!(body_of_vertex.len(), mesh.vertex_count());
        assert!(D == 2 || D == 3, "contact is defined in 2D and 3D");
        let first_obstacle = body_of_vertex.iter().max().map_or(0, |b| b + 1);
        // Every facet with its body, and the rest position of every vertex.
        let mut facets: Vec<([usize; D], usize)> = mesh
            .boundary()
            .iter()
            .map(|f| (f.vertices, body_of_vertex[f.vertices[0]]))
            .collect();
        let mut rest: Vec<Vector<D>> = mesh.rest_positions().to_vec();
        let mut closed = vec![true; first_obstacle];
        for (k, obstacle) in obstacles.iter().enumerate() {
            assert_eq!(obstacle.offset, rest.len(), "obstacle {k}'s points follow");
            rest.extend_from_slice(obstacle.surface.points());
            facets.extend(
                obstacle
                    .surface
                    .facets()
                    .iter()
                    .map(|f| (f.map(|p| p + obstacle.offset), first_obstacle + k)),
            );
            closed.push(obstacle.surface.is_closed());
        }
        let vertex_count = rest.len();
        let mut owner: Vec<usize> = body_of_vertex.to_vec();
        for (k, obstacle) in obstacles.iter().enumerate() {
            owner.extend(std::iter::repeat_n(
                first_obstacle + k,
                obstacle.surface.points().len(),
            ));
        }
        let mut edges: Vec<[usize; 2]> = Vec::new();
        let mut faces: Vec<[usize; 3]> = Vec::new();
        if D == 2 {
            edges.extend(facets.iter().map(|(f, _)| [f[0], f[1]]));
        } else {
            faces.extend(facets.iter().map(|(f, _)| [f[0], f[1], f[2]]));
            edges.extend(faces.iter().flat_map(|t| {
                [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]].map(|[a, b]| [a.min(b), a.max(b)])
            }));
            edges.sort_unstable();
            edges.dedup();
        }
        let mut on_surface = vec![false; vertex_count];
        for &v in edges.iter().flatten() {
            on_surface[v] = true;
        }
        let vertices: Vec<usize> = (0..vertex_count).filter(|&v| on_surface[v]).collect();
        let mut surface_index = vec![None; vertex_count];
        for (s, &v) in vertices.iter().enumerate() {
            surface_index[v] = Some(s);
        }
        Self {
            vertex_body: vertices.iter().map(|&v| owner[v]).collect(),
            edge_body: edges.iter().map(|e| owner[e[0]]).collect(),
            face_body: faces.iter().map(|f| owner[f[0]]).collect(),
            edge_rest_length_squared: edges
                .iter()
                .map(|e| distance_squared(&rest[e[0]], &rest[e[1]]))
                .collect(),
            vertices,
            surface_index,
            edges,
            faces,
            first_obstacle: if obstacles.is_empty() {
                usize::MAX
            } else {
                first_obstacle
            },
            obstacle_friction: obstacles.iter().map(|o| o.friction).collect(),
            closed,
        }
    }

    /// The number of bodies with a surface (one more than the largest body index).
    pub fn body_count(&self) -> usize {
        self.vertex_body.iter().max().map_or(0, |b| b + 1)
    }

    /// Whether body `body`'s surface is closed (every body's is; an
    /// obstacle's may be open: a ramp, a bowl).
    pub fn is_closed(&self, body: usize) -> bool {
        self.closed[body]
    }

    /// Whether body `body` is an obstacle.
    pub fn is_obstacle(&self, body: usize) -> bool {
        body >= self.first_obstacle
    }

    /// Whether primitives of bodies `a` and `b` can be in contact: never two
    /// obstacles' (nor one obstacle's own), parts of one body only with
    /// `self_contact`.
    pub fn may_touch(&self, a: usize, b: usize, self_contact: bool) -> bool {
        if self.is_obstacle(a) && self.is_obstacle(b) {
            return false;
        }
        self_contact || a != b
    }

    /// The friction coefficient of contact between bodies `a` and `b`: an
    /// obstacle's own where one of them is an obstacle that has one, else
    /// `contact`.
    pub fn friction_between(&self, a: usize, b: usize, contact: f64) -> f64 {
        [a, b]
            .into_iter()
            .filter(|&body| self.is_obstacle(body))
            .find_map(|body| self.obstacle_friction[body - self.first_obstacle])
            .unwrap_or(contact)
    }

    /// The body of simulation vertex `vertex`, if it is on the surface.
    pub fn body_of(&self, vertex: usize) -> Option<usize> {
        self.surface_index
            .get(vertex)
            .copied()
            .flatten()
            .map(|s| self.vertex_body[s])
    }

    /// Whether some friction coefficient of an obstacle is above 0.
    pub fn has_obstacle_friction(&self) -> bool {
        self.obstacle_friction
            .iter()
            .any(|mu| mu.is_some_and(|mu| mu > 0.0))
    }

    /// Surface vertices, as simulation vertex ids (ascending).
    pub fn vertices(&self) -> &[usize] {
        &self.vertices
    }

    /// The surface index of simulation vertex `vertex` (`None` inside a body).
    pub fn surface_index(&self, vertex: usize) -> Option<usize> {
        self.surface_index[vertex]
    }

    /// Surface edges (simulation vertex ids): the boundary in 2D, the edges of
    /// the boundary triangles in 3D (each once, its smaller id first).
    pub fn edges(&self) -> &[[usize; 2]] {
        &self.edges
    }

    /// Boundary triangles (simulation vertex ids, outward); empty in 2D.
    pub fn faces(&self) -> &[[usize; 3]] {
        &self.faces
    }

    /// The body of surface vertex `s` (an index into [`Self::vertices`]).
    pub fn vertex_body(&self, s: usize) -> usize {
        self.vertex_body[s]
    }

    /// The body of edge `e`.
    pub fn edge_body(&self, e: usize) -> usize {
        self.edge_body[e]
    }

    /// The body of face `f`.
    pub fn face_body(&self, f: usize) -> usize {
        self.face_body[f]
    }

    /// `|e1 - e0|^2` of edge `e` at rest (the edge-edge mollifier's scale).
    pub fn edge_rest_length_squared(&self, e: usize) -> f64 {
        self.edge_rest_length_squared[e]
    }
}

fn distance_squared<const D: usize>(a: &Vector<D>, b: &Vector<D>) -> f64 {
    (a - b).norm_squared()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_of_two_by_two_cells_has_eight_boundary_edges_and_vertices() {
        let mesh =
            Mesh::axis_aligned_box(Vector::<2>::zeros(), Vector::<2>::repeat(1.0), [2, 2]).unwrap();
        let surface = CollisionMesh::new(&mesh, &vec![0; mesh.vertex_count()]);
        assert_eq!(surface.edges().len(), 8);
        assert_eq!(surface.vertices().len(), 8);
        assert!(surface.faces().is_empty());
        // The centre vertex (1 of 9) is inside.
        let centre = (0..mesh.vertex_count())
            .find(|&v| (mesh.rest_positions()[v] - Vector::<2>::repeat(0.5)).norm() < 1e-12)
            .unwrap();
        assert_eq!(surface.surface_index(centre), None);
        assert!((surface.edge_rest_length_squared(0) - 0.25).abs() < 1e-15);
    }

    #[test]
    fn a_cube_surface_is_closed_and_its_edges_are_unique() {
        let mesh =
            Mesh::axis_aligned_box(Vector::<3>::zeros(), Vector::<3>::repeat(1.0), [2, 2, 2])
                .unwrap();
        let bodies: Vec<usize> = (0..mesh.vertex_count()).map(|v| v % 2).collect();
        let surface = CollisionMesh::new(&mesh, &bodies);
        // 6 sides of 2 x 2 squares, each split into 2 triangles.
        assert_eq!(surface.faces().len(), 48);
        // A closed triangulated surface: E = 3F/2, V = E - F + 2.
        assert_eq!(surface.edges().len(), 72);
        assert_eq!(surface.vertices().len(), 26);
        for (s, &v) in surface.vertices().iter().enumerate() {
            assert_eq!(surface.vertex_body(s), v % 2);
            assert_eq!(surface.surface_index(v), Some(s));
        }
    }
}
