//! The strain energy of a scene of one or several bodies, each of its own
//! material: one [`Elasticity`] per body over the body's own mesh, placed at
//! the body's vertex and element offsets in the scene's mesh.
//!
//! The scene's mesh is the bodies' meshes one after the other (vertices and
//! elements in body order, each simplex's vertex order kept), so body `b`
//! owns the contiguous vertices `V_b` and elements `E_b` and
//! `U(x) = sum_b U_b(x[V_b])`. Values, gradients and step caps are the
//! bodies' own on their slices. For the Hessian, each body fills the scene
//! Hessian's element slots `E_b` directly (the same local vertex order, no
//! copy), which are then gathered once. A single body is its `Elasticity`
//! over the whole mesh, unchanged.
//!
//! Why not a per-element material index inside [`Elasticity`]: it would mean
//! touching every loop of that term (its value, gradient, Hessian, step cap,
//! fields), where this keeps the term as it is.

use super::{Elasticity, ElementField, EnergyTerm};
use crate::assembly::{FactorisationError, SparseHessian, element_slot_len};
use crate::material::Material;
use crate::math::Vector;
use crate::mesh::Mesh;
use std::ops::Range;
use std::sync::Arc;

/// One body's strain energy and where it sits in the scene's mesh.
struct BodyPart<const D: usize> {
    elasticity: Elasticity<D>,
    vertices: Range<usize>,
    elements: Range<usize>,
}

/// The strain energy of every body of a scene, named `elastic`.
pub struct BodyElasticity<const D: usize> {
    parts: Vec<BodyPart<D>>,
}

impl<const D: usize> BodyElasticity<D> {
    /// One body: `material` over all of `mesh`.
    pub fn single(mesh: Arc<Mesh<D>>, material: Material) -> Self {
        let (vertices, elements) = (0..mesh.vertex_count(), 0..mesh.element_count());
        Self {
            parts: vec![BodyPart {
                elasticity: Elasticity::new(mesh, material),
                vertices,
                elements,
            }],
        }
    }

    /// Several bodies, each its mesh (with its own vertex numbering) and
    /// material, in the order their meshes are concatenated in the scene's.
    /// (It no longer fails: the bodies need no Hessians of their own. The
    /// `Result` stays for the callers in `sim`.)
    pub fn bodies(bodies: Vec<(Arc<Mesh<D>>, Material)>) -> Result<Self, FactorisationError> {
        if bodies.len() == 1 {
            let (mesh, material) = bodies.into_iter().next().expect("one body");
            return Ok(Self::single(mesh, material));
        }
        let (mut vertex, mut element) = (0, 0);
        let mut parts = Vec::with_capacity(bodies.len());
        for (mesh, material) in bodies {
            let vertices = vertex..vertex + mesh.vertex_count();
            let elements = element..element + mesh.element_count();
            (vertex, element) = (vertices.end, elements.end);
            parts.push(BodyPart {
                elasticity: Elasticity::new(mesh, material),
                vertices,
                elements,
            });
        }
        Ok(Self { parts })
    }

    /// The material of each body, in order.
    pub fn materials(&self) -> Vec<&Material> {
        self.parts.iter().map(|p| p.elasticity.material()).collect()
    }

    /// Minimum volume ratio `J = det F` over all elements.
    pub fn min_volume_ratio(&self, x: &[Vector<D>]) -> f64 {
        self.parts
            .iter()
            .map(|p| p.elasticity.min_volume_ratio(&x[p.vertices.clone()]))
            .fold(f64::INFINITY, f64::min)
    }

    /// A per-element scalar at positions `x`, in the scene's element order.
    pub fn element_field(&self, x: &[Vector<D>], field: ElementField) -> Vec<f64> {
        let mut out = Vec::new();
        for p in &self.parts {
            out.extend(p.elasticity.element_field(&x[p.vertices.clone()], field));
        }
        out
    }
}

