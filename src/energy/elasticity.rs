//! Hyperelastic strain energy of linear simplices, with its gradient and projected Hessian.
//!
//! With constant strain per element `e`, `U = sum_e V_e Psi(F_e)` and
//! `F_e = D_s D_m^{-1}`. Writing `B = D_m^{-1}` and the shape-function gradients
//! `g_a = B^T e_a` for the vertices `a = 1..D` and `g_0 = -sum_a g_a`, one has
//! `dF/dx_{a,k} = e_k g_a^T`, hence
//!
//! ```text
//! dU/dx_a                 = V P g_a,
//! d2U/dx_{a,k} dx_{b,l}   = V sum_{j,n} (dP/dF_{l n})_{k j} (g_a)_j (g_b)_n.
//! ```
//!
//! The per-element work (gradient and Hessian in one pass, the Hessian made
//! PSD by projecting `dP/dF`, everything fixed-size) is
//! `element_derivatives.rs`. Elements are processed into per-element slots
//! (in parallel for large meshes, on the calling thread below
//! `PARALLEL_MIN_ELEMENTS`, where a rayon dispatch would cost more than the
//! work), which are then summed per vertex (or per matrix entry) in a fixed
//! order, so the result is bitwise the same whatever the thread count. The
//! slots live in the [`SparseHessian`], so a Newton iteration allocates
//! nothing here.
//!
//! The finite-volume force of the report equals `-dU/dx_a`; see
//! [`crate::finite_volume`].

use super::ElementField;
use super::EnergyTerm;
use super::element_derivatives::{ElementSlots, element_gradient_and_hessian};
use crate::assembly::{SparseHessian, element_slot_index, element_slot_len};
use crate::material::{HyperelasticMaterial, Material, with_material};
use crate::math::{DenseMatrix, Matrix, Polynomial, Vector, determinant, first_root_in};
use crate::mesh::{Mesh, RestElement, edge_matrix};
use rayon::prelude::*;
use std::sync::Arc;

/// The fraction of its volume an element may keep at least in one
/// line-search step, for a material that forbids inversion (IPC's
/// injective-step filter, Li et al. 2020): 10% in 2D, 20% in 3D. Relative,
/// so no element is ever held at a fixed floor.
pub const fn volume_kept_per_step(dimension: usize) -> f64 {
    if dimension == 2 { 0.1 } else { 0.2 }
}

/// Elements per rayon task.
const ELEMENTS_PER_TASK: usize = 256;
/// Below this many elements (or vertices) a pass runs on the calling thread.
pub(crate) const PARALLEL_MIN_ELEMENTS: usize = 4 * ELEMENTS_PER_TASK;

/// The strain energy of a mesh made of one material.
pub struct Elasticity<const D: usize> {
    mesh: Arc<Mesh<D>>,
    material: Material,
    /// For each vertex, the slots `e * (D + 1) + a` of the elements around it, in element order.
    vertex_slot_offsets: Vec<usize>,
    vertex_slots: Vec<usize>,
}

/// Gradient of the linear shape function of local vertex `a` (constant over the element).
fn shape_gradient<const D: usize>(dm_inv: &Matrix<D>, a: usize) -> Vector<D> {
    if a == 0 {
        -dm_inv.row_sum().transpose()
    } else {
        dm_inv.row(a - 1).transpose()
    }
}

impl<const D: usize> Elasticity<D> {
    /// The strain energy of `mesh` made of `material`.
    pub fn new(mesh: Arc<Mesh<D>>, material: Material) -> Self {
        let nodes = D + 1;
        let mut counts = vec![0usize; mesh.vertex_count() + 1];
        for simplex in mesh.simplices() {
            for &v in simplex {
                counts[v + 1] += 1;
            }
        }
        for v in 0..mesh.vertex_count() {
            counts[v + 1] += counts[v];
        }
        let mut next = counts.clone();
        let mut slots = vec![0usize; counts[mesh.vertex_count()]];
        for (e, simplex) in mesh.simplices().enumerate() {
            for (a, &v) in simplex.iter().enumerate() {
                slots[next[v]] = e * nodes + a;
                next[v] += 1;
            }
        }
        Self {
            mesh,
            material,
            vertex_slot_offsets: counts,
            vertex_slots: slots,
        }
    }

    /// The material.
    pub fn material(&self) -> &Material {
        &self.material
    }

    /// The mesh.
    pub fn mesh(&self) -> &Arc<Mesh<D>> {
        &self.mesh
    }

