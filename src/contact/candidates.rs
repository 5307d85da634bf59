//! Candidate stencils: every pair of surface primitives close enough to matter, from the broad phase.
//!
//! At a state `x` (a Newton iterate) the candidates are the pairs that may
//! be within `d_hat`; over a line-search segment `x -> x + dx` every pair
//! that may come within `d_hat` anywhere on the segment is a candidate: the
//! barrier's value at any trial point of the segment, and the
//! collision-free step, need nothing else. Pairs that share a vertex are
//! never candidates (a vertex against its own edge or triangle, edges with a
//! common end), nor, with self-contact off, pairs within one body.
//!
//! A candidate passes two tests: its primitives' (swept) boxes, grown by
//! `d_hat / 2` each, overlap (the broad phase's test), and a *certificate
//! of distance* does not rule it out (see [`CandidateFinder`]): the list is
//! every pair whose distance can be at most `d_hat` somewhere on the query,
//! and no pair that provably stays farther on it (those add nothing to the
//! barrier and cannot collide).
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
/// ([`Aabb::inflated`], [`Aabb::overlaps`]). A vertex outside its cache box
/// starts a new grid search around the query.
///
/// The margin is the activation distance `d_hat`: Newton's later iterates
/// and a body at rest move far less than that, so one search serves many
/// queries, and the cached pairs are those within about `3 d_hat`. A
/// search for a segment also reaches one segment further along it (the
/// box holds `x`, `x + dx` and `x + 2 dx`): a body in flight moves about
/// as far in the next step, whose queries the cache then covers (on four
/// falling boxes, 8 searches in a run instead of 13). The pairs this adds
/// are far ones, which the certificate below drops at a few comparisons
/// each.
///
/// # The certificate of distance
///
/// Boxes are a coarse test on the flat, axis-aligned surfaces meshes
/// often have: a vertex's box touches those of the triangles one ring
/// beyond its own, which are a whole element away. Such pairs would cost a
/// distance at every iterate, every trial point of every line search and
/// every CCD query while never coming near. So a search also measures each
/// cached pair's distance `d_k` at the search's positions `a` (the
/// *anchor*), and a query drops the pairs that provably stay farther than
/// `d_hat`. With `delta_i = y_i - a_i` the displacement of vertex `i` at a
/// point `y` of the query (for a segment, every vertex's `delta_i` is the
/// same convex combination of its values at the two ends), `t_b` the mean
/// of `delta` over body `b`'s surface vertices (per end) and
///
/// ```text
/// u_i = max(|delta_i(x) - t_b(x)|, |delta_i(x + dx) - t_b(x + dx)|)      (i in body b)
/// ```
///
/// every point of a primitive of body `b` moves by at most the largest
/// `u` of its corners relative to the translation `t_b`, which leaves
/// distances alone. Between a primitive `A` of body `a` and `B` of body
/// `b`, anywhere on the query,
///
/// ```text
/// distance >= d_k - max_{i in A} u_i - max_{j in B} u_j - [a != b] max(|t_a - t_b| at both ends)
/// ```
///
/// and the pair is dropped when that bound exceeds `d_hat + e`, with `e` a
/// margin for the rounding of the distances and displacements (`1e-9` of
/// the coordinates' magnitude, and `d_k` read `1e-9` short). A body that
/// falls, slides or deforms a little keeps every `u` far below an
/// element's size; the test costs a few comparisons per cached pair per
/// query, and O(1) per surface vertex.
pub struct CandidateFinder<const D: usize> {
    broad_phase: BroadPhase<D>,
    vertex_boxes: Vec<Aabb<D>>,
    edge_boxes: Vec<Aabb<D>>,
    face_boxes: Vec<Aabb<D>>,
    /// Per surface vertex, its displacement from its anchor at both ends
    /// of the query (reused buffer).
    displacements: Vec<[Vector<D>; 2]>,
    /// Per body, the mean of its surface vertices' displacements `t_b` at
    /// both ends, then their count (reused buffer).
    body_shifts: Vec<([Vector<D>; 2], usize)>,
    /// Per simulation vertex on the surface, `u_i` (reused buffer).
    motion: Vec<f64>,
    cache: CandidateCache<D>,
    searches: usize,
}

