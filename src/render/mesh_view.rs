//! What the renderer sees of a simulation mesh: triangles to fill, the element
//! that colours each, edges to draw; and frames converted to `f32`.
//!
//! 2D: every triangle of the mesh, and every unique mesh edge.
//! 3D: the outward-oriented boundary triangles of the tetrahedral mesh, each
//! coloured by the tetrahedron it bounds, and the unique edges of those
//! triangles. A simulation mesh has no obstacles; they are added to the
//! view by whoever has them.

use super::{RenderFrame, RenderMesh};
use crate::math::Vector;
use crate::mesh::Mesh;
use std::collections::BTreeSet;

impl RenderMesh {
    /// Builds the render view of a 2D triangle mesh or a 3D tetrahedral mesh.
    ///
    /// # Panics
    /// When `D` is neither 2 nor 3 (there is no such mesh in elasto).
    pub fn from_mesh<const D: usize>(mesh: &Mesh<D>) -> RenderMesh {
        let (triangles, triangle_element): (Vec<[u32; 3]>, Vec<u32>) = match D {
            2 => mesh
                .simplices()
                .enumerate()
                .map(|(element, s)| ([s[0] as u32, s[1] as u32, s[2] as u32], element as u32))
                .unzip(),
            3 => mesh
                .boundary()
                .iter()
                .map(|f| {
                    let [a, b, c] = [f.vertices[0], f.vertices[1], f.vertices[2]];
                    ([a as u32, b as u32, c as u32], f.element as u32)
                })
                .unzip(),
            _ => panic!("elasto renders 2D and 3D meshes, not {D}D ones"),
        };
        RenderMesh {
            dimension: D,
            edges: unique_edges(&triangles),
            triangles,
            triangle_element,
            element_count: mesh.element_count(),
            obstacle_triangles: Vec::new(),
            obstacle_edges: Vec::new(),
        }
    }

    /// Adds an obstacle to the view: a surface of `facets` (edges in 2D,
    /// triangles in 3D) and, in 2D, `fill` triangles over its points, whose
    /// point `i` is the frame's vertex `first_vertex + i` (obstacles' points
    /// follow the bodies' vertices). 2D: `fill` is shaded, `facets` are the
    /// outline; 3D: `facets` are shaded and their unique edges drawn.
    pub fn add_obstacle<const D: usize>(
        &mut self,
        first_vertex: usize,
        facets: &[[usize; D]],
        fill: &[[usize; 3]],
    ) {
        let at = |i: usize| (first_vertex + i) as u32;
        match D {
            2 => {
                self.obstacle_triangles
                    .extend(fill.iter().map(|t| t.map(at)));
                self.obstacle_edges
                    .extend(facets.iter().map(|f| [at(f[0]), at(f[1])]));
            }
            _ => {
                let triangles: Vec<[u32; 3]> = facets
                    .iter()
                    .map(|f| [at(f[0]), at(f[1]), at(f[2])])
                    .collect();
                self.obstacle_edges.extend(unique_edges(&triangles));
                self.obstacle_triangles.extend(triangles);
            }
        }
    }

    /// How many of a frame's `vertex_count` positions are the bodies': those
    /// before the first obstacle vertex.
    pub(super) fn body_vertices(&self, vertex_count: usize) -> usize {
        let obstacles = self.obstacle_triangles.iter().flatten();
        let first = obstacles.chain(self.obstacle_edges.iter().flatten()).min();
        first.map_or(vertex_count, |&v| (v as usize).min(vertex_count))
    }
}

/// The edges of `triangles`, each once, as `[low, high]` in ascending order.
fn unique_edges(triangles: &[[u32; 3]]) -> Vec<[u32; 2]> {
    let edges: BTreeSet<[u32; 2]> = triangles
        .iter()
        .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect();
    edges.into_iter().collect()
}