    fn deformation_gradients(&self, x: &[Vector<D>]) -> Vec<Matrix<D>> {
        (0..self.mesh.element_count())
            .into_par_iter()
            .with_min_len(ELEMENTS_PER_TASK)
            .map(|e| self.mesh.deformation_gradient(e, x))
            .collect()
    }

    /// `D + 1` gradient vectors per element, `dU_e/dx_a = V P g_a`.
    fn element_gradients<M: HyperelasticMaterial<D>>(
        &self,
        material: &M,
        x: &[Vector<D>],
    ) -> Vec<Vector<D>> {
        let nodes = D + 1;
        let mut out = vec![Vector::<D>::zeros(); self.mesh.element_count() * nodes];
        out.par_chunks_mut(nodes)
            .with_min_len(ELEMENTS_PER_TASK)
            .enumerate()
            .for_each(|(e, slot)| {
                let RestElement { dm_inv, volume } = self.mesh.rest_elements()[e];
                let p = material.first_piola(&self.mesh.deformation_gradient(e, x));
                for (a, g) in slot.iter_mut().enumerate() {
                    *g = p * shape_gradient(&dm_inv, a) * volume;
                }
            });
        out
    }

    /// Fills the element slots of this mesh, `hessian_slots`
    /// ([`element_slot_len`] per element, packed lower triangles) and `gradient_slots` (`D + 1` per
    /// element), with `scale` times each element's gradient and
    /// Hessian: PSD-projected if `project`, exact otherwise.
    pub fn fill_element_slots(
        &self,
        (x, scale, project): (&[Vector<D>], f64, bool),
        hessian_slots: &mut [f64],
        gradient_slots: &mut [Vector<D>],
    ) {
        let size = element_slot_len(D);
        let mesh = &*self.mesh;
        with_material!(&self.material, m => {
            let fill = |(e, (hessian, gradient)): (usize, (&mut [f64], &mut [Vector<D>]))| {
                element_gradient_and_hessian(m, mesh, (e, x, scale), project, ElementSlots { gradient, hessian });
            };
            if mesh.element_count() < PARALLEL_MIN_ELEMENTS {
                hessian_slots
                    .chunks_mut(size)
                    .zip(gradient_slots.chunks_mut(D + 1))
                    .enumerate()
                    .for_each(fill);
            } else {
                hessian_slots
                    .par_chunks_mut(size)
                    .zip(gradient_slots.par_chunks_mut(D + 1))
                    .with_min_len(ELEMENTS_PER_TASK)
                    .enumerate()
                    .for_each(fill);
            }
        });
    }

    /// Adds the gradient slots (as filled by [`Self::fill_element_slots`])
    /// into `gradient`, per vertex in element order.
    pub fn add_gradient_slots(&self, gradient_slots: &[Vector<D>], gradient: &mut [Vector<D>]) {
        // Vertices after the mesh's (an obstacle's points) have no elements.
        let gradient = &mut gradient[..self.vertex_slot_offsets.len() - 1];
        let add = |(v, g): (usize, &mut Vector<D>)| {
            for &slot in
                &self.vertex_slots[self.vertex_slot_offsets[v]..self.vertex_slot_offsets[v + 1]]
            {
                *g += gradient_slots[slot];
            }
        };
        if gradient.len() < PARALLEL_MIN_ELEMENTS {
            gradient.iter_mut().enumerate().for_each(add);
        } else {
            gradient
                .par_iter_mut()
                .with_min_len(ELEMENTS_PER_TASK)
                .enumerate()
                .for_each(add);
        }
    }

    /// Gradient and Hessian (projected if `project`) in one pass over the
    /// elements, added into `gradient` and `hessian`.
    fn gradient_and_hessian_pass(
        &self,
        (x, scale, project): (&[Vector<D>], f64, bool),
        gradient: &mut [Vector<D>],
        hessian: &mut SparseHessian<D>,
    ) {
        let (hessian_slots, gradient_slots) = hessian.element_slots_mut();
        self.fill_element_slots((x, scale, project), hessian_slots, gradient_slots);
        self.add_gradient_slots(gradient_slots, gradient);
        hessian.gather_element_buffer();
    }

