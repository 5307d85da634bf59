//! Bodies inside bodies: the check that no body starts wholly inside another.
//!
//! Surfaces that cross are found by [`super::first_surface_crossing`], pairs
//! closer than `d_hat` by the distances; a body that lies entirely inside
//! another (a ball inside a box, both meshed) has neither. With no crossing
//! surfaces, a body is inside another exactly when one of its surface
//! vertices is, so one vertex per body is tested against the closed
//! surface of every other body by its **winding number**
//!
//! ```text
//! 2D:  w(p) = (1 / 2 pi) sum_{edges (a, b)} angle(a - p, b - p),
//! 3D:  w(p) = (1 / 4 pi) sum_{triangles (a, b, c)} Omega(a - p, b - p, c - p),
//!      tan(Omega / 2) = a . (b x c) / (|a||b||c| + (a . b)|c| + (a . c)|b| + (b . c)|a|)
//! ```
//!
//! (signed angles and solid angles, Van Oosterom and Strackee 1983 for the
//! latter): `|w| = 1` inside a closed oriented surface, `0` outside it, and
//! `0` in a cavity (its surface counts against the outer one), so a body
//! held in another's hole is not "inside". `|w| > 1/2` is taken as inside,
//! which rounding cannot flip. Obstacles count as bodies: a body inside a
//! closed obstacle surface (a box obstacle is a solid box) or an obstacle
//! inside a body is refused too, while an open obstacle (a bowl) encloses
//! nothing. A box test comes first, so the cost is one
//! sum over a surface per pair of bodies whose boxes hold each other's
//! vertex.

use super::CollisionMesh;
use super::broad_phase::Aabb;
use crate::math::{Vector, Vector3};
use std::f64::consts::PI;

/// A body that starts inside another.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Containment {
    /// The enclosed body.
    pub inner: usize,
    /// The body whose surface encloses it.
    pub outer: usize,
    /// The inner body's surface vertex that was tested (a simulation id).
    pub vertex: usize,
}

/// The first body of `mesh` at positions `x` (by body, then enclosing body)
/// that lies inside another, if any. Meaningful once no surfaces cross.
pub fn first_contained_body<const D: usize>(
    mesh: &CollisionMesh,
    x: &[Vector<D>],
) -> Option<Containment> {
    let bodies = mesh.body_count();
    // Per body: a surface vertex and the box of its surface.
    let mut first_vertex = vec![None; bodies];
    let mut boxes = vec![Aabb::<D>::empty(); bodies];
    for (s, &v) in mesh.vertices().iter().enumerate() {
        let body = mesh.vertex_body(s);
        first_vertex[body].get_or_insert(v);
        boxes[body] = boxes[body].union_point(&x[v]);
    }
    let inside_box =
        |b: &Aabb<D>, p: &Vector<D>| (0..D).all(|k| b.min[k] <= p[k] && p[k] <= b.max[k]);
    for (inner, vertex) in first_vertex.iter().enumerate() {
        let Some(&vertex) = vertex.as_ref() else {
            continue;
        };
        let p = x[vertex];
        // Only a closed surface encloses; obstacles may overlap each other.
        let encloses = |outer: usize| {
            outer != inner && mesh.is_closed(outer) && mesh.may_touch(inner, outer, true)
        };
        for outer in (0..bodies).filter(|&b| encloses(b)) {
            if !inside_box(&boxes[outer], &p) {
                continue;
            }
            let winding = if D == 2 {
                winding_number_2d(mesh, x, outer, &p)
            } else {
                winding_number_3d(mesh, x, outer, &p)
            };
            if winding.abs() > 0.5 {
                return Some(Containment {
                    inner,
                    outer,
                    vertex,
                });
            }
        }
    }
    None
}

/// The winding number of body `body`'s boundary edges (oriented) around `p`.
fn winding_number_2d<const D: usize>(
    mesh: &CollisionMesh,
    x: &[Vector<D>],
    body: usize,
    p: &Vector<D>,
) -> f64 {
    let angle: f64 = mesh
        .edges()
        .iter()
        .enumerate()
        .filter(|&(e, _)| mesh.edge_body(e) == body)
        .map(|(_, &[a, b])| {
            let (u, w) = (x[a] - p, x[b] - p);
            let cross = u[0] * w[1] - u[1] * w[0];
            let dot = u[0] * w[0] + u[1] * w[1];
            cross.atan2(dot)
        })
        .sum();
    angle / (2.0 * PI)
}