impl RenderFrame {
    /// Converts simulation positions and per-element values to a frame
    /// (single precision; z = 0 in 2D).
    pub fn from_positions<const D: usize>(
        positions: &[Vector<D>],
        element_values: &[f64],
    ) -> RenderFrame {
        RenderFrame {
            positions: positions
                .iter()
                .map(|p| std::array::from_fn(|c| if c < D { p[c] as f32 } else { 0.0 }))
                .collect(),
            element_values: element_values.iter().map(|&v| v as f32).collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Vector2, Vector3};

    #[test]
    fn square_2d_has_all_triangles_and_unique_edges() {
        let mesh =
            Mesh::<2>::axis_aligned_box(Vector2::zeros(), Vector2::new(2.0, 1.0), [2, 1]).unwrap();
        let view = RenderMesh::from_mesh(&mesh);
        assert_eq!(view.dimension, 2);
        assert_eq!(view.triangles.len(), 4);
        assert_eq!(view.triangle_element, vec![0, 1, 2, 3]);
        assert_eq!(view.element_count, 4);
        // 2x1 cells: 7 grid edges + 2 diagonals.
        assert_eq!(view.edges.len(), 9);
        assert!(view.edges.iter().all(|e| e[0] < e[1]));
    }

    #[test]
    fn obstacles_follow_the_bodies_vertices_with_their_own_triangles_and_edges() {
        let mesh =
            Mesh::<2>::axis_aligned_box(Vector2::zeros(), Vector2::new(1.0, 1.0), [1, 1]).unwrap();
        let mut view = RenderMesh::from_mesh(&mesh);
        // 2D: a quad outline of 4 facets, filled by 2 triangles, after 4 body vertices.
        view.add_obstacle(
            4,
            &[[0, 1], [1, 2], [2, 3], [3, 0]],
            &[[0, 1, 2], [0, 2, 3]],
        );
        assert_eq!(view.obstacle_triangles, vec![[4, 5, 6], [4, 6, 7]]);
        assert_eq!(view.obstacle_edges, vec![[4, 5], [5, 6], [6, 7], [7, 4]]);
        assert_eq!(view.body_vertices(8), 4);
        // 3D: a tetrahedron's 4 faces shaded, its 6 edges drawn once each.
        let mesh =
            Mesh::<3>::axis_aligned_box(Vector3::zeros(), Vector3::repeat(1.0), [1, 1, 1]).unwrap();
        let mut view = RenderMesh::from_mesh(&mesh);
        let faces = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
        view.add_obstacle(8, &faces, &[]);
        assert_eq!(view.obstacle_triangles[0], [8, 10, 9]);
        assert_eq!(view.obstacle_triangles.len(), 4);
        assert_eq!(
            view.obstacle_edges,
            vec![[8, 9], [8, 10], [8, 11], [9, 10], [9, 11], [10, 11]]
        );
        assert_eq!(view.body_vertices(12), 8);
    }

    #[test]
    fn cube_3d_boundary_is_closed_outward_and_owned() {
        let mesh =
            Mesh::<3>::axis_aligned_box(Vector3::zeros(), Vector3::repeat(1.0), [2, 2, 2]).unwrap();
        let view = RenderMesh::from_mesh(&mesh);
        assert_eq!(view.dimension, 3);
        // 6 faces x 2x2 squares x 2 triangles.
        assert_eq!(view.triangles.len(), 48);
        assert_eq!(view.element_count, 48);
        // Closed surface: V - E + F = 2 with V = 26 boundary vertices.
        assert_eq!(26 - view.edges.len() as i64 + 48, 2);
        let x = mesh.rest_positions();
        let centre = Vector3::repeat(0.5);
        for (t, &e) in view.triangles.iter().zip(&view.triangle_element) {
            let p = t.map(|i| x[i as usize]);
            let normal = (p[1] - p[0]).cross(&(p[2] - p[0]));
            let mid = (p[0] + p[1] + p[2]) / 3.0;
            assert!(
                normal.dot(&(mid - centre)) > 0.0,
                "triangle {t:?} points inward"
            );
            // The owning tetrahedron holds all three vertices.
            let simplex = mesh.simplex(e as usize);
            assert!(
                t.iter().all(|&v| simplex.contains(&(v as usize))),
                "{t:?} not in element {e}"
            );
        }
    }

    #[test]
    fn frame_from_2d_positions_pads_z() {
        let frame = RenderFrame::from_positions(&[Vector2::new(1.5, -2.0)], &[0.25]);
        assert_eq!(frame.positions, vec![[1.5, -2.0, 0.0]]);
        assert_eq!(frame.element_values, vec![0.25]);
    }
}