    /// The element Hessian of element `e`, exact or PSD-projected (through
    /// `dP/dF`, as assembled), as a dense matrix (for tests and analysis).
    fn dense_element_hessian(&self, e: usize, x: &[Vector<D>], project: bool) -> DenseMatrix {
        let size = D * (D + 1);
        let mut hessian = vec![0.0; element_slot_len(D)];
        let mut gradient = vec![Vector::<D>::zeros(); D + 1];
        let slots = ElementSlots {
            gradient: &mut gradient,
            hessian: &mut hessian,
        };
        with_material!(&self.material, m => element_gradient_and_hessian(m, &*self.mesh, (e, x, 1.0), project, slots));
        DenseMatrix::from_fn(size, size, |p, q| {
            hessian[element_slot_index(size, p.max(q), p.min(q))]
        })
    }

    /// The element Hessian of element `e` before projection (for tests and analysis).
    pub fn unprojected_element_hessian(&self, e: usize, x: &[Vector<D>]) -> DenseMatrix {
        self.dense_element_hessian(e, x, false)
    }

    /// The element Hessian of element `e` as assembled: `V G^T [dP/dF]_+ G`
    /// (for tests and analysis).
    pub fn projected_element_hessian(&self, e: usize, x: &[Vector<D>]) -> DenseMatrix {
        self.dense_element_hessian(e, x, true)
    }

    /// Minimum volume ratio `J = det F` over all elements.
    pub fn min_volume_ratio(&self, x: &[Vector<D>]) -> f64 {
        self.deformation_gradients(x)
            .iter()
            .map(determinant)
            .fold(f64::INFINITY, f64::min)
    }

    /// A per-element scalar at positions `x`.
    pub fn element_field(&self, x: &[Vector<D>], field: ElementField) -> Vec<f64> {
        let gradients = self.deformation_gradients(x);
        with_material!(&self.material, m => gradients
            .par_iter()
            .with_min_len(ELEMENTS_PER_TASK)
            .map(|f| match field {
                ElementField::EnergyDensity => m.energy_density(f),
                ElementField::VolumeRatio => determinant(f),
                ElementField::VonMises => {
                    let p = HyperelasticMaterial::<D>::first_piola(m, f);
                    let out_of_plane = if D == 2 { m.plane_strain_normal_stress(f) } else { 0.0 };
                    von_mises(&p, f, out_of_plane)
                }
            })
            .collect())
    }

    /// Element `e`'s cap on the step `x -> x + t dx` (Neo-Hookean, StVK):
    /// the first `t` at which its volume ratio falls to
    /// [`volume_kept_per_step`] of its current value (IPC's relative
    /// filter), halved until the ratio there is safely above half of that.
    fn element_cap(&self, e: usize, x: &[Vector<D>], dx: &[Vector<D>]) -> f64 {
        let simplex = self.mesh.simplex(e);
        let dm_inv = self.mesh.rest_elements()[e].dm_inv;
        let ds = edge_matrix(x, simplex);
        let dds = edge_matrix(dx, simplex);
        let ratio = |t: f64| determinant(&((ds + dds * t) * dm_inv));
        // J(t) = det(F + t dF), dF = dD_s D_m^{-1}, in closed form.
        let mut volume = Polynomial::determinant_of_line(&(ds * dm_inv), &(dds * dm_inv));
        let j0 = volume.coefficients()[0];
        if !(j0 > 0.0) {
            // Not reachable (the energy is infinite there): keep the
            // element from crossing zero again.
            return first_root_in(&volume, 1.0).map_or(1.0, |t| 0.9 * t);
        }
        let floor = volume_kept_per_step(D) * j0;
        volume.coefficients_mut()[0] -= floor;
        // For t in [0, 1], J(t) - floor >= c_0 - sum of the negative
        // higher coefficients: when that is positive (most elements,
        // most steps) there is no root to look for.
        let lower_bound = volume.coefficients()[1..]
            .iter()
            .fold(volume.coefficients()[0], |bound, c| bound + c.min(0.0));
        let mut cap = if lower_bound > 0.0 {
            1.0
        } else {
            first_root_in(&volume, 1.0).unwrap_or(1.0)
        };
        let mut halvings = 0;
        while !(ratio(cap) >= 0.5 * floor) && halvings < 60 {
            cap *= 0.5;
            halvings += 1;
        }
        cap
    }
}

/// Von Mises equivalent stress of the Cauchy stress `sigma = P F^T / J`:
/// `sqrt(3/2 s:s)` with the deviator `s` of the 3D stress. A 2D stress is
/// completed by its plane-strain `sigma_zz` (`out_of_plane`; 0 in 3D), so
/// `s:s = sigma:sigma + sigma_zz^2 - (tr(sigma) + sigma_zz)^2 / 3`.
fn von_mises<const D: usize>(p: &Matrix<D>, f: &Matrix<D>, out_of_plane: f64) -> f64 {
    let j = determinant(f);
    if !(j > 0.0) {
        return f64::NAN;
    }
    let sigma = p * f.transpose() / j;
    let squares = sigma.norm_squared() + out_of_plane.powi(2);
    let trace = sigma.trace() + out_of_plane;
    (1.5 * (squares - trace.powi(2) / 3.0)).max(0.0).sqrt()
}

