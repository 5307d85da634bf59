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
//! The order of every list is deterministic (the boundary's order, edges
//! sorted), so the candidate lists built from it are too.

use crate::math::Vector;
use crate::mesh::Mesh;

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
}

impl CollisionMesh {
    /// The collision mesh of `mesh`, whose vertex `v` belongs to body `body_of_vertex[v]`.
    ///
    /// # Panics
    /// When `body_of_vertex` does not have one entry per vertex, or `D` is neither 2 nor 3.
    pub fn new<const D: usize>(mesh: &Mesh<D>, body_of_vertex: &[usize]) -> Self {
        assert_eq!(body_of_vertex.len(), mesh.vertex_count());
        assert!(D == 2 || D == 3, "contact is defined in 2D and 3D");
        let boundary = mesh.boundary();
        let mut edges: Vec<[usize; 2]> = Vec::new();
        let mut faces: Vec<[usize; 3]> = Vec::new();
        if D == 2 {
            edges.extend(boundary.iter().map(|f| [f.vertices[0], f.vertices[1]]));
        } else {
            faces.extend(
                boundary
                    .iter()
                    .map(|f| [f.vertices[0], f.vertices[1], f.vertices[2]]),
            );
            edges.extend(faces.iter().flat_map(|t| {
                [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]].map(|[a, b]| [a.min(b), a.max(b)])
            }));
            edges.sort_unstable();
            edges.dedup();
        }
        let mut on_surface = vec![false; mesh.vertex_count()];
        for &v in edges.iter().flatten() {
            on_surface[v] = true;
        }
        let vertices: Vec<usize> = (0..mesh.vertex_count())
            .filter(|&v| on_surface[v])
            .collect();
        let mut surface_index = vec![None; mesh.vertex_count()];
        for (s, &v) in vertices.iter().enumerate() {
            surface_index[v] = Some(s);
        }
        let rest = mesh.rest_positions();
        Self {
            vertex_body: vertices.iter().map(|&v| body_of_vertex[v]).collect(),
            edge_body: edges.iter().map(|e| body_of_vertex[e[0]]).collect(),
            face_body: faces.iter().map(|f| body_of_vertex[f[0]]).collect(),
            edge_rest_length_squared: edges
                .iter()
                .map(|e| distance_squared(&rest[e[0]], &rest[e[1]]))
                .collect(),
            vertices,
            surface_index,
            edges,
            faces,
        }
    }

    /// The number of bodies with a surface (one more than the largest body index).
    pub fn body_count(&self) -> usize {
        self.vertex_body.iter().max().map_or(0, |b| b + 1)
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
