//! An independent intersection checker for surfaces saved with
//! `--save-surface obj`, written apart from the solver's own distance code so
//! that a contact test does not grade the solver with the solver's maths.
//!
//! **Input.** The OBJ that `output::surface_writer` writes: `v x y z` (numbers
//! printed from `f32`, z = 0 in 2D), 3D boundary triangles `f a b c` with
//! outward normals, 2D boundary edges `l a b` with the body on the left. Only
//! boundary vertices are written and bodies are not labelled, so a body is a
//! connected component of the facets (vertices joined when a facet holds both).
//!
//! **Crossings** (every pair of facets that share no vertex, found through a
//! uniform grid of bounding boxes, so near-linear for surfaces of even size):
//! * 2D, segments ab and cd, with `orient(a, b, c) = (b − a) × (c − a)`:
//!   they cross properly when `orient(a,b,c)`, `orient(a,b,d)` have opposite
//!   signs and so have `orient(c,d,a)`, `orient(c,d,b)`; the point is
//!   `a + t (b − a)` with `t = orient(c,d,a) / (orient(c,d,a) − orient(c,d,b))`.
//!   They touch when an orientation is exactly 0 and that endpoint lies in the
//!   other segment's bounding box (this covers collinear overlap).
//! * 3D, edge pq against triangle abc, with the signed volume
//!   `orient3d(a, b, c, d) = ((b − a) × (c − a)) · (d − a)`: no contact when
//!   p and q lie strictly on one side of the plane (`orient3d(a,b,c,p)` and
//!   `orient3d(a,b,c,q)` of one strict sign); otherwise the line pq meets the
//!   closed triangle iff `orient3d(p,q,a,b)`, `orient3d(p,q,b,c)`,
//!   `orient3d(p,q,c,a)` are not of mixed strict signs. When p and q both lie
//!   in the plane, the test is done in 2D (dropping the axis of the largest
//!   normal component): an endpoint inside the triangle or a contact with one
//!   of its edges. Degenerate (zero-area) triangles are skipped.
//!
//! **Tolerance.** [`find_intersections`] uses 0: only exact contact *in the
//! saved numbers* counts, crossing or touching (an orientation exactly 0).
//! The coordinates are `f32`-rounded (spacing 1.2e-7 near 1), so two surfaces
//! 1e-7 apart in the solver stay apart in the file unless rounding puts them on
//! the same or opposite `f32`s; the checker judges the file, not the solver's
//! unrounded state. In 2D, orientations of `f32` inputs of similar size are
//! exact in `f64`; in 3D they are not (no robust predicates), which matters
//! only for contacts within a few `f32` ulps. [`find_intersections_within`]
//! also reports pairs closer than `tolerance` (segment–segment distance in 2D;
//! in 3D the edge–triangle distance, the least of the endpoint–triangle and
//! edge–edge distances); on a fine mesh, facets two rings apart can be closer
//! than a large tolerance, so keep it below the mesh size.
//!
//! **Containment** (one vertex, the lowest-numbered, per component, against
//! every other closed component). 2D: the winding number by signed crossings
//! (Sunday): a crossing number that counts an upward crossing with the point
//! on the left +1 and a downward crossing with it on the right −1, so that a
//! clockwise hole counts −1 where plain parity could not tell it from a body.
//! 3D: the generalised winding number `w(p) = Σ Ω / (4π)` over the triangles,
//! with the solid angle (van Oosterom–Strackee) of A = a − p, B, C:
//! `tan(Ω/2) = A·(B×C) / (|A||B||C| + (A·B)|C| + (B·C)|A| + (C·A)|B|)`.
//! A component is closed when its facets balance (2D: each vertex starts as
//! many edges as it ends; 3D: the directed edges equal their reverses as
//! multisets); the winding number means nothing otherwise, so open
//! components are never `outer`. A closed component with negative signed
//! area/volume is a hole (the inside wall of a hollow body, a separate
//! component): it is not tested as `inner`, and a vertex counts as inside only
//! when the winding numbers of all other closed components sum above 0.5, so
//! a body in a cavity (+1 − 1 = 0) is clean. Each component with w > 0.5 is
//! then reported as `outer`.
//!
//! **Obstacles** (`surfaces/obstacles_NNNN.obj`, see
//! [`SavedSurface::with_obstacles`]): their facets are appended to the
//! bodies' and marked, and every test above runs on the union with one rule
//! more: a pair of obstacle facets is never a problem (obstacles are rigid
//! and never collide with each other, so two may cross or touch), nor is an
//! obstacle component inside another. A body's facet crossing or touching an
//! obstacle's counts, and so does a body inside a closed obstacle or an
//! obstacle inside a body. An open obstacle (a bowl, a ramp) is never
//! `outer`: it has no inside, as for bodies.
//!
//! No crate: a mesh-boolean or BVH crate would be a second solver-grade
//! dependency for a test, and this module must stay std-only.

mod broad_phase;
mod containment;
mod geometry;
#[cfg(test)]
mod tests;

use broad_phase::{Aabb, overlapping_pairs};
use containment::containment;
use geometry::{
    edge_meets_triangle, flat, segment_contact_2d, segment_segment_closest,
    segment_triangle_distance,
};
use std::path::Path;

