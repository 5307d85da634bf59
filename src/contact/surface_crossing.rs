//! Surfaces that cross: the check that bodies do not start intersecting.
//!
//! A pair of primitives closer than `d_hat` is found by the distances; two
//! primitives that cross with every corner far from the other one are not
//! (two edges crossing in their middles, an edge through a triangle's
//! interior), so the start of a contact scene also looks for crossings:
//!
//! * 2D: two edges `ab`, `cd` cross properly when `orient(a, b, c)` and
//!   `orient(a, b, d)` have strictly opposite signs, and so have
//!   `orient(c, d, a)` and `orient(c, d, b)` (`orient` the signed area);
//! * 3D: an edge `pq` passes through triangle `t0 t1 t2` when the signed
//!   volumes `vol(t0, t1, t2, p)` and `vol(t0, t1, t2, q)` have strictly
//!   opposite signs and the three volumes `vol(p, q, t_i, t_{i+1})` do not
//!   have opposite signs (the line through `pq` meets the closed triangle).
//!
//! Touching configurations (a zero orientation) have a corner at distance 0
//! from the other primitive, which the distance check finds. Candidates come
//! from the broad phase with no inflation; pairs that share a vertex are
//! skipped. A body wholly inside another without any crossing is found by
//! [`super::first_contained_body`].

use super::CollisionMesh;
use super::broad_phase::{Aabb, BroadPhase};
use crate::math::{Vector, Vector3};

/// Two surface primitives that cross.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SurfaceCrossing {
    /// 2D: edges `a` and `b` (indices into [`CollisionMesh::edges`]).
    Edges(usize, usize),
    /// 3D: edge `edge` passes through face `face`.
    EdgeThroughFace {
        /// An index into [`CollisionMesh::edges`].
        edge: usize,
        /// An index into [`CollisionMesh::faces`].
        face: usize,
    },
}

/// The first crossing of `mesh` at positions `x` (in the broad phase's
/// order), if any; with `self_contact` off, only crossings between bodies.
pub fn first_surface_crossing<const D: usize>(
    mesh: &CollisionMesh,
    x: &[Vector<D>],
    self_contact: bool,
) -> Option<SurfaceCrossing> {
    let box_of = |corners: &[usize]| {
        corners
            .iter()
            .fold(Aabb::<D>::empty(), |b, &v| b.union_point(&x[v]))
    };
    let edge_boxes: Vec<Aabb<D>> = mesh.edges().iter().map(|e| box_of(e)).collect();
    let mut broad_phase = BroadPhase::<D>::new();
    let mut pairs = Vec::new();
    if D == 2 {
        let keep = |a: usize, b: usize| {
            let (ea, eb) = (mesh.edges()[a], mesh.edges()[b]);
            !ea.iter().any(|v| eb.contains(v))
                && mesh.may_touch(mesh.edge_body(a), mesh.edge_body(b), self_contact)
        };
        broad_phase.pairs_within(&edge_boxes, 0.0, keep, &mut pairs);
        let orient = |a: &Vector<D>, b: &Vector<D>, c: &Vector<D>| {
            (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        };
        return pairs.iter().find_map(|&(a, b)| {
            let (ea, eb) = (mesh.edges()[a as usize], mesh.edges()[b as usize]);
            let [p, q, r, s] = [&x[ea[0]], &x[ea[1]], &x[eb[0]], &x[eb[1]]];
            let crosses =
                orient(p, q, r) * orient(p, q, s) < 0.0 && orient(r, s, p) * orient(r, s, q) < 0.0;
            crosses.then_some(SurfaceCrossing::Edges(a as usize, b as usize))
        });
    }
    let face_boxes: Vec<Aabb<D>> = mesh.faces().iter().map(|f| box_of(f)).collect();
    let keep = |e: usize, f: usize| {
        let (edge, face) = (mesh.edges()[e], mesh.faces()[f]);
        !edge.iter().any(|v| face.contains(v))
            && mesh.may_touch(mesh.edge_body(e), mesh.face_body(f), self_contact)
    };
    broad_phase.pairs_between(&edge_boxes, &face_boxes, 0.0, keep, &mut pairs);
    let point = |v: usize| Vector3::new(x[v][0], x[v][1], x[v][2]);
    let volume =
        |a: &Vector3, b: &Vector3, c: &Vector3, d: &Vector3| (b - a).cross(&(c - a)).dot(&(d - a));
    pairs.iter().find_map(|&(e, f)| {
        let (edge, face) = (mesh.edges()[e as usize], mesh.faces()[f as usize]);
        let [p, q] = edge.map(point);
        let t = face.map(point);
        let through_plane = volume(&t[0], &t[1], &t[2], &p) * volume(&t[0], &t[1], &t[2], &q) < 0.0;
        let sides = [0, 1, 2].map(|i| volume(&p, &q, &t[i], &t[(i + 1) % 3]));
        let inside = sides.iter().all(|&v| v >= 0.0) || sides.iter().all(|&v| v <= 0.0);
        (through_plane && inside).then_some(SurfaceCrossing::EdgeThroughFace {
            edge: e as usize,
            face: f as usize,
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;

    fn two_boxes<const D: usize>(shift: f64) -> (Mesh<D>, Vec<usize>) {
        let unit = |offset: f64| {
            let low = Vector::<D>::from_fn(|k, _| if k == 1 { offset } else { 0.25 * offset });
            Mesh::axis_aligned_box(low, low + Vector::<D>::repeat(1.0), [2; D]).unwrap()
        };
        let (a, b) = (unit(0.0), unit(shift));
        let n = a.vertex_count();
        let positions = [a.rest_positions(), b.rest_positions()].concat();
        let simplices = a
            .simplices()
            .map(<[usize]>::to_vec)
            .chain(b.simplices().map(|s| s.iter().map(|v| v + n).collect()))
            .collect();
        let owner = (0..2 * n).map(|v| v / n).collect();
        (Mesh::new(positions, simplices).unwrap(), owner)
    }

    fn crossing<const D: usize>(shift: f64, self_contact: bool) -> Option<SurfaceCrossing> {
        let (mesh, owner) = two_boxes::<D>(shift);
        let surface = CollisionMesh::new(&mesh, &owner);
        first_surface_crossing(&surface, mesh.rest_positions(), self_contact)
    }

    #[test]
    fn overlapping_boxes_cross_and_separate_ones_do_not() {
        assert!(matches!(
            crossing::<2>(0.6, true),
            Some(SurfaceCrossing::Edges(..))
        ));
        assert!(matches!(
            crossing::<3>(0.6, true),
            Some(SurfaceCrossing::EdgeThroughFace { .. })
        ));
        assert_eq!(crossing::<2>(1.5, true), None);
        assert_eq!(crossing::<3>(1.5, true), None);
        // Between two bodies, self-contact off does not hide the crossing.
        assert!(crossing::<3>(0.6, false).is_some());
    }
}
