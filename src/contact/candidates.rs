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
pub struct CandidateFinder<const D: usize> {
    broad_phase: BroadPhase<D>,
    vertex_boxes: Vec<Aabb<D>>,
    edge_boxes: Vec<Aabb<D>>,
    face_boxes: Vec<Aabb<D>>,
    pairs: Vec<(u32, u32)>,
}

impl<const D: usize> Default for CandidateFinder<D> {
    fn default() -> Self {
        Self {
            broad_phase: BroadPhase::new(),
            vertex_boxes: Vec::new(),
            edge_boxes: Vec::new(),
            face_boxes: Vec::new(),
            pairs: Vec::new(),
        }
    }
}

impl<const D: usize> CandidateFinder<D> {
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
        let box_of = |corners: &[usize]| -> Aabb<D> {
            let mut b = Aabb::empty();
            for &v in corners {
                b = b.union_point(&x[v]);
                if let Some(dx) = dx {
                    b = b.union_point(&(x[v] + dx[v]));
                }
            }
            b
        };
        self.vertex_boxes.clear();
        self.vertex_boxes
            .extend(mesh.vertices().iter().map(|&v| box_of(&[v])));
        self.edge_boxes.clear();
        self.edge_boxes
            .extend(mesh.edges().iter().map(|e| box_of(e)));
        let distinct_bodies = |a: usize, b: usize| self_contact || a != b;
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
                &mut self.pairs,
            );
            stencils.extend(self.pairs.iter().map(|&(s, e)| {
                let v = mesh.vertices()[s as usize];
                let edge = mesh.edges()[e as usize];
                ContactStencil {
                    kind: StencilKind::PointEdge,
                    vertices: [v, edge[0], edge[1], usize::MAX],
                    mollifier_threshold: 0.0,
                }
            }));
            return;
        }
        self.face_boxes.clear();
        self.face_boxes
            .extend(mesh.faces().iter().map(|f| box_of(f)));
        let keep = |s: usize, f: usize| {
            let v = mesh.vertices()[s];
            !mesh.faces()[f].contains(&v) && distinct_bodies(mesh.vertex_body(s), mesh.face_body(f))
        };
        self.broad_phase.pairs_between(
            &self.vertex_boxes,
            &self.face_boxes,
            activation,
            keep,
            &mut self.pairs,
        );
        stencils.extend(self.pairs.iter().map(|&(s, f)| {
            let v = mesh.vertices()[s as usize];
            let face = mesh.faces()[f as usize];
            ContactStencil {
                kind: StencilKind::PointTriangle,
                vertices: [v, face[0], face[1], face[2]],
                mollifier_threshold: 0.0,
            }
        }));
        let keep = |a: usize, b: usize| {
            let (ea, eb) = (mesh.edges()[a], mesh.edges()[b]);
            !ea.iter().any(|v| eb.contains(v))
                && distinct_bodies(mesh.edge_body(a), mesh.edge_body(b))
        };
        self.broad_phase
            .pairs_within(&self.edge_boxes, activation, keep, &mut self.pairs);
        stencils.extend(self.pairs.iter().map(|&(a, b)| {
            let (ea, eb) = (mesh.edges()[a as usize], mesh.edges()[b as usize]);
            ContactStencil {
                kind: StencilKind::EdgeEdge,
                vertices: [ea[0], ea[1], eb[0], eb[1]],
                mollifier_threshold: 1e-3
                    * mesh.edge_rest_length_squared(a as usize)
                    * mesh.edge_rest_length_squared(b as usize),
            }
        }));
    }
}
