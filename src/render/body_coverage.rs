//! The 2D body drawn without multisampling, anti-aliased by coverage
//! computed in its shaders (`shaders/body2d.wgsl`, and `vs_coverage` in
//! `shaders/line.wgsl` for the edge lines).
//!
//! On llvmpipe a 4x-multisampled tile of the default scene took about 2.3 ms
//! from submission to completion, and the same tile single-sampled about
//! 0.8 ms: the software rasteriser handles every sample of a multisampled
//! target on its slow path; and the golden images tell the two apart (the
//! report-drop-2d frames drawn with 4x MSAA measured a FLIP 99.9th
//! percentile of 0.112 against them, over the 0.1 limit, at the small
//! body's outline). So a 2D tile has one sample per pixel, and the shaders give
//! each pixel what a box filter over it would see:
//!
//! - a triangle's pixel, at distance `d_i` (pixels) inside the edge opposite
//!   its corner `i`, gives the part `o_i = clamp(1/2 − d_i, 0, 1)` beyond
//!   that edge to the neighbouring triangle's colour;
//! - a *fringe* quad along each boundary edge covers the pixels within half
//!   a pixel of it: at signed distance `s` outwards, a pixel outside gets
//!   the body's colour over `clamp(1/2 − s, 0, 1)` of it, a pixel inside
//!   the backdrop's over `clamp(1/2 + s, 0, 1)`. The fringe, not the
//!   triangle, does this, so that a triangle touching the boundary at a
//!   vertex only cannot leave its pixels there opaque;
//! - an edge line covers, per axis of the segment, the overlap of the pixel
//!   with its rectangle (square caps included).
//!
//! Each is exact for a straight edge and a box filter, and blending in the
//! sRGB target happens in linear light, as resolving samples did (the
//! tests check a straight edge's pixels against the area the body covers).
//! The approximations are where two edges meet within a pixel: at an
//! interior vertex the parts beyond two edges are mixed one after the
//! other; at a convex boundary corner the body's share inside is the
//! product of the two fringes' (as a box filter gives) and just outside the
//! corner no fringe reaches; at a reflex corner the inner strips miss a
//! sliver and the outer ones overlap.
//!
//! Here: the mesh's triangle adjacency, fixed for the run, and the
//! per-frame vertices and fringes built from it.

use super::RenderMesh;
use bytemuck::{Pod, Zeroable};
use std::collections::HashMap;

/// One corner of a body triangle (2D tiles).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(super) struct BodyVertex {
    pub position: [f32; 2],
    /// The barycentric unit vector of this corner.
    pub corner: [f32; 3],
    /// The triangle's colour (linear).
    pub colour: [f32; 3],
    /// Per edge, opposite corner `i`: the colour across it (w = 1), or
    /// w = 0 for a boundary edge.
    pub across: [[f32; 4]; 3],
}

/// The pixels along one boundary edge (instanced).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(super) struct FringeInstance {
    pub start: [f32; 2],
    pub end: [f32; 2],
    /// A point on the body's side: the edge's triangle's third corner.
    pub inside: [f32; 2],
    pub colour: [f32; 3],
}

/// Marks an edge with no triangle across it.
const BOUNDARY: u32 = u32::MAX;

/// Which triangle lies across each edge of each triangle of a 2D mesh.
#[derive(Debug, Clone)]
pub(super) struct BodyTopology {
    /// Per triangle, the triangle across the edge opposite each corner, or
    /// [`BOUNDARY`].
    across: Vec<[u32; 3]>,
    /// The boundary edges: (triangle, corner opposite the edge).
    boundary: Vec<(u32, u8)>,
}

impl BodyTopology {
    /// The adjacency of `mesh`'s triangles. An edge of one triangle is on
    /// the boundary; an edge shared by more (a mesh that is not a manifold)
    /// is interior, and each of its triangles sees the next one round.
    pub fn new(mesh: &RenderMesh) -> Self {
        let mut sharing: HashMap<[u32; 2], Vec<(u32, u8)>> = HashMap::new();
        for (t, triangle) in mesh.triangles.iter().enumerate() {
            for corner in 0..3u8 {
                let c = usize::from(corner);
                let (a, b) = (triangle[(c + 1) % 3], triangle[(c + 2) % 3]);
                sharing
                    .entry([a.min(b), a.max(b)])
                    .or_default()
                    .push((t as u32, corner));
            }
        }
        let mut across = vec![[BOUNDARY; 3]; mesh.triangles.len()];
        let mut boundary = Vec::new();
        for sides in sharing.values() {
            if let [only] = sides.as_slice() {
                boundary.push(*only);
                continue;
            }
            for (k, &(t, corner)) in sides.iter().enumerate() {
                let (other, _) = sides[(k + 1) % sides.len()];
                across[t as usize][usize::from(corner)] = other;
            }
        }
        // The fringes' order does not change the image (they do not overlap
        // along an edge), but a fixed one keeps uploads reproducible.
        boundary.sort_unstable();
        BodyTopology { across, boundary }
    }

