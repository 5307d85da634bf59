//! Candidate stencils: every pair of surface primitives close enough to matter, from the broad phase.
//!
//! At a state `x` (a Newton iterate) the candidates are the pairs whose
//! bounding boxes come within `d_hat`; over a line-search segment
//! `x -> x + dx` the boxes are swept (each primitive's box at both ends), so
//! every pair that comes within `d_hat` anywhere on the segment is a
//! candidate: the barrier's value at any trial point of the segment, and the
//! collision-free step, need nothing else. Pairs that share a vertex are
//! never candidates (a vertex against its own edge or triangle, edges with a
//! common end), nor, with self-contact off, pairs within one body.
//!
//! The list is in a fixed order (point-edge or point-triangle stencils
//! first, then edge-edge, each sorted by primitive index), so every sum over
//! it is deterministic.

use super::broad_phase::{Aabb, BroadPhase};
use super::{CollisionMesh, ContactStencil, StencilKind};
use crate::math::Vector;

/// Finds candidate stencils, keeping its buffers between calls.
///
/// # The cache of candidates
///
/// A broad phase over every surface primitive at every Newton iterate and
/// line search costs as much as the rest of a contact-free step's
/// assembly. So the grid search runs over *cache boxes* instead: each
/// surface vertex's box at the query (its position, or both ends of its
/// motion), grown by a margin `m` on every side. Its pairs (the *cached
/// pairs*) are kept with those boxes; a later query whose every surface
/// vertex lies in its cache box (at both ends of its motion) is covered by
/// them: a primitive's box then lies in the union of its vertices' cache
/// boxes, growing a box and testing overlap are monotone in floating
/// point, so every pair the grid would report for the query is a cached
/// pair. The query then only tests each cached pair's own boxes against
/// each other, with the grid's inflation and comparison
/// ([`Aabb::inflated`], [`Aabb::overlaps`]): the answer is exactly the
/// grid's, in the same order, at the cost of the boxes and one test per
/// cached pair. A vertex outside its cache box starts a new grid search
/// around the query.
///
/// The margin is the activation distance `d_hat`: Newton's later iterates
/// and a body at rest move far less than that, so one search serves many
/// queries, and the cached pairs are those within about `3 d_hat`.
pub struct CandidateFinder<const D: usize> {
    broad_phase: BroadPhase<D>,
    vertex_boxes: Vec<Aabb<D>>,
    edge_boxes: Vec<Aabb<D>>,
    face_boxes: Vec<Aabb<D>>,
    cache: CandidateCache<D>,
    searches: usize,
}

/// The cached pairs and the region of states they cover.
struct CandidateCache<const D: usize> {
    /// Per surface vertex, the box it must stay in (empty: no cache).
    vertex_boxes: Vec<Aabb<D>>,
    /// What the pairs were found for: `(activation, self_contact)`.
    key: Option<(f64, bool)>,
    /// 2D: (vertex, edge); 3D: (vertex, face).
    point_pairs: Vec<(u32, u32)>,
    /// 3D: (edge, edge).
    edge_pairs: Vec<(u32, u32)>,
}

impl<const D: usize> Default for CandidateFinder<D> {
    fn default() -> Self {
        Self {
            broad_phase: BroadPhase::new(),
            vertex_boxes: Vec::new(),
            edge_boxes: Vec::new(),
            face_boxes: Vec::new(),
            cache: CandidateCache {
                vertex_boxes: Vec::new(),
                key: None,
                point_pairs: Vec::new(),
                edge_pairs: Vec::new(),
            },
            searches: 0,
        }
    }
}

impl<const D: usize> CandidateFinder<D> {
    /// Grid searches so far (queries the cache did not cover).
    pub fn searches(&self) -> usize {
        self.searches
    }

    /// Writes into `stencils` (cleared first) every candidate of `mesh` at
    /// positions `x`, or along `x -> x + dx` when `dx` is given, within
    /// `activation` (`d_hat`); with `self_contact` off, only pairs of
    /// different bodies.
    pub fn find(
        &mut self,
        mesh: &CollisionMesh,
        x: &[Vector<D>],
        dx: Option<&[Vector<D>]>,
        activation: f64,
        self_contact: bool,
        stencils: &mut Vec<ContactStencil>,
    ) {
        stencils.clear();
        let end = |v: usize| dx.map(|dx| x[v] + dx[v]);
        if !self.cache.covers(mesh, x, &end, (activation, self_contact)) {
            self.search(mesh, x, &end, activation, self_contact);
        }
        let box_of = |corners: &[usize]| -> Aabb<D> {
            let mut b = Aabb::empty();
            for &v in corners {
                b = b.union_point(&x[v]);
                if let Some(e) = end(v) {
                    b = b.union_point(&e);
                }
            }
            b
        };
        fill_boxes(
            &mut self.vertex_boxes,
            &mut self.edge_boxes,
            &mut self.face_boxes,
            mesh,
            box_of,
        );
        let half = activation / 2.0;
        let near = |a: &Aabb<D>, b: &Aabb<D>| a.inflated(half).overlaps(&b.inflated(half));
        let (vertex_boxes, edge_boxes, face_boxes) =
            (&self.vertex_boxes, &self.edge_boxes, &self.face_boxes);
        if D == 2 {
            stencils.extend(
                self.cache
                    .point_pairs
                    .iter()
                    .filter(|&&(s, e)| near(&vertex_boxes[s as usize], &edge_boxes[e as usize]))
                    .map(|&(s, e)| point_edge(mesh, s, e)),
            );
            return;
        }
        stencils.extend(
            self.cache
                .point_pairs
                .iter()
                .filter(|&&(s, f)| near(&vertex_boxes[s as usize], &face_boxes[f as usize]))
                .map(|&(s, f)| point_triangle(mesh, s, f)),
        );
        stencils.extend(
            self.cache
                .edge_pairs
                .iter()
                .filter(|&&(a, b)| near(&edge_boxes[a as usize], &edge_boxes[b as usize]))
                .map(|&(a, b)| edge_edge(mesh, a, b)),
        );
    }