impl<const D: usize> EnergyTerm<D> for Elasticity<D> {
    fn name(&self) -> &'static str {
        "elastic"
    }

    fn value(&self, x: &[Vector<D>]) -> f64 {
        let count = self.mesh.element_count();
        with_material!(&self.material, m => {
            let energy = |e: usize| self.mesh.rest_elements()[e].volume * m.energy_density(&self.mesh.deformation_gradient(e, x));
            // A sequential sum in element order either way: the same
            // result whatever the thread count.
            if count < PARALLEL_MIN_ELEMENTS {
                (0..count).map(energy).sum()
            } else {
                let energies: Vec<f64> = (0..count)
                    .into_par_iter()
                    .with_min_len(ELEMENTS_PER_TASK)
                    .map(energy)
                    .collect();
                energies.iter().sum()
            }
        })
    }

    fn add_gradient(&self, x: &[Vector<D>], scale: f64, gradient: &mut [Vector<D>]) {
        let slots = with_material!(&self.material, m => self.element_gradients(m, x));
        gradient
            .par_iter_mut()
            .with_min_len(ELEMENTS_PER_TASK)
            .enumerate()
            .for_each(|(v, g)| {
                for &slot in
                    &self.vertex_slots[self.vertex_slot_offsets[v]..self.vertex_slot_offsets[v + 1]]
                {
                    *g += slots[slot] * scale;
                }
            });
    }

    fn add_hessian(&self, x: &[Vector<D>], scale: f64, hessian: &mut SparseHessian<D>) {
        let (hessian_slots, gradient_slots) = hessian.element_slots_mut();
        self.fill_element_slots((x, scale, true), hessian_slots, gradient_slots);
        hessian.gather_element_buffer();
    }

    /// One pass over the elements for both (`F`, `P` and `dP/dF` once per element).
    fn add_gradient_and_hessian(
        &self,
        x: &[Vector<D>],
        scale: f64,
        gradient: &mut [Vector<D>],
        hessian: &mut SparseHessian<D>,
    ) {
        self.gradient_and_hessian_pass((x, scale, true), gradient, hessian);
    }

    /// The same pass with the exact element Hessians `V G^T (dP/dF) G`.
    fn add_gradient_and_unprojected_hessian(
        &self,
        x: &[Vector<D>],
        scale: f64,
        gradient: &mut [Vector<D>],
        hessian: &mut SparseHessian<D>,
    ) {
        self.gradient_and_hessian_pass((x, scale, false), gradient, hessian);
    }

    /// The inversion policy of the material. A material that allows
    /// inversion (stable Neo-Hookean, fixed corotated) has no cap: 1. One
    /// that forbids it (Neo-Hookean, StVK with its volume barrier) gets
    /// IPC's relative filter: for each element the first `t` where
    /// `J(t) = det((D_s + t dD_s) D_m^{-1})` (a polynomial of degree `D` in
    /// `t`) falls to `c J(0)`, `c` = `volume_kept_per_step` (0.1 in 2D, 0.2
    /// in 3D); 1 if none does in `(0, 1]`. The cap shrinks with the element
    /// but is never 0 while `J(0) > 0` (the barrier's energy keeps the
    /// minimiser away from `J = 0`, so the filter only stops a step from
    /// jumping over it). Round-off in the coefficients is caught by
    /// evaluating `J` at the cap itself (halved until it holds).
    fn max_step(&mut self, x: &[Vector<D>], dx: &[Vector<D>]) -> f64 {
        if !self.material.forbids_inversion() {
            return 1.0;
        }
        let cap = |e: usize| self.element_cap(e, x, dx);
        // The minimum does not depend on the order: no need for a fixed one.
        let count = self.mesh.element_count();
        if count < PARALLEL_MIN_ELEMENTS {
            (0..count).map(cap).fold(1.0, f64::min)
        } else {
            (0..count)
                .into_par_iter()
                .with_min_len(ELEMENTS_PER_TASK)
                .map(cap)
                .reduce(|| 1.0, f64::min)
        }
    }
}