    /// Builds a frame's triangle corners and fringes from its `positions`
    /// and the colour of each triangle's element (`element_colours`).
    pub fn fill(
        &self,
        mesh: &RenderMesh,
        positions: &[[f32; 3]],
        element_colours: &[[f32; 3]],
        vertices: &mut Vec<BodyVertex>,
        fringes: &mut Vec<FringeInstance>,
    ) {
        let colour_of = |t: u32| element_colours[mesh.triangle_element[t as usize] as usize];
        let xy = |v: u32| {
            let p = positions[v as usize];
            [p[0], p[1]]
        };
        vertices.clear();
        for (t, (triangle, across)) in mesh.triangles.iter().zip(&self.across).enumerate() {
            let colour = colour_of(t as u32);
            let across = across.map(|other| match other {
                BOUNDARY => [0.0; 4],
                other => {
                    let [r, g, b] = colour_of(other);
                    [r, g, b, 1.0]
                }
            });
            for (c, &v) in triangle.iter().enumerate() {
                let mut corner = [0.0; 3];
                corner[c] = 1.0;
                vertices.push(BodyVertex {
                    position: xy(v),
                    corner,
                    colour,
                    across,
                });
            }
        }
        fringes.clear();
        fringes.extend(self.boundary.iter().map(|&(t, corner)| {
            let triangle = mesh.triangles[t as usize];
            let c = usize::from(corner);
            FringeInstance {
                start: xy(triangle[(c + 1) % 3]),
                end: xy(triangle[(c + 2) % 3]),
                inside: xy(triangle[c]),
                colour: colour_of(t),
            }
        }));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two triangles sharing the diagonal of the unit square.
    fn square() -> RenderMesh {
        RenderMesh {
            dimension: 2,
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            triangle_element: vec![0, 1],
            edges: vec![[0, 1], [1, 2], [0, 2], [2, 3], [0, 3]],
            element_count: 2,
            obstacle_triangles: Vec::new(),
            obstacle_edges: Vec::new(),
        }
    }

    #[test]
    fn the_shared_edge_is_across_and_the_others_are_fringes() {
        let mesh = square();
        let topology = BodyTopology::new(&mesh);
        // Triangle 0's edge opposite corner 1 (vertices 2, 0) is the diagonal.
        assert_eq!(
            topology.across,
            vec![[BOUNDARY, 1, BOUNDARY], [BOUNDARY, BOUNDARY, 0]]
        );
        assert_eq!(topology.boundary.len(), 4);

        let positions = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let colours = [[0.1, 0.2, 0.3], [0.7, 0.8, 0.9]];
        let (mut vertices, mut fringes) = (Vec::new(), Vec::new());
        topology.fill(&mesh, &positions, &colours, &mut vertices, &mut fringes);
        assert_eq!(vertices.len(), 6);
        assert_eq!(vertices[1].position, [1.0, 0.0]);
        assert_eq!(vertices[1].corner, [0.0, 1.0, 0.0]);
        assert_eq!(vertices[1].colour, colours[0]);
        assert_eq!(
            vertices[1].across,
            [[0.0; 4], [0.7, 0.8, 0.9, 1.0], [0.0; 4]]
        );
        assert_eq!(
            vertices[3].across,
            [[0.0; 4], [0.0; 4], [0.1, 0.2, 0.3, 1.0]]
        );

        // Every boundary edge once, with the third corner of its triangle inside.
        type Side = ([f32; 2], [f32; 2], [f32; 2], [f32; 3]);
        let mut sides: Vec<Side> = fringes
            .iter()
            .map(|f| (f.start, f.end, f.inside, f.colour))
            .collect();
        sides.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(
            sides,
            vec![
                ([0.0, 0.0], [1.0, 0.0], [1.0, 1.0], colours[0]),
                ([0.0, 1.0], [0.0, 0.0], [1.0, 1.0], colours[1]),
                ([1.0, 0.0], [1.0, 1.0], [0.0, 0.0], colours[0]),
                ([1.0, 1.0], [0.0, 1.0], [0.0, 0.0], colours[1]),
            ]
        );
    }
}