impl<const D: usize> BodyElasticity<D> {
    /// Every body fills its own elements' slots of the scene's `hessian`
    /// (projected if `project`).
    fn fill_element_slots(
        &self,
        (x, scale, project): (&[Vector<D>], f64, bool),
        hessian: &mut SparseHessian<D>,
    ) {
        let block = element_slot_len(D);
        let (hessian_slots, gradient_slots) = hessian.element_slots_mut();
        for p in &self.parts {
            let (elements, vertices) = (p.elements.clone(), p.vertices.clone());
            p.elasticity.fill_element_slots(
                (&x[vertices], scale, project),
                &mut hessian_slots[elements.start * block..elements.end * block],
                &mut gradient_slots[elements.start * (D + 1)..elements.end * (D + 1)],
            );
        }
    }

    /// Gradient and Hessian (projected if `project`) of every body in one
    /// pass, added into `gradient` and `hessian`.
    fn gradient_and_hessian_pass(
        &self,
        (x, scale, project): (&[Vector<D>], f64, bool),
        gradient: &mut [Vector<D>],
        hessian: &mut SparseHessian<D>,
    ) {
        let [part] = &self.parts[..] else {
            self.fill_element_slots((x, scale, project), hessian);
            let (_, gradient_slots) = hessian.element_slots_mut();
            for p in &self.parts {
                let slots = p.elements.start * (D + 1)..p.elements.end * (D + 1);
                p.elasticity
                    .add_gradient_slots(&gradient_slots[slots], &mut gradient[p.vertices.clone()]);
            }
            hessian.gather_element_buffer();
            return;
        };
        if project {
            part.elasticity
                .add_gradient_and_hessian(x, scale, gradient, hessian);
        } else {
            part.elasticity
                .add_gradient_and_unprojected_hessian(x, scale, gradient, hessian);
        }
    }
}

impl<const D: usize> EnergyTerm<D> for BodyElasticity<D> {
    fn name(&self) -> &'static str {
        "elastic"
    }

    fn value(&self, x: &[Vector<D>]) -> f64 {
        self.parts
            .iter()
            .map(|p| p.elasticity.value(&x[p.vertices.clone()]))
            .sum()
    }

    fn add_gradient(&self, x: &[Vector<D>], scale: f64, gradient: &mut [Vector<D>]) {
        for p in &self.parts {
            let v = p.vertices.clone();
            p.elasticity
                .add_gradient(&x[v.clone()], scale, &mut gradient[v]);
        }
    }

    fn add_hessian(&self, x: &[Vector<D>], scale: f64, hessian: &mut SparseHessian<D>) {
        let [part] = &self.parts[..] else {
            self.fill_element_slots((x, scale, true), hessian);
            hessian.gather_element_buffer();
            return;
        };
        part.elasticity.add_hessian(x, scale, hessian);
    }

    fn add_gradient_and_hessian(
        &self,
        x: &[Vector<D>],
        scale: f64,
        gradient: &mut [Vector<D>],
        hessian: &mut SparseHessian<D>,
    ) {
        self.gradient_and_hessian_pass((x, scale, true), gradient, hessian);
    }

    fn add_gradient_and_unprojected_hessian(
        &self,
        x: &[Vector<D>],
        scale: f64,
        gradient: &mut [Vector<D>],
        hessian: &mut SparseHessian<D>,
    ) {
        self.gradient_and_hessian_pass((x, scale, false), gradient, hessian);
    }

    fn max_step(&mut self, x: &[Vector<D>], dx: &[Vector<D>]) -> f64 {
        self.parts
            .iter_mut()
            .map(|p| {
                let v = p.vertices.clone();
                p.elasticity.max_step(&x[v.clone()], &dx[v])
            })
            .fold(1.0, f64::min)
    }

    fn begin_step(&mut self, x: &[Vector<D>], v: &[Vector<D>]) {
        for p in &mut self.parts {
            let r = p.vertices.clone();
            p.elasticity.begin_step(&x[r.clone()], &v[r]);
        }
    }
}