/// A saved boundary surface: vertices and either 2D segments or 3D triangles
/// (indices into vertices).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SavedSurface {
    /// Vertex positions (z = 0 in 2D).
    pub vertices: Vec<[f64; 3]>,
    /// 2D boundary edges, body on the left.
    pub segments: Vec<[usize; 2]>,
    /// 3D boundary triangles, counter-clockwise seen from outside.
    pub triangles: Vec<[usize; 3]>,
    /// The vertices from this index on are obstacles' (see
    /// [`Self::with_obstacles`]); `None`: bodies only.
    pub obstacles_from: Option<usize>,
}

impl SavedSurface {
    /// Reads an OBJ file: `v`, `l` (a polyline of n indices gives n − 1
    /// segments), `f` (`a`, `a/b`, `a//c`, `a/b/c`; polygons fanned into
    /// triangles); 1-based or negative (relative) indices; other lines ignored.
    pub fn read_obj(path: &Path) -> Result<Self, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        Self::parse_obj(&text).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Parses the text of an OBJ file, as [`Self::read_obj`].
    pub fn parse_obj(text: &str) -> Result<Self, String> {
        let mut surface = SavedSurface::default();
        for (number, line) in text.lines().enumerate() {
            let at = |what: String| format!("line {}: {what}", number + 1);
            let mut words = line.split_whitespace();
            let keyword = words.next();
            let rest: Vec<&str> = words.collect();
            match keyword {
                Some("v") => {
                    if rest.len() < 2 {
                        return Err(at(format!("`v` needs 2 or 3 numbers: `{line}`")));
                    }
                    let mut p = [0.0; 3];
                    for (c, word) in p.iter_mut().zip(&rest) {
                        *c = word
                            .parse::<f64>()
                            .ok()
                            .filter(|x| x.is_finite())
                            .ok_or_else(|| at(format!("bad coordinate `{word}`")))?;
                    }
                    surface.vertices.push(p);
                }
                Some(keyword @ ("l" | "f")) => {
                    let count = surface.vertices.len();
                    let indices = rest
                        .iter()
                        .map(|word| obj_index(word, count))
                        .collect::<Option<Vec<usize>>>()
                        .ok_or_else(|| at(format!("bad index in `{line}`")))?;
                    if keyword == "l" {
                        if indices.len() < 2 {
                            return Err(at("`l` needs 2 indices".into()));
                        }
                        surface
                            .segments
                            .extend(indices.windows(2).map(|w| [w[0], w[1]]));
                    } else {
                        if indices.len() < 3 {
                            return Err(at("`f` needs 3 indices".into()));
                        }
                        let fan = indices[1..].windows(2);
                        surface
                            .triangles
                            .extend(fan.map(|w| [indices[0], w[0], w[1]]));
                    }
                }
                _ => {}
            }
        }
        let count = surface.vertices.len();
        let used = surface.segments.iter().flatten();
        if let Some(&bad) = used
            .chain(surface.triangles.iter().flatten())
            .find(|&&i| i >= count)
        {
            return Err(format!("index {} past the {count} vertices", bad + 1));
        }
        Ok(surface)
    }

    /// The bodies' surface `self` with the obstacles' surface appended (as
    /// read from `obstacles_NNNN.obj`; its vertices follow the bodies', its
    /// facets marked as obstacles' by [`Self::obstacles_from`]), for
    /// [`find_intersections`] to check bodies against obstacles but not
    /// obstacles against each other.
    ///
    /// # Panics
    /// When `self` already has obstacles appended.
    pub fn with_obstacles(&self, obstacles: &SavedSurface) -> SavedSurface {
        assert!(self.obstacles_from.is_none(), "obstacles appended twice");
        let offset = self.vertices.len();
        let shift = |i: usize| i + offset;
        let mut joined = self.clone();
        joined.vertices.extend_from_slice(&obstacles.vertices);
        joined
            .segments
            .extend(obstacles.segments.iter().map(|s| s.map(shift)));
        joined
            .triangles
            .extend(obstacles.triangles.iter().map(|t| t.map(shift)));
        joined.obstacles_from = Some(offset);
        joined
    }

    /// Whether vertex `v` is an obstacle's.
    fn is_obstacle(&self, v: usize) -> bool {
        self.obstacles_from.is_some_and(|first| v >= first)
    }

    /// Connected components of the surface (bodies), by shared vertices:
    /// component index per vertex, numbered in order of their lowest vertex
    /// (a vertex in no facet is a component of its own).
    ///
    /// # Panics
    /// When a facet's index is past the vertices.
    pub fn components(&self) -> Vec<usize> {
        fn root(parent: &mut [usize], mut v: usize) -> usize {
            while parent[v] != v {
                parent[v] = parent[parent[v]];
                v = parent[v];
            }
            v
        }
        let mut parent: Vec<usize> = (0..self.vertices.len()).collect();
        let facets = self.segments.iter().map(|s| &s[..]);
        for facet in facets.chain(self.triangles.iter().map(|t| &t[..])) {
            for &v in &facet[1..] {
                let (a, b) = (root(&mut parent, facet[0]), root(&mut parent, v));
                parent[a.max(b)] = a.min(b);
            }
        }
        let mut number = vec![usize::MAX; self.vertices.len()];
        let mut count = 0;
        (0..self.vertices.len())
            .map(|v| {
                let r = root(&mut parent, v);
                if number[r] == usize::MAX {
                    number[r] = count;
                    count += 1;
                }
                number[r]
            })
            .collect()
    }
}

