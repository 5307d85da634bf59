//! The report's finite-volume force, and why it equals the finite-element gradient.
//!
//! The report (after Teran et al. 2003) computes the elastic force on a vertex
//! `V` as a sum over the elements around it of `P n_E A_E`, where `n_E A_E` is
//! the area-weighted outward normal of the face of the element opposite to `V`
//! in the rest configuration (a length times a normal in 2D), and `P` is the
//! element's first Piola-Kirchhoff stress. It wondered why this should equal
//! the finite-element force `-dU/dx_V`. The computation is short:
//!
//! * Linear shape functions: `N_V` is 1 at `V` and 0 on the opposite face, so
//!   its gradient points from that face towards `V` with length `1 / h_V`,
//!   where `h_V` is the height of `V` above the face: `grad N_V = -n_E / h_V`.
//! * The simplex volume is `V_e = A_E h_V / D`, so `grad N_V = -n_E A_E / (D V_e)`.
//! * With constant strain, `U_e = V_e Psi(F)` and `dF/dx_V = (.) grad N_V^T`, so
//!   `dU_e/dx_V = V_e P grad N_V = -P n_E A_E / D`.
//!
//! Hence `f_V = -sum_e dU_e/dx_V = (1/D) sum_E P n_E A_E`: the report's sum is
//! the finite-element force up to the constant `1/D` (Teran et al. write the
//! same sum over the `D` faces incident to `V`, `-(1/3) sum P N_i A_i`, which is
//! the same thing because the area-weighted normals of a closed simplex sum to
//! zero). Finite volumes on linear simplices *are* linear finite elements.

use crate::material::HyperelasticMaterial;
use crate::math::{Vector, determinant};
use crate::mesh::{Mesh, edge_matrix};

/// The outward area-weighted normal `n A` (rest configuration) of the face of
/// `simplex` opposite to its local vertex `opposite`.
///
/// Computed from the cofactor identity: for the rest edge matrix `D_m`, the
/// columns of `det(D_m) D_m^{-T}` are the area-weighted normals (times
/// `(D-1)!`) of the faces through vertex 0; the face opposite vertex 0 closes
/// the sum to zero.
pub fn face_area_normal<const D: usize>(
    rest: &[Vector<D>],
    simplex: &[usize],
    opposite: usize,
) -> Vector<D> {
    let dm = edge_matrix(rest, simplex);
    let det = determinant(&dm);
    let dm_inv_t = crate::math::inverse(&dm)
        .expect("non-degenerate rest element")
        .transpose();
    let factorial: f64 = (1..D).map(|k| k as f64).product();
    // Face opposite local vertex a >= 1 has inward normal along column a-1 of D_m^{-T}.
    let normal_of = |a: usize| -> Vector<D> { -dm_inv_t.column(a - 1) * (det / factorial) };
    if opposite == 0 {
        -(1..=D).map(normal_of).sum::<Vector<D>>()
    } else {
        normal_of(opposite)
    }
}

/// The report's sum `sum_E P n_E A_E` per vertex, exactly as written (without
/// the `1/D`).
pub fn report_face_sum<const D: usize, M: HyperelasticMaterial<D>>(
    mesh: &Mesh<D>,
    material: &M,
    x: &[Vector<D>],
) -> Vec<Vector<D>> {
    let mut sums = vec![Vector::<D>::zeros(); mesh.vertex_count()];
    for (e, simplex) in mesh.simplices().enumerate() {
        let p = material.first_piola(&mesh.deformation_gradient(e, x));
        for (a, &vertex) in simplex.iter().enumerate() {
            sums[vertex] += p * face_area_normal(mesh.rest_positions(), simplex, a);
        }
    }
    sums
}

/// The finite-volume elastic force per vertex, `f_V = (1/D) sum_E P n_E A_E`.
pub fn finite_volume_forces<const D: usize, M: HyperelasticMaterial<D>>(
    mesh: &Mesh<D>,
    material: &M,
    x: &[Vector<D>],
) -> Vec<Vector<D>> {
    report_face_sum(mesh, material, x)
        .into_iter()
        .map(|s| s / D as f64)
        .collect()
}