/// The cached pairs and the region of states they cover.
struct CandidateCache<const D: usize> {
    /// Per surface vertex, the box it must stay in (empty: no cache).
    vertex_boxes: Vec<Aabb<D>>,
    /// Per surface vertex, its position at the search (the anchor).
    anchor: Vec<Vector<D>>,
    /// What the pairs were found for: `(activation, self_contact)`.
    key: Option<(f64, bool)>,
    /// 2D: (vertex, edge); 3D: (vertex, face).
    point_pairs: Vec<(u32, u32)>,
    /// 3D: (edge, edge).
    edge_pairs: Vec<(u32, u32)>,
    /// Per point pair, `d_k - d_hat - e`: a query drops the pair when its
    /// corners' motion bound is below it.
    point_reach: Vec<f64>,
    /// The same per edge pair.
    edge_reach: Vec<f64>,
}

impl<const D: usize> Default for CandidateFinder<D> {
    fn default() -> Self {
        Self {
            broad_phase: BroadPhase::new(),
            vertex_boxes: Vec::new(),
            edge_boxes: Vec::new(),
            face_boxes: Vec::new(),
            displacements: Vec::new(),
            body_shifts: Vec::new(),
            motion: Vec::new(),
            cache: CandidateCache {
                vertex_boxes: Vec::new(),
                anchor: Vec::new(),
                key: None,
                point_pairs: Vec::new(),
                edge_pairs: Vec::new(),
                point_reach: Vec::new(),
                edge_reach: Vec::new(),
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
        self.measure_motion(mesh, x, &end);
        let (motion, shifts) = (&self.motion, &self.body_shifts);
        let largest = |corners: &[usize]| corners.iter().fold(0.0f64, |m, &v| m.max(motion[v]));
        // The bound on how much closer a pair of bodies `a`, `b` can be
        // than at the anchor, beyond their corners' own motion.
        let apart = |a: usize, b: usize| {
            if a == b {
                return 0.0;
            }
            let ([a0, a1], [b0, b1]) = (shifts[a].0, shifts[b].0);
            let shift = (a0 - b0).norm().max((a1 - b1).norm());
            if shift.is_nan() { f64::INFINITY } else { shift }
        };
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
        let half = activation / 2.0;
        let candidate = |stencil: &ContactStencil, bodies: (usize, usize), reach: f64| {
            let (a, b) = stencil.sides();
            !(largest(a) + largest(b) + apart(bodies.0, bodies.1) < reach)
                && box_of(a).inflated(half).overlaps(&box_of(b).inflated(half))
        };
        let cache = &self.cache;
        for (&(s, p), &reach) in cache.point_pairs.iter().zip(&cache.point_reach) {
            let (stencil, other) = if D == 2 {
                (point_edge(mesh, s, p), mesh.edge_body(p as usize))
            } else {
                (point_triangle(mesh, s, p), mesh.face_body(p as usize))
            };
            if candidate(&stencil, (mesh.vertex_body(s as usize), other), reach) {
                stencils.push(stencil);
            }
        }
        for (&(a, b), &reach) in cache.edge_pairs.iter().zip(&cache.edge_reach) {
            let stencil = edge_edge(mesh, a, b);
            let bodies = (mesh.edge_body(a as usize), mesh.edge_body(b as usize));
            if candidate(&stencil, bodies, reach) {
                stencils.push(stencil);
            }
        }
    }

    /// `u_i` of every surface vertex and `t_b` of every body (see the
    /// certificate of distance) for the query at `x` (and `end`), from the
    /// cache's anchor.
    fn measure_motion(
        &mut self,
        mesh: &CollisionMesh,
        x: &[Vector<D>],
        end: &impl Fn(usize) -> Option<Vector<D>>,
    ) {
        let zero = Vector::<D>::zeros();
        self.displacements.clear();
        self.body_shifts.clear();
        for (s, (&v, anchor)) in mesh.vertices().iter().zip(&self.cache.anchor).enumerate() {
            let moved = [x[v] - anchor, end(v).unwrap_or(x[v]) - anchor];
            let body = mesh.vertex_body(s);
            if body >= self.body_shifts.len() {
                self.body_shifts.resize(body + 1, ([zero; 2], 0));
            }
            let (sum, count) = &mut self.body_shifts[body];
            sum[0] += moved[0];
            sum[1] += moved[1];
            *count += 1;
            self.displacements.push(moved);
        }
        for (sum, count) in &mut self.body_shifts {
            if *count > 0 {
                let n = *count as f64;
                *sum = [sum[0] / n, sum[1] / n];
            }
        }
        // A coordinate that is not a number (a position, or through its
        // body's mean) makes the motion unbounded: no pair it touches is
        // dropped by the certificate (the boxes decide, as without it).
        let bounded = |u: f64| if u.is_nan() { f64::INFINITY } else { u };
        self.motion.resize(x.len(), 0.0);
        for (s, (&v, moved)) in mesh.vertices().iter().zip(&self.displacements).enumerate() {
            let [t0, t1] = self.body_shifts[mesh.vertex_body(s)].0;
            self.motion[v] = bounded((moved[0] - t0).norm()).max(bounded((moved[1] - t1).norm()));
        }
    }

    /// A grid search over the cache boxes of the query (each surface
    /// vertex's box at `x` and `end`, grown by `activation`): the new cached
    /// pairs, with their distances at `x` (the new anchor).
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
            let b = end(v).map_or(b, |e| b.union_point(&e).union_point(&(e + (e - x[v]))));
            b.inflated(margin)
        }));
        cache.anchor.clear();
        cache.anchor.extend(mesh.vertices().iter().map(|&v| x[v]));
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
        } else {
            let keep = |s: usize, f: usize| {
                let v = mesh.vertices()[s];
                !mesh.faces()[f].contains(&v)
                    && distinct_bodies(mesh.vertex_body(s), mesh.face_body(f))
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
            self.broad_phase.pairs_within(
                &self.edge_boxes,
                activation,
                keep,
                &mut cache.edge_pairs,
            );
        }
        cache.measure_reach(mesh, x, activation, &mut self.motion);
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

    /// Each cached pair's `d_k - d_hat - e` from its distance at the
    /// anchor `x` (see [`CandidateFinder`]); NaN where a coordinate is not
    /// a number, which no comparison passes, so such a pair is never
    /// dropped. The pairs that no covered query can keep are forgotten:
    /// while each vertex stays in its cache box it moves at most `R_v`, the
    /// distance from its anchor to the box's farthest corner, so a pair
    /// whose `d_k - d_hat - e` exceeds `max_{i in A} R_i + max_{j in B} R_j`
    /// stays beyond `d_hat` until the next search. `reach_of_box` is a
    /// buffer for `R_v` by simulation vertex.
    fn measure_reach(
        &mut self,
        mesh: &CollisionMesh,
        x: &[Vector<D>],
        activation: f64,
        reach_of_box: &mut Vec<f64>,
    ) {
        let magnitude = self
            .vertex_boxes
            .iter()
            .flat_map(|b| b.min.iter().chain(b.max.iter()))
            .fold(0.0f64, |m, c| m.max(c.abs()));
        let margin = activation + 1e-9 * magnitude;
        reach_of_box.resize(x.len(), 0.0);
        for ((&v, b), a) in mesh
            .vertices()
            .iter()
            .zip(&self.vertex_boxes)
            .zip(&self.anchor)
        {
            let farthest = (b.min - a).abs().sup(&(b.max - a).abs());
            reach_of_box[v] = farthest.norm();
        }
        let largest =
            |corners: &[usize]| corners.iter().fold(0.0f64, |m, &v| m.max(reach_of_box[v]));
        // The pair's reach, or None when it can never be kept.
        let reach = |stencil: ContactStencil| {
            let reach = stencil.distance_squared(x).sqrt() * (1.0 - 1e-9) - margin;
            let (a, b) = stencil.sides();
            (!(largest(a) + largest(b) < reach)).then_some(reach)
        };
        let point_stencil = if D == 2 { point_edge } else { point_triangle };
        let kept = |pairs: &mut Vec<(u32, u32)>,
                    reaches: &mut Vec<f64>,
                    stencil: &dyn Fn(u32, u32) -> ContactStencil| {
            reaches.clear();
            pairs.retain(|&(a, b)| match reach(stencil(a, b)) {
                Some(r) => {
                    reaches.push(r);
                    true
                }
                None => false,
            });
        };
        kept(&mut self.point_pairs, &mut self.point_reach, &|s, p| {
            point_stencil(mesh, s, p)
        });
        kept(&mut self.edge_pairs, &mut self.edge_reach, &|a, b| {
            edge_edge(mesh, a, b)
        });
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
mod tests;