/// The 0-based index of an OBJ index word (`7`, `7/1`, `7//3`, `-1`).
fn obj_index(word: &str, vertex_count: usize) -> Option<usize> {
    let first: i64 = word.split('/').next()?.parse().ok()?;
    match first {
        0 => None,
        i if i > 0 => Some(i as usize - 1),
        i => vertex_count.checked_sub(i.unsigned_abs() as usize),
    }
}

/// What was found wrong.
#[derive(Debug, Clone, PartialEq)]
pub enum Intersection {
    /// 2D: two segments that share no vertex cross or touch (indices of the
    /// segments, `a < b`, and a point of contact, or the midpoint of the
    /// closest points when only within tolerance).
    SegmentsCross {
        /// The first segment.
        a: usize,
        /// The second segment.
        b: usize,
        /// Where they meet.
        at: [f64; 2],
    },
    /// 3D: an edge (vertex indices, ascending) of one triangle passes through
    /// or touches another triangle (or comes within tolerance); they share no
    /// vertex.
    EdgeThroughTriangle {
        /// The edge's vertices.
        edge: [usize; 2],
        /// The triangle's index.
        triangle: usize,
    },
    /// One component lies inside another (a vertex of `inner` inside the
    /// closed surface/curve of `outer`); components as [`SavedSurface::components`].
    Contained {
        /// The component inside.
        inner: usize,
        /// The closed component around it.
        outer: usize,
        /// The vertex of `inner` that was tested.
        vertex: usize,
    },
}

/// Every problem found, or empty: exact contact in the saved numbers
/// (tolerance 0, see the module doc), then containment. Deterministic.
///
/// # Panics
/// When a facet's index is past the vertices or a coordinate is not finite.
pub fn find_intersections(surface: &SavedSurface) -> Vec<Intersection> {
    find_intersections_within(surface, 0.0)
}

/// As [`find_intersections`], and facets that share no vertex and are closer
/// than `tolerance` count as touching.
///
/// # Panics
/// When a facet's index is past the vertices or a coordinate is not finite.
pub fn find_intersections_within(surface: &SavedSurface, tolerance: f64) -> Vec<Intersection> {
    let v = &surface.vertices;
    assert!(
        v.iter().flatten().all(|x| x.is_finite()),
        "a vertex is not finite"
    );
    let mut found = Vec::new();
    let boxes: Vec<Aabb> = surface
        .segments
        .iter()
        .map(|s| Aabb::of(s.map(|i| flat(v[i]))))
        .collect();
    for (i, j) in overlapping_pairs(&boxes, &boxes, tolerance) {
        let ([a, b], [c, d]) = (surface.segments[i], surface.segments[j]);
        if i >= j || a == c || a == d || b == c || b == d {
            continue;
        }
        if surface.is_obstacle(a) && surface.is_obstacle(c) {
            continue; // obstacles never collide with each other
        }
        let at = segment_contact_2d(v[a], v[b], v[c], v[d]).or_else(|| {
            let (distance, midpoint) =
                segment_segment_closest(flat(v[a]), flat(v[b]), flat(v[c]), flat(v[d]));
            (distance < tolerance).then_some([midpoint[0], midpoint[1]])
        });
        if let Some(at) = at {
            found.push(Intersection::SegmentsCross { a: i, b: j, at });
        }
    }
    let mut edges: Vec<[usize; 2]> = surface
        .triangles
        .iter()
        .flat_map(|&[a, b, c]| [[a, b], [b, c], [c, a]])
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect();
    edges.sort_unstable();
    edges.dedup();
    let edge_boxes: Vec<Aabb> = edges.iter().map(|e| Aabb::of(e.map(|i| v[i]))).collect();
    let triangle_boxes: Vec<Aabb> = surface
        .triangles
        .iter()
        .map(|t| Aabb::of(t.map(|i| v[i])))
        .collect();
    for (e, t) in overlapping_pairs(&edge_boxes, &triangle_boxes, tolerance) {
        let ([p, q], triangle) = (edges[e], surface.triangles[t]);
        if triangle.contains(&p) || triangle.contains(&q) {
            continue;
        }
        if surface.is_obstacle(p) && surface.is_obstacle(triangle[0]) {
            continue; // obstacles never collide with each other
        }
        let corners = triangle.map(|i| v[i]);
        if edge_meets_triangle(v[p], v[q], corners)
            || (tolerance > 0.0 && segment_triangle_distance(v[p], v[q], corners) < tolerance)
        {
            found.push(Intersection::EdgeThroughTriangle {
                edge: [p, q],
                triangle: t,
            });
        }
    }
    found.extend(containment(surface));
    found
}
