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

    #[test]
    fn the_bodies_vertices_end_where_the_first_obstacles_begins() {
        let mut view = RenderMesh {
            dimension: 2,
            triangles: vec![[0, 1, 2]],
            triangle_element: vec![0],
            edges: vec![[0, 1], [1, 2], [0, 2]],
            element_count: 1,
            obstacle_triangles: Vec::new(),
            obstacle_edges: Vec::new(),
        };
        assert_eq!(view.body_vertices(3), 3, "no obstacle");
        view.add_obstacle(4, &[[0, 1]], &[]);
        assert_eq!(view.body_vertices(6), 4, "an outline from vertex 4");
        view.add_obstacle::<2>(3, &[], &[[0, 1, 2]]);
        assert_eq!(view.body_vertices(7), 3, "a fill from vertex 3");
    }
}
