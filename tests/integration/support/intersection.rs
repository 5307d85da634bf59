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
//! dependency for a test, and this file must stay std-only.

use std::collections::HashMap;
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

// ---- vectors -------------------------------------------------------------

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn along(a: [f64; 3], d: [f64; 3], t: f64) -> [f64; 3] {
    [a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]]
}
fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
/// The point with z dropped (2D segments are judged in the plane).
fn flat(a: [f64; 3]) -> [f64; 3] {
    [a[0], a[1], 0.0]
}
fn sign(x: f64) -> i8 {
    (x > 0.0) as i8 - (x < 0.0) as i8
}

// ---- 2D segments ---------------------------------------------------------

/// `(b − a) × (c − a)` in the xy-plane: > 0 when c is left of ab.
fn orient2d(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Whether c, known to be on the line ab, lies in the closed segment ab.
fn in_box(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> bool {
    (0..2).all(|k| a[k].min(b[k]) <= c[k] && c[k] <= a[k].max(b[k]))
}

/// A point common to the closed segments ab and cd (xy only), if any.
fn segment_contact_2d(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> Option<[f64; 2]> {
    let (abc, abd) = (orient2d(a, b, c), orient2d(a, b, d));
    let (cda, cdb) = (orient2d(c, d, a), orient2d(c, d, b));
    if sign(abc) * sign(abd) < 0 && sign(cda) * sign(cdb) < 0 {
        let p = along(a, sub(b, a), cda / (cda - cdb));
        return Some([p[0], p[1]]);
    }
    let touch = [
        (abc, a, b, c),
        (abd, a, b, d),
        (cda, c, d, a),
        (cdb, c, d, b),
    ];
    touch
        .into_iter()
        .find(|&(o, s, e, p)| o == 0.0 && in_box(s, e, p))
        .map(|(_, _, _, p)| [p[0], p[1]])
}

// ---- 3D edge against triangle --------------------------------------------

/// `((b − a) × (c − a)) · (d − a)`: six times the signed volume of abcd.
fn orient3d(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> f64 {
    dot(cross(sub(b, a), sub(c, a)), sub(d, a))
}

/// Whether the closed segment pq meets the closed triangle abc.
fn edge_meets_triangle(p: [f64; 3], q: [f64; 3], [a, b, c]: [[f64; 3]; 3]) -> bool {
    let normal = cross(sub(b, a), sub(c, a));
    if normal == [0.0; 3] {
        return false;
    }
    let (side_p, side_q) = (sign(dot(normal, sub(p, a))), sign(dot(normal, sub(q, a))));
    if side_p * side_q > 0 {
        return false;
    }
    let signs = [
        orient3d(p, q, a, b),
        orient3d(p, q, b, c),
        orient3d(p, q, c, a),
    ]
    .map(sign);
    // All three volumes zero: the edge lies in the triangle's plane, whatever
    // rounding made of `side_p` and `side_q` (a hair off zero): the 2D test.
    if (side_p == 0 && side_q == 0) || signs == [0; 3] {
        // Coplanar: work in the plane of the two axes other than the normal's largest.
        let drop = (0..3)
            .max_by(|&i, &j| normal[i].abs().total_cmp(&normal[j].abs()))
            .unwrap_or(2);
        let keep = |x: [f64; 3]| [x[(drop + 1) % 3], x[(drop + 2) % 3], 0.0];
        let (p, q, a, b, c) = (keep(p), keep(q), keep(a), keep(b), keep(c));
        let signs = [orient2d(a, b, p), orient2d(b, c, p), orient2d(c, a, p)].map(sign);
        let inside = !(signs.contains(&1) && signs.contains(&-1));
        return inside
            || [(a, b), (b, c), (c, a)]
                .iter()
                .any(|&(s, e)| segment_contact_2d(p, q, s, e).is_some());
    }
    !(signs.contains(&1) && signs.contains(&-1))
}

/// The point of segment ab closest to p.
fn point_segment_closest(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    let d = sub(b, a);
    let length2 = dot(d, d);
    let t = if length2 > 0.0 {
        (dot(sub(p, a), d) / length2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    along(a, d, t)
}

/// The distance between segments pq and rs and the midpoint of the closest
/// points: the least over the four endpoint–segment pairs and, when the lines
/// are not parallel, the interior stationary point of `|p + s(q−p) − r − t(s−r)|²`,
/// `s = (b e − c d) / (a c − b²)`, `t = (a e − b d) / (a c − b²)`.
fn segment_segment_closest(p: [f64; 3], q: [f64; 3], r: [f64; 3], s: [f64; 3]) -> (f64, [f64; 3]) {
    let pair = |x: [f64; 3], y: [f64; 3]| (norm(sub(x, y)), along(x, sub(y, x), 0.5));
    let mut best = [
        pair(p, point_segment_closest(p, r, s)),
        pair(q, point_segment_closest(q, r, s)),
        pair(r, point_segment_closest(r, p, q)),
        pair(s, point_segment_closest(s, p, q)),
    ]
    .into_iter()
    .min_by(|x, y| x.0.total_cmp(&y.0))
    .unwrap_or((f64::INFINITY, p));
    let (d1, d2, w) = (sub(q, p), sub(s, r), sub(p, r));
    let (a, b, c, d, e) = (
        dot(d1, d1),
        dot(d1, d2),
        dot(d2, d2),
        dot(d1, w),
        dot(d2, w),
    );
    let denominator = a * c - b * b;
    if denominator > 1e-14 * a * c {
        let (u, t) = ((b * e - c * d) / denominator, (a * e - b * d) / denominator);
        if (0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&t) {
            let interior = pair(along(p, d1, u), along(r, d2, t));
            if interior.0 < best.0 {
                best = interior;
            }
        }
    }
    best
}

/// The distance from p to triangle abc: to its plane when the foot falls
/// inside, else to the nearest edge.
fn point_triangle_distance(p: [f64; 3], [a, b, c]: [[f64; 3]; 3]) -> f64 {
    let normal = cross(sub(b, a), sub(c, a));
    let area2 = dot(normal, normal);
    if area2 > 0.0 {
        let height = dot(normal, sub(p, a)) / area2;
        let foot = along(p, normal, -height);
        let sides =
            [(a, b), (b, c), (c, a)].map(|(s, e)| dot(cross(sub(e, s), sub(foot, s)), normal));
        if sides.iter().all(|&x| x >= 0.0) {
            return height.abs() * area2.sqrt();
        }
    }
    [(a, b), (b, c), (c, a)]
        .map(|(s, e)| norm(sub(p, point_segment_closest(p, s, e))))
        .into_iter()
        .fold(f64::INFINITY, f64::min)
}

/// The distance between segment pq and triangle abc that it does not meet.
fn segment_triangle_distance(p: [f64; 3], q: [f64; 3], corners @ [a, b, c]: [[f64; 3]; 3]) -> f64 {
    let to_edges = [(a, b), (b, c), (c, a)].map(|(s, e)| segment_segment_closest(p, q, s, e).0);
    to_edges
        .into_iter()
        .chain([
            point_triangle_distance(p, corners),
            point_triangle_distance(q, corners),
        ])
        .fold(f64::INFINITY, f64::min)
}

// ---- broad phase -----------------------------------------------------------

/// An axis-aligned bounding box.
#[derive(Debug, Clone, Copy)]
struct Aabb {
    min: [f64; 3],
    max: [f64; 3],
}

impl Aabb {
    fn of<const N: usize>(points: [[f64; 3]; N]) -> Self {
        let pick =
            |k: usize, f: fn(f64, f64) -> f64| points.iter().map(|p| p[k]).fold(points[0][k], f);
        Aabb {
            min: std::array::from_fn(|k| pick(k, f64::min)),
            max: std::array::from_fn(|k| pick(k, f64::max)),
        }
    }
    fn union(self, o: Aabb) -> Aabb {
        Aabb {
            min: std::array::from_fn(|k| self.min[k].min(o.min[k])),
            max: std::array::from_fn(|k| self.max[k].max(o.max[k])),
        }
    }
    fn grown(self, margin: f64) -> Aabb {
        Aabb {
            min: self.min.map(|x| x - margin),
            max: self.max.map(|x| x + margin),
        }
    }
    fn extent(&self) -> f64 {
        (0..3)
            .map(|k| self.max[k] - self.min[k])
            .fold(0.0, f64::max)
    }
    fn overlaps(&self, o: &Aabb) -> bool {
        (0..3).all(|k| self.min[k] <= o.max[k] && o.min[k] <= self.max[k])
    }
}

/// The cells of an inclusive range of cell indices per axis.
fn cells_in([x, y, z]: [(i64, i64); 3]) -> impl Iterator<Item = [i64; 3]> {
    (x.0..=x.1)
        .flat_map(move |cx| (y.0..=y.1).flat_map(move |cy| (z.0..=z.1).map(move |cz| [cx, cy, cz])))
}

/// Every `(query, item)` whose boxes are within `margin`, sorted. The items
/// go into a uniform grid of cells about their mean size (doubled while they
/// would fill more than 16 cells each on average); each query looks only at
/// the cells its box covers.
fn overlapping_pairs(queries: &[Aabb], items: &[Aabb], margin: f64) -> Vec<(usize, usize)> {
    let grown: Vec<Aabb> = items.iter().map(|b| b.grown(margin)).collect();
    let Some(whole) = grown.iter().copied().reduce(Aabb::union) else {
        return Vec::new();
    };
    let mean = grown.iter().map(Aabb::extent).sum::<f64>() / grown.len() as f64;
    // At most ~1e6 cells per axis, so that indices stay small whatever the sizes.
    let mut cell = mean.max(whole.extent() * 1e-6);
    if !(cell > 0.0 && cell.is_finite()) {
        cell = 1.0;
    }
    // Cell indices of a box clipped to the items' box (so queries far out visit none).
    let range = |b: &Aabb, cell: f64| -> [(i64, i64); 3] {
        std::array::from_fn(|k| {
            let index = |x: f64| ((x - whole.min[k]) / cell).floor() as i64;
            (
                index(b.min[k].max(whole.min[k])),
                index(b.max[k].min(whole.max[k])),
            )
        })
    };
    let volume = |r: [(i64, i64); 3]| {
        r.iter()
            .map(|&(lo, hi)| (hi - lo + 1).max(0) as f64)
            .product::<f64>()
    };
    while grown.iter().map(|b| volume(range(b, cell))).sum::<f64>()
        > 16.0 * grown.len() as f64 + 1024.0
    {
        cell *= 2.0;
    }
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, b) in grown.iter().enumerate() {
        for key in cells_in(range(b, cell)) {
            grid.entry(key).or_default().push(i);
        }
    }
    let (mut pairs, mut candidates) = (Vec::new(), Vec::new());
    for (q, query) in queries.iter().enumerate() {
        candidates.clear();
        candidates.extend(
            cells_in(range(query, cell))
                .filter_map(|key| grid.get(&key))
                .flatten(),
        );
        candidates.sort_unstable();
        candidates.dedup();
        pairs.extend(
            candidates
                .iter()
                .filter(|&&i| query.overlaps(&grown[i]))
                .map(|&i| (q, i)),
        );
    }
    pairs
}

// ---- containment -----------------------------------------------------------

/// Components lying inside others (see the module doc).
fn containment(surface: &SavedSurface) -> Vec<Intersection> {
    let component = surface.components();
    let count = component.iter().max().map_or(0, |&c| c + 1);
    let v = &surface.vertices;
    let three_d = !surface.triangles.is_empty();
    let mut facets: Vec<Vec<Vec<usize>>> = vec![Vec::new(); count];
    if three_d {
        for t in &surface.triangles {
            facets[component[t[0]]].push(t.to_vec());
        }
    } else {
        for s in &surface.segments {
            facets[component[s[0]]].push(s.to_vec());
        }
    }
    let closed: Vec<bool> = facets
        .iter()
        .map(|f| !f.is_empty() && is_closed(f))
        .collect();
    let mut first_vertex = vec![usize::MAX; count];
    for (vertex, &c) in component.iter().enumerate().rev() {
        first_vertex[c] = vertex;
    }
    let winding = |p: [f64; 3], f: &[Vec<usize>]| {
        if three_d {
            winding_number_3d(p, f, v)
        } else {
            winding_number_2d(p, f, v)
        }
    };
    let mut found = Vec::new();
    for inner in (0..count).filter(|&c| !facets[c].is_empty()) {
        let vertex = first_vertex[inner];
        if closed[inner] && signed_measure(&facets[inner], v, v[vertex]) <= 0.0 {
            continue; // a hole: the inside wall of a hollow body
        }
        let obstacle = |c: usize| surface.is_obstacle(first_vertex[c]);
        let windings: Vec<(usize, f64)> = (0..count)
            .filter(|&outer| outer != inner && closed[outer])
            .filter(|&outer| !(obstacle(inner) && obstacle(outer)))
            .map(|outer| (outer, winding(v[vertex], &facets[outer])))
            .collect();
        if windings.iter().map(|w| w.1).sum::<f64>() > 0.5 {
            let outside_of = windings.iter().filter(|w| w.1 > 0.5);
            found.extend(outside_of.map(|&(outer, _)| Intersection::Contained {
                inner,
                outer,
                vertex,
            }));
        }
    }
    found
}

/// Whether oriented facets close up: 2D edges start at each vertex as often
/// as they end there; 3D directed edges equal their reverses as multisets.
fn is_closed(facets: &[Vec<usize>]) -> bool {
    let (mut forward, mut backward) = (Vec::new(), Vec::new());
    for f in facets {
        if f.len() == 2 {
            forward.push((f[0], 0));
            backward.push((f[1], 0));
        } else {
            for k in 0..f.len() {
                let (a, b) = (f[k], f[(k + 1) % f.len()]);
                forward.push((a, b));
                backward.push((b, a));
            }
        }
    }
    forward.sort_unstable();
    backward.sort_unstable();
    forward == backward
}

/// Signed area (2D, Σ (a × b) / 2) or volume (3D, Σ a · (b × c) / 6), with
/// positions taken relative to `origin`.
fn signed_measure(facets: &[Vec<usize>], v: &[[f64; 3]], origin: [f64; 3]) -> f64 {
    let at = |i: usize| sub(v[i], origin);
    facets
        .iter()
        .map(|f| match f[..] {
            [a, b] => orient2d([0.0; 3], at(a), at(b)) / 2.0,
            [a, b, c] => dot(at(a), cross(at(b), at(c))) / 6.0,
            _ => 0.0,
        })
        .sum()
}

/// Winding number of a closed oriented polyline around p, by signed crossings
/// of the ray from p towards +x (half-open in y, so vertices count once).
fn winding_number_2d(p: [f64; 3], segments: &[Vec<usize>], v: &[[f64; 3]]) -> f64 {
    let mut winding = 0i64;
    for s in segments {
        let (a, b) = (v[s[0]], v[s[1]]);
        if a[1] <= p[1] {
            if b[1] > p[1] && orient2d(a, b, p) > 0.0 {
                winding += 1;
            }
        } else if b[1] <= p[1] && orient2d(a, b, p) < 0.0 {
            winding -= 1;
        }
    }
    winding as f64
}

/// Generalised winding number `Σ Ω / (4π)` of closed oriented triangles
/// around p (van Oosterom–Strackee solid angles).
fn winding_number_3d(p: [f64; 3], triangles: &[Vec<usize>], v: &[[f64; 3]]) -> f64 {
    let total: f64 = triangles
        .iter()
        .map(|t| {
            let (a, b, c) = (sub(v[t[0]], p), sub(v[t[1]], p), sub(v[t[2]], p));
            let (la, lb, lc) = (norm(a), norm(b), norm(c));
            let numerator = dot(a, cross(b, c));
            let denominator = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
            2.0 * numerator.atan2(denominator)
        })
        .sum();
    total / (4.0 * std::f64::consts::PI)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    /// Appends a piece (indices local to it) to `s`.
    fn add(
        s: &mut SavedSurface,
        vertices: &[[f64; 3]],
        segments: &[[usize; 2]],
        triangles: &[[usize; 3]],
    ) {
        let o = s.vertices.len();
        s.vertices.extend_from_slice(vertices);
        s.segments.extend(segments.iter().map(|e| e.map(|i| i + o)));
        s.triangles
            .extend(triangles.iter().map(|t| t.map(|i| i + o)));
    }

    /// A closed loop through `points` in order.
    fn polygon(s: &mut SavedSurface, points: &[[f64; 2]]) {
        let n = points.len();
        let vertices: Vec<[f64; 3]> = points.iter().map(|p| [p[0], p[1], 0.0]).collect();
        let segments: Vec<[usize; 2]> = (0..n).map(|i| [i, (i + 1) % n]).collect();
        add(s, &vertices, &segments, &[]);
    }

    /// A counter-clockwise square with its lower-left corner first.
    fn square(s: &mut SavedSurface, x: f64, y: f64, size: f64) {
        polygon(
            s,
            &[[x, y], [x + size, y], [x + size, y + size], [x, y + size]],
        );
    }

    /// The outward boundary of the cube `min + [0, size]³`, each face split
    /// into n × n squares of two triangles, vertices shared.
    fn cube(s: &mut SavedSurface, min: [f64; 3], size: f64, n: usize) {
        let mut index: HashMap<[usize; 3], usize> = HashMap::new();
        let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
        for axis in 0..3 {
            let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
            for side in [0, n] {
                for i in 0..n {
                    for j in 0..n {
                        let mut corner = |di: usize, dj: usize| {
                            let mut l = [0; 3];
                            (l[axis], l[u], l[w]) = (side, i + di, j + dj);
                            *index.entry(l).or_insert_with(|| {
                                vertices.push(std::array::from_fn(|k| {
                                    min[k] + size * l[k] as f64 / n as f64
                                }));
                                vertices.len() - 1
                            })
                        };
                        let (c00, c10, c11, c01) =
                            (corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1));
                        // (c00, c10, c11) has normal e_u × e_w = +e_axis.
                        if side == n {
                            triangles.extend([[c00, c10, c11], [c00, c11, c01]]);
                        } else {
                            triangles.extend([[c00, c11, c10], [c00, c01, c11]]);
                        }
                    }
                }
            }
        }
        add(s, &vertices, &[], &triangles);
    }

    /// The OBJ text elasto writes: coordinates printed from `f32`.
    fn to_obj(s: &SavedSurface) -> String {
        let mut text = String::from("# test surface\n");
        for p in &s.vertices {
            let [x, y, z] = p.map(|c| c as f32);
            text.push_str(&format!("v {x} {y} {z}\n"));
        }
        for [a, b] in &s.segments {
            text.push_str(&format!("l {} {}\n", a + 1, b + 1));
        }
        for [a, b, c] in &s.triangles {
            text.push_str(&format!("f {} {} {}\n", a + 1, b + 1, c + 1));
        }
        text
    }

    fn temp_file(name: &str, text: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("elasto_intersection_{}_{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("surface.obj");
        std::fs::write(&path, text).unwrap();
        path
    }

    /// Saved by elasto's rules and read back.
    fn saved(s: &SavedSurface, name: &str) -> SavedSurface {
        let path = temp_file(name, &to_obj(s));
        let read = SavedSurface::read_obj(&path).unwrap();
        std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
        read
    }

    fn vertex_at(s: &SavedSurface, p: [f64; 3]) -> usize {
        s.vertices.iter().position(|&v| v == p).unwrap()
    }

    #[test]
    fn crossing_squares_are_found_where_they_cross() {
        let mut s = SavedSurface::default();
        square(&mut s, 0.0, 0.0, 1.0);
        square(&mut s, 0.5, 0.25, 1.0);
        let found = find_intersections(&saved(&s, "cross2"));
        // Right edge of A (segment 1) meets bottom of B (4) at (1, 0.25);
        // top of A (2) meets left of B (7) at (0.5, 1); B's corner is in A.
        assert_eq!(
            found,
            [
                Intersection::SegmentsCross {
                    a: 1,
                    b: 4,
                    at: [1.0, 0.25]
                },
                Intersection::SegmentsCross {
                    a: 2,
                    b: 7,
                    at: [0.5, 1.0]
                },
                Intersection::Contained {
                    inner: 1,
                    outer: 0,
                    vertex: 4
                },
            ]
        );
    }

    #[test]
    fn separate_squares_are_clean_and_nested_ones_contained() {
        let mut s = SavedSurface::default();
        square(&mut s, 0.0, 0.0, 1.0);
        square(&mut s, 1.5, 0.0, 1.0);
        assert_eq!(s.components(), [0, 0, 0, 0, 1, 1, 1, 1]);
        assert_eq!(find_intersections(&s), []);
        let mut nested = SavedSurface::default();
        square(&mut nested, 0.0, 0.0, 3.0);
        square(&mut nested, 1.0, 1.0, 1.0);
        assert_eq!(
            find_intersections(&nested),
            [Intersection::Contained {
                inner: 1,
                outer: 0,
                vertex: 4
            }]
        );
    }

    #[test]
    fn a_gap_of_1e_3_is_clean_unless_within_the_tolerance() {
        let mut s = SavedSurface::default();
        square(&mut s, 0.0, 0.0, 1.0);
        square(&mut s, 1.001, 0.0, 1.0);
        assert_eq!(find_intersections(&s), []);
        assert_eq!(find_intersections_within(&s, 9e-4), []);
        let near = find_intersections_within(&s, 2e-3);
        // A's right edge (1) and B's left edge (7) are 1e-3 apart, midway at x = 1.0005.
        assert!(
            near.iter().any(
                |i| matches!(i, Intersection::SegmentsCross { a: 1, b: 7, at }
            if (at[0] - 1.0005).abs() < 1e-12)
            ),
            "{near:?}"
        );
    }

    #[test]
    fn the_checker_judges_the_f32_numbers_in_the_file() {
        // 1 + 1e-7 rounds to the next f32 above 1 (1 + 1.19e-7): still apart.
        // 1 + 4e-8 rounds to 1: in the file the squares touch along x = 1.
        for (gap, touching) in [(1e-7, false), (4e-8, true)] {
            let mut s = SavedSurface::default();
            square(&mut s, 0.0, 0.0, 1.0);
            square(&mut s, 1.0 + gap, 0.0, 1.0);
            assert_eq!(find_intersections(&s), [], "unrounded, gap {gap}");
            let found = find_intersections(&saved(&s, &format!("f32_{touching}")));
            assert_eq!(!found.is_empty(), touching, "gap {gap}: {found:?}");
            assert!(
                found
                    .iter()
                    .all(|i| matches!(i, Intersection::SegmentsCross { at, .. } if at[0] == 1.0))
            );
        }
    }

    #[test]
    fn a_figure_eight_crosses_itself() {
        let mut s = SavedSurface::default();
        polygon(&mut s, &[[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 2.0]]);
        assert_eq!(
            find_intersections(&s),
            [Intersection::SegmentsCross {
                a: 0,
                b: 2,
                at: [1.0, 1.0]
            }]
        );
    }

    #[test]
    fn a_body_in_a_hole_is_clean_and_one_in_the_material_is_not() {
        for (x, contained) in [(4.0, false), (1.0, true)] {
            let mut s = SavedSurface::default();
            square(&mut s, 0.0, 0.0, 10.0);
            polygon(&mut s, &[[3.0, 3.0], [3.0, 7.0], [7.0, 7.0], [7.0, 3.0]]); // clockwise hole
            square(&mut s, x, x, 1.0);
            let expected: &[Intersection] = if contained {
                &[Intersection::Contained {
                    inner: 2,
                    outer: 0,
                    vertex: 8,
                }]
            } else {
                &[]
            };
            assert_eq!(find_intersections(&s), expected, "square at {x}");
        }
    }

    #[test]
    fn a_cube_has_its_volume_and_winds_once_around_its_inside() {
        let mut s = SavedSurface::default();
        cube(&mut s, [1.0, 2.0, 3.0], 2.0, 2);
        let facets: Vec<Vec<usize>> = s.triangles.iter().map(|t| t.to_vec()).collect();
        assert_eq!(facets.len(), 48);
        assert!(is_closed(&facets));
        assert!(!is_closed(&facets[1..]));
        assert!((signed_measure(&facets, &s.vertices, [0.0; 3]) - 8.0).abs() < 1e-12);
        let w = |p| winding_number_3d(p, &facets, &s.vertices);
        assert!(
            (w([2.1, 2.9, 4.2]) - 1.0).abs() < 1e-12,
            "{}",
            w([2.1, 2.9, 4.2])
        );
        assert!(w([3.5, 3.0, 4.0]).abs() < 1e-12);
        assert!(w([-5.0, 40.0, 1.0]).abs() < 1e-12);
    }

    #[test]
    fn interpenetrating_cubes_are_found() {
        let mut s = SavedSurface::default();
        cube(&mut s, [0.0; 3], 1.0, 1);
        cube(&mut s, [0.5, 0.3, 0.2], 1.0, 1);
        let s = saved(&s, "cross3");
        let found = find_intersections(&s);
        // B's edge along x from its lowest corner leaves A through A's face
        // x = 1 at (1, 0.3, 0.2), in that face's triangle below the diagonal z = y.
        let edge = [
            vertex_at(&s, [0.5, 0.3, 0.2]),
            vertex_at(&s, [1.5, 0.3, 0.2]),
        ];
        let corners = [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [1.0, 1.0, 1.0]].map(|p| vertex_at(&s, p));
        let triangle = s.triangles.iter().position(|&t| t == corners).unwrap();
        assert!(
            found.contains(&Intersection::EdgeThroughTriangle { edge, triangle }),
            "{found:?}"
        );
        assert!(found.contains(&Intersection::Contained {
            inner: 1,
            outer: 0,
            vertex: edge[0]
        }));
        let lowest_of_a = |i: &Intersection| matches!(i, Intersection::EdgeThroughTriangle { edge, .. } if edge.contains(&0));
        assert!(
            !found.iter().any(lowest_of_a),
            "A's corner at the origin is outside B"
        );
    }

    #[test]
    fn edges_meet_triangles_they_reach_or_overlap_in_their_plane() {
        let triangle = [[0.0, 0.0, 1.0], [2.0, 0.0, 1.0], [0.0, 2.0, 1.0]];
        let meets = |p, q| edge_meets_triangle(p, q, triangle);
        assert!(meets([-1.0, 0.5, 1.0], [3.0, 0.5, 1.0]), "across");
        assert!(meets([0.2, 0.2, 1.0], [0.5, 0.3, 1.0]), "inside");
        assert!(
            meets([1.0, 1.0, 1.0], [3.0, 3.0, 1.0]),
            "from the hypotenuse"
        );
        assert!(!meets([1.5, 1.5, 1.0], [3.0, 1.0, 1.0]), "beside");
        assert!(!meets([0.5, 0.5, 2.0], [0.5, 0.5, 1.5]), "short of it");
        assert!(meets([0.5, 0.5, 2.0], [0.5, 0.5, 1.0]), "ending on it");
        assert!(meets([0.5, 0.5, 2.0], [0.5, 0.5, 0.5]), "through it");
        assert!(
            !meets([1.5, 1.5, 2.0], [1.5, 1.5, 0.5]),
            "past its hypotenuse"
        );
        assert!(
            !meets([-1.0, 0.5, 1.0 + 1e-9], [3.0, 0.5, 1.0 + 1e-9]),
            "above"
        );
        // Cubes touching face to face: B's edge in the plane x = 1 lies on A's face.
        let mut s = SavedSurface::default();
        cube(&mut s, [0.0; 3], 1.0, 1);
        cube(&mut s, [1.0, 0.2, 0.3], 1.0, 1);
        let edge = [
            vertex_at(&s, [1.0, 0.2, 0.3]),
            vertex_at(&s, [1.0, 1.2, 0.3]),
        ];
        let on_face = |t: usize| {
            s.triangles[t]
                .iter()
                .all(|&i| s.vertices[i][0] == 1.0 && i < 8)
        };
        let found = find_intersections(&s);
        assert!(
            found.iter().any(
                |i| matches!(i, Intersection::EdgeThroughTriangle { edge: e, triangle }
            if *e == edge && on_face(*triangle))
            ),
            "{found:?}"
        );
    }

    #[test]
    fn separate_and_nested_cubes() {
        let mut s = SavedSurface::default();
        cube(&mut s, [0.0; 3], 1.0, 2);
        cube(&mut s, [1.001, 0.2, 0.3], 1.0, 1);
        assert_eq!(find_intersections(&s), []);
        assert_eq!(find_intersections_within(&s, 9e-4), []);
        let near = find_intersections_within(&s, 2e-3);
        assert!(
            !near.is_empty()
                && near
                    .iter()
                    .all(|i| matches!(i, Intersection::EdgeThroughTriangle { .. }))
        );
        let mut nested = SavedSurface::default();
        cube(&mut nested, [0.0; 3], 3.0, 2);
        let first_of_small = nested.vertices.len();
        cube(&mut nested, [1.0, 1.2, 0.9], 1.0, 1);
        assert_eq!(
            find_intersections(&nested),
            [Intersection::Contained {
                inner: 1,
                outer: 0,
                vertex: first_of_small
            }]
        );
    }

    #[test]
    fn a_tetrahedron_poking_a_vertex_through_a_triangle_is_found() {
        for (apex_z, poking) in [(0.2, true), (-0.1, false)] {
            let mut s = SavedSurface::default();
            add(
                &mut s,
                &[[-2.0, -2.0, 0.0], [3.0, -1.0, 0.0], [-1.0, 3.0, 0.0]],
                &[],
                &[[0, 1, 2]],
            );
            let tetrahedron = [
                [0.0, 0.0, -1.0],
                [1.0, 0.0, -1.0],
                [0.0, 1.0, -1.0],
                [0.25, 0.25, apex_z],
            ];
            add(
                &mut s,
                &tetrahedron,
                &[],
                &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]],
            );
            let expected: Vec<Intersection> = if poking {
                (3..6)
                    .map(|b| Intersection::EdgeThroughTriangle {
                        edge: [b, 6],
                        triangle: 0,
                    })
                    .collect()
            } else {
                Vec::new()
            };
            assert_eq!(find_intersections(&s), expected, "apex at z = {apex_z}");
        }
    }

    #[test]
    fn near_misses_within_the_tolerance_are_found_by_their_distance() {
        // Skew segments 0.5 apart, closest at their middles.
        let (d, at) =
            segment_segment_closest([0.0; 3], [2.0, 0.0, 0.0], [1.0, -1.0, 0.5], [1.0, 1.0, 0.5]);
        assert_eq!((d, at), (0.5, [1.0, 0.0, 0.25]));
        // The foot of the apex falls inside the sheet, 1e-3 below it.
        let mut s = SavedSurface::default();
        add(
            &mut s,
            &[[-2.0, -2.0, 0.0], [3.0, -1.0, 0.0], [-1.0, 3.0, 0.0]],
            &[],
            &[[0, 1, 2]],
        );
        let tetrahedron = [
            [0.0, 0.0, -1.0],
            [1.0, 0.0, -1.0],
            [0.0, 1.0, -1.0],
            [0.25, 0.25, -1e-3],
        ];
        add(
            &mut s,
            &tetrahedron,
            &[],
            &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]],
        );
        assert_eq!(find_intersections_within(&s, 9e-4), []);
        let near: Vec<Intersection> = (3..6)
            .map(|b| Intersection::EdgeThroughTriangle {
                edge: [b, 6],
                triangle: 0,
            })
            .collect();
        assert_eq!(find_intersections_within(&s, 2e-3), near);
    }

    #[test]
    fn obj_files_read_every_index_form() {
        let text = "# comment\nmtllib x.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0.5\nv 0 1 0\nvn 0 0 1\nvt 0 0\n\
                    l 1 2 3\nf 1/1/1 2/1/1 3/1/1\nf 1//1 2//1 3//1 4//1\nf -1 -2 -3\nf 2/7 3/7 4/7\n";
        let path = temp_file("read", text);
        let s = SavedSurface::read_obj(&path).unwrap();
        std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
        assert_eq!(
            s.vertices,
            [
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.5],
                [0.0, 1.0, 0.0]
            ]
        );
        assert_eq!(s.segments, [[0, 1], [1, 2]]);
        assert_eq!(
            s.triangles,
            [[0, 1, 2], [0, 1, 2], [0, 2, 3], [3, 2, 1], [1, 2, 3]]
        );
        assert_eq!(s.components(), [0, 0, 0, 0]);
        assert!(
            SavedSurface::parse_obj("v 0 0 0\nf 1 2 3\n")
                .unwrap_err()
                .contains("index 2")
        );
        assert!(
            SavedSurface::parse_obj("v 0 x 0\n")
                .unwrap_err()
                .contains("line 1")
        );
        assert!(SavedSurface::parse_obj("v 0 0 0\nl 1 0\n").is_err());
        assert!(SavedSurface::read_obj(Path::new("/nonexistent/surface.obj")).is_err());
    }

    #[test]
    fn a_surface_of_ten_thousand_triangles_is_checked_quickly() {
        let mut s = SavedSurface::default();
        cube(&mut s, [0.0; 3], 1.0, 20);
        cube(&mut s, [1.01, 0.3, 0.2], 1.0, 20);
        assert_eq!(s.triangles.len(), 9600);
        let start = std::time::Instant::now();
        assert_eq!(find_intersections(&s), []);
        let shifted = SavedSurface {
            vertices: s
                .vertices
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    if i < 2402 {
                        *p
                    } else {
                        [p[0] - 0.1, p[1], p[2]]
                    }
                })
                .collect(),
            ..s.clone()
        };
        let found = find_intersections(&shifted);
        assert!(
            found
                .iter()
                .filter(|i| matches!(i, Intersection::EdgeThroughTriangle { .. }))
                .count()
                > 20
        );
        assert!(
            start.elapsed().as_secs_f64() < 20.0,
            "{:?}",
            start.elapsed()
        );
    }

    /// Two open plates, OBJ text as `obstacles_NNNN.obj` holds them: one
    /// across y = `y` over x, z in [-1, 2], one upright across it (x = 0.5,
    /// y in [y − 0.5, y + 0.5]); each fanned from its first vertex.
    fn crossed_plates_obj(y: f64) -> String {
        let (lo, hi) = (y - 0.5, y + 0.5);
        format!(
            "# elasto boundary surface\n\
             v -1 {y} -1\nv 2 {y} -1\nv 2 {y} 2\nv -1 {y} 2\n\
             v 0.5 {lo} -1\nv 0.5 {hi} -1\nv 0.5 {hi} 2\nv 0.5 {lo} 2\n\
             f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\n"
        )
    }

    #[test]
    fn a_body_through_an_obstacle_is_found_and_obstacles_crossing_each_other_are_not() {
        let mut body = SavedSurface::default();
        cube(&mut body, [0.0; 3], 1.0, 1);
        let body = SavedSurface::parse_obj(&to_obj(&body)).unwrap();
        // Plates above the cube: they cross each other, which is no problem.
        let above = SavedSurface::parse_obj(&crossed_plates_obj(1.6)).unwrap();
        assert_eq!(find_intersections(&body.with_obstacles(&above)), []);
        // The same obstacles as a body would cross it.
        assert!(!find_intersections(&above).is_empty());
        // Plates through the cube's middle: the level one (triangles 12 and
        // 13 of the union) is crossed by the cube's upright edges and side
        // diagonals; the upright one touches the cube's top and bottom.
        let through = SavedSurface::parse_obj(&crossed_plates_obj(0.5)).unwrap();
        let joined = body.with_obstacles(&through);
        assert_eq!(joined.obstacles_from, Some(8));
        let found = find_intersections(&joined);
        assert!(!found.is_empty());
        for problem in &found {
            let Intersection::EdgeThroughTriangle { edge, triangle } = problem else {
                panic!("{problem:?}");
            };
            // Always a body's edge against an obstacle's triangle (or an
            // obstacle's edge against a body's triangle), never two obstacles'.
            let body_edge = edge[1] < 8;
            let body_triangle = *triangle < 12;
            assert!(body_edge != body_triangle, "{problem:?}");
        }
        let upright_edges_through_the_level_plate = found
            .iter()
            .filter(|p| {
                matches!(p, Intersection::EdgeThroughTriangle { edge: [a, b], triangle: 12 | 13 }
                    if *b < 8 && joined.vertices[*a][1] != joined.vertices[*b][1])
            })
            .count();
        assert!(upright_edges_through_the_level_plate >= 4, "{found:?}");
    }

    #[test]
    fn a_body_inside_a_closed_obstacle_is_found_but_not_inside_an_open_one() {
        let mut body = SavedSurface::default();
        cube(&mut body, [1.0; 3], 1.0, 1);
        // A closed box obstacle around the body, and a second one around
        // that (an obstacle inside an obstacle is no problem).
        let mut boxes = SavedSurface::default();
        cube(&mut boxes, [0.0; 3], 3.0, 1);
        cube(&mut boxes, [-1.0; 3], 5.0, 1);
        let boxes = SavedSurface::parse_obj(&to_obj(&boxes)).unwrap();
        assert_eq!(
            find_intersections(&body.with_obstacles(&boxes)),
            [
                Intersection::Contained {
                    inner: 0,
                    outer: 1,
                    vertex: 0
                },
                Intersection::Contained {
                    inner: 0,
                    outer: 2,
                    vertex: 0
                },
            ]
        );
        // The same box with its top open (a bowl): it has no inside.
        let mut open = boxes.clone();
        open.triangles.truncate(12);
        open.triangles
            .retain(|t| t.iter().any(|&v| open.vertices[v][1] < 3.0));
        assert_eq!(open.triangles.len(), 10);
        open.vertices.truncate(8);
        assert_eq!(find_intersections(&body.with_obstacles(&open)), []);
        // A closed obstacle inside a body counts too.
        let mut big = SavedSurface::default();
        cube(&mut big, [-1.0; 3], 5.0, 1);
        let mut small = SavedSurface::default();
        cube(&mut small, [1.0; 3], 1.0, 1);
        assert_eq!(
            find_intersections(&big.with_obstacles(&small)),
            [Intersection::Contained {
                inner: 1,
                outer: 0,
                vertex: 8
            }]
        );
    }

    #[test]
    fn in_2d_a_body_crossing_an_obstacle_polyline_is_found() {
        let mut body = SavedSurface::default();
        square(&mut body, 0.0, 0.0, 1.0);
        // Two obstacle polylines crossing each other at (0.5, 2), above the
        // square, as `l` lines of an OBJ file.
        let above =
            SavedSurface::parse_obj("v -1 2 0\nv 2 2 0\nv 0.5 1.5 0\nv 0.5 2.5 0\nl 1 2\nl 3 4\n")
                .unwrap();
        assert_eq!(find_intersections(&body.with_obstacles(&above)), []);
        // One lower, through the square at y = 0.5: its segment (4 of the
        // union) crosses the square's right (1) and left (3) sides.
        let through = SavedSurface::parse_obj(
            "v -1 0.5 0\nv 2 0.5 0\nv 0.5 1.5 0\nv 0.5 2.5 0\nl 1 2\nl 3 4\n",
        )
        .unwrap();
        assert_eq!(
            find_intersections(&body.with_obstacles(&through)),
            [
                Intersection::SegmentsCross {
                    a: 1,
                    b: 4,
                    at: [1.0, 0.5]
                },
                Intersection::SegmentsCross {
                    a: 3,
                    b: 4,
                    at: [0.0, 0.5]
                },
            ]
        );
    }
}