/// The generalised winding number of body `body`'s boundary triangles
/// around `p`.
fn winding_number_3d<const D: usize>(
    mesh: &CollisionMesh,
    x: &[Vector<D>],
    body: usize,
    p: &Vector<D>,
) -> f64 {
    let point = |v: usize| Vector3::new(x[v][0] - p[0], x[v][1] - p[1], x[v][2] - p[2]);
    let solid_angle: f64 = mesh
        .faces()
        .iter()
        .enumerate()
        .filter(|&(f, _)| mesh.face_body(f) == body)
        .map(|(_, face)| {
            let [a, b, c] = face.map(point);
            let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
            let numerator = a.dot(&b.cross(&c));
            let denominator = la * lb * lc + a.dot(&b) * lc + a.dot(&c) * lb + b.dot(&c) * la;
            2.0 * numerator.atan2(denominator)
        })
        .sum();
    solid_angle / (4.0 * PI)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;

    /// Bodies from boxes `(low, size)`, joined into one collision mesh.
    fn boxes<const D: usize>(parts: &[(f64, f64)]) -> (CollisionMesh, Vec<Vector<D>>) {
        let (mut positions, mut simplices, mut owner) = (Vec::new(), Vec::new(), Vec::new());
        for (body, &(low, size)) in parts.iter().enumerate() {
            let low = Vector::<D>::repeat(low);
            let part =
                Mesh::axis_aligned_box(low, low + Vector::<D>::repeat(size), [2; D]).unwrap();
            let n = positions.len();
            positions.extend_from_slice(part.rest_positions());
            simplices.extend(part.simplices().map(|s| s.iter().map(|v| v + n).collect()));
            owner.extend(std::iter::repeat_n(body, part.vertex_count()));
        }
        let mesh = Mesh::new(positions.clone(), simplices).unwrap();
        (CollisionMesh::new(&mesh, &owner), positions)
    }

    fn contained<const D: usize>(parts: &[(f64, f64)]) -> Option<(usize, usize)> {
        let (mesh, x) = boxes::<D>(parts);
        first_contained_body(&mesh, &x).map(|c| (c.inner, c.outer))
    }

    #[test]
    fn a_body_inside_another_is_found_in_2d_and_3d() {
        // A small box inside a big one, listed either way round.
        assert_eq!(contained::<2>(&[(0.0, 3.0), (1.0, 0.5)]), Some((1, 0)));
        assert_eq!(contained::<2>(&[(1.0, 0.5), (0.0, 3.0)]), Some((0, 1)));
        assert_eq!(contained::<3>(&[(0.0, 3.0), (1.0, 0.5)]), Some((1, 0)));
        assert_eq!(contained::<3>(&[(1.0, 0.5), (0.0, 3.0)]), Some((0, 1)));
        // Apart (the small box's vertex is outside the big one's box), or
        // side by side within each other's boxes: nothing.
        assert_eq!(contained::<2>(&[(0.0, 1.0), (2.0, 1.0)]), None);
        assert_eq!(contained::<3>(&[(0.0, 1.0), (2.0, 1.0)]), None);
        assert_eq!(contained::<3>(&[(0.0, 1.0)]), None);
    }

    #[test]
    fn winding_numbers_are_one_inside_and_zero_outside() {
        let (mesh, x) = boxes::<3>(&[(0.0, 1.0)]);
        let at = |p: [f64; 3]| winding_number_3d(&mesh, &x, 0, &Vector::<3>::from(p));
        assert!((at([0.3, 0.6, 0.2]).abs() - 1.0).abs() < 1e-12);
        assert!(at([1.3, 0.6, 0.2]).abs() < 1e-12);
        assert!(at([-5.0, 7.0, 2.0]).abs() < 1e-12);
        let (mesh, x) = boxes::<2>(&[(0.0, 1.0)]);
        let at = |p: [f64; 2]| winding_number_2d(&mesh, &x, 0, &Vector::<2>::from(p));
        assert!((at([0.3, 0.6]).abs() - 1.0).abs() < 1e-12);
        assert!(at([1.3, 0.6]).abs() < 1e-12);
    }

    #[test]
    fn a_body_in_a_cavity_is_not_inside() {
        // A 2D ring (a square with a square hole) around a small square.
        let ring = Mesh::<2>::new(
            vec![
                Vector::<2>::new(0.0, 0.0),
                Vector::<2>::new(3.0, 0.0),
                Vector::<2>::new(3.0, 3.0),
                Vector::<2>::new(0.0, 3.0),
                Vector::<2>::new(1.0, 1.0),
                Vector::<2>::new(2.0, 1.0),
                Vector::<2>::new(2.0, 2.0),
                Vector::<2>::new(1.0, 2.0),
            ],
            vec![
                vec![0, 1, 5],
                vec![0, 5, 4],
                vec![1, 2, 6],
                vec![1, 6, 5],
                vec![2, 3, 7],
                vec![2, 7, 6],
                vec![3, 0, 4],
                vec![3, 4, 7],
            ],
        )
        .unwrap();
        let inner =
            Mesh::axis_aligned_box(Vector::<2>::repeat(1.25), Vector::<2>::repeat(1.75), [1, 1])
                .unwrap();
        let positions = [ring.rest_positions(), inner.rest_positions()].concat();
        let simplices = ring
            .simplices()
            .map(<[usize]>::to_vec)
            .chain(inner.simplices().map(|s| s.iter().map(|v| v + 8).collect()))
            .collect();
        let mesh = Mesh::new(positions.clone(), simplices).unwrap();
        let owner: Vec<usize> = (0..12).map(|v| usize::from(v >= 8)).collect();
        let surface = CollisionMesh::new(&mesh, &owner);
        assert_eq!(first_contained_body(&surface, &positions), None);
    }
}