    /// A grid search over the cache boxes of the query (each surface
    /// vertex's box at `x` and `end`, grown by `activation`): the new cached
    /// pairs.
    fn search(
        &mut self,
        mesh: &CollisionMesh,
        x: &[Vector<D>],
        end: &impl Fn(usize) -> Option<Vector<D>>,
        activation: f64,
        self_contact: bool,
    ) {
        self.searches += 1;
        let margin = activation;
        let cache = &mut self.cache;
        cache.key = Some((activation, self_contact));
        cache.vertex_boxes.clear();
        cache.vertex_boxes.extend(mesh.vertices().iter().map(|&v| {
            let b = Aabb::empty().union_point(&x[v]);
            let b = end(v).map_or(b, |e| b.union_point(&e));
            b.inflated(margin)
        }));
        let by_vertex = &cache.vertex_boxes;
        let box_of = |corners: &[usize]| -> Aabb<D> {
            corners.iter().fold(Aabb::empty(), |b, &v| {
                let c = by_vertex[mesh.surface_index(v).expect("a surface vertex")];
                b.union_point(&c.min).union_point(&c.max)
            })
        };
        fill_boxes(
            &mut self.vertex_boxes,
            &mut self.edge_boxes,
            &mut self.face_boxes,
            mesh,
            box_of,
        );
        let distinct_bodies = |a: usize, b: usize| mesh.may_touch(a, b, self_contact);
        cache.point_pairs.clear();
        cache.edge_pairs.clear();
        if D == 2 {
            let keep = |s: usize, e: usize| {
                let v = mesh.vertices()[s];
                let edge = mesh.edges()[e];
                v != edge[0]
                    && v != edge[1]
                    && distinct_bodies(mesh.vertex_body(s), mesh.edge_body(e))
            };
            self.broad_phase.pairs_between(
                &self.vertex_boxes,
                &self.edge_boxes,
                activation,
                keep,
                &mut cache.point_pairs,
            );
            return;
        }
        let keep = |s: usize, f: usize| {
            let v = mesh.vertices()[s];
            !mesh.faces()[f].contains(&v) && distinct_bodies(mesh.vertex_body(s), mesh.face_body(f))
        };
        self.broad_phase.pairs_between(
            &self.vertex_boxes,
            &self.face_boxes,
            activation,
            keep,
            &mut cache.point_pairs,
        );
        let keep = |a: usize, b: usize| {
            let (ea, eb) = (mesh.edges()[a], mesh.edges()[b]);
            !ea.iter().any(|v| eb.contains(v))
                && distinct_bodies(mesh.edge_body(a), mesh.edge_body(b))
        };
        self.broad_phase
            .pairs_within(&self.edge_boxes, activation, keep, &mut cache.edge_pairs);
    }
}

impl<const D: usize> CandidateCache<D> {
    /// Whether the cached pairs cover a query with `key` whose surface
    /// vertices are at `x` (and `end`): each in its cache box.
    fn covers(
        &self,
        mesh: &CollisionMesh,
        x: &[Vector<D>],
        end: &impl Fn(usize) -> Option<Vector<D>>,
        key: (f64, bool),
    ) -> bool {
        let inside =
            |b: &Aabb<D>, p: &Vector<D>| (0..D).all(|k| b.min[k] <= p[k] && p[k] <= b.max[k]);
        self.key == Some(key)
            && self.vertex_boxes.len() == mesh.vertices().len()
            && mesh
                .vertices()
                .iter()
                .zip(&self.vertex_boxes)
                .all(|(&v, b)| inside(b, &x[v]) && end(v).is_none_or(|e| inside(b, &e)))
    }
}

/// The boxes of a mesh's surface vertices, edges and (3D) faces by `box_of`
/// their corners.
fn fill_boxes<const D: usize>(
    vertex_boxes: &mut Vec<Aabb<D>>,
    edge_boxes: &mut Vec<Aabb<D>>,
    face_boxes: &mut Vec<Aabb<D>>,
    mesh: &CollisionMesh,
    box_of: impl Fn(&[usize]) -> Aabb<D>,
) {
    vertex_boxes.clear();
    vertex_boxes.extend(mesh.vertices().iter().map(|&v| box_of(&[v])));
    edge_boxes.clear();
    edge_boxes.extend(mesh.edges().iter().map(|e| box_of(e)));
    face_boxes.clear();
    if D == 3 {
        face_boxes.extend(mesh.faces().iter().map(|f| box_of(f)));
    }
}

fn point_edge(mesh: &CollisionMesh, s: u32, e: u32) -> ContactStencil {
    let v = mesh.vertices()[s as usize];
    let edge = mesh.edges()[e as usize];
    ContactStencil {
        kind: StencilKind::PointEdge,
        vertices: [v, edge[0], edge[1], usize::MAX],
        mollifier_threshold: 0.0,
    }
}

fn point_triangle(mesh: &CollisionMesh, s: u32, f: u32) -> ContactStencil {
    let v = mesh.vertices()[s as usize];
    let face = mesh.faces()[f as usize];
    ContactStencil {
        kind: StencilKind::PointTriangle,
        vertices: [v, face[0], face[1], face[2]],
        mollifier_threshold: 0.0,
    }
}

fn edge_edge(mesh: &CollisionMesh, a: u32, b: u32) -> ContactStencil {
    let (ea, eb) = (mesh.edges()[a as usize], mesh.edges()[b as usize]);
    ContactStencil {
        kind: StencilKind::EdgeEdge,
        vertices: [ea[0], ea[1], eb[0], eb[1]],
        mollifier_threshold: 1e-3
            * mesh.edge_rest_length_squared(a as usize)
            * mesh.edge_rest_length_squared(b as usize),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;

    /// A finder that never reuses its cache: the grid's own answer.
    fn fresh<const D: usize>(
        mesh: &CollisionMesh,
        x: &[Vector<D>],
        dx: Option<&[Vector<D>]>,
        activation: f64,
    ) -> Vec<ContactStencil> {
        let mut out = Vec::new();
        CandidateFinder::<D>::default().find(mesh, x, dx, activation, true, &mut out);
        out
    }

    /// Two stacked boxes, `gap` apart, as one collision mesh.
    fn stacked<const D: usize>(cells: usize, gap: f64) -> (CollisionMesh, Vec<Vector<D>>) {
        let unit =
            Mesh::axis_aligned_box(Vector::<D>::zeros(), Vector::<D>::repeat(1.0), [cells; D])
                .unwrap();
        let n = unit.vertex_count();
        let mut lift = Vector::<D>::zeros();
        lift[1] = 1.0 + gap;
        let mut positions = unit.rest_positions().to_vec();
        positions.extend(unit.rest_positions().iter().map(|p| p + lift));
        let mut simplices: Vec<Vec<usize>> = unit.simplices().map(<[usize]>::to_vec).collect();
        simplices.extend(unit.simplices().map(|s| s.iter().map(|v| v + n).collect()));
        let mesh = Mesh::new(positions.clone(), simplices).unwrap();
        let owner: Vec<usize> = (0..2 * n).map(|v| v / n).collect();
        (CollisionMesh::new(&mesh, &owner), positions)
    }

    /// A deterministic pseudo-random number in [-1, 1).
    fn noise(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// Over a walk of small and large moves, static and swept, the cached
    /// finder answers exactly what a fresh grid search answers, and small
    /// moves are answered from the cache.
    fn cached_answers_are_the_grids<const D: usize>() {
        let activation = 0.05;
        let (mesh, mut x) = stacked::<D>(3, 0.03);
        let mut finder = CandidateFinder::<D>::default();
        let mut seed = 7;
        let mut out = Vec::new();
        let mut queries = 0;
        for step in 0..60 {
            // Mostly moves well below the margin; every 10th a jump.
            let size = if step % 10 == 9 { 0.3 } else { 0.004 };
            let dx: Vec<Vector<D>> = x
                .iter()
                .map(|_| Vector::<D>::from_fn(|_, _| size * noise(&mut seed)))
                .collect();
            finder.find(&mesh, &x, None, activation, true, &mut out);
            assert_eq!(
                out,
                fresh(&mesh, &x, None, activation),
                "static query {step}"
            );
            finder.find(&mesh, &x, Some(&dx), activation, true, &mut out);
            assert_eq!(
                out,
                fresh(&mesh, &x, Some(&dx), activation),
                "swept query {step}"
            );
            queries += 2;
            for (p, d) in x.iter_mut().zip(&dx) {
                *p += d * 0.5;
            }
        }
        assert!(!out.is_empty());
        assert!(
            finder.searches() < queries / 3,
            "{} grid searches for {queries} queries",
            finder.searches()
        );
    }

    #[test]
    fn cached_candidates_are_the_grids_in_2d() {
        cached_answers_are_the_grids::<2>();
    }

    #[test]
    fn cached_candidates_are_the_grids_in_3d() {
        cached_answers_are_the_grids::<3>();
    }
}
