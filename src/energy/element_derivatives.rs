//! The per-element kernel of the strain energy: gradient and PSD-projected Hessian of one simplex in one fused pass, on the stack.
//!
//! For element `e` with `F = D_s D_m^{-1}`, shape-function gradients `g_a`
//! (`g_a = B^T e_a` for `a = 1..D`, `g_0 = -sum_a g_a`, `B = D_m^{-1}`) and
//! rest volume `V`, the derivatives of `U_e = V Psi(F)` are
//!
//! ```text
//! dU_e/dx_{a,k}              = V (P g_a)_k
//! d2U_e/dx_{a,k} dx_{b,l}    = V sum_{j,n} A_{(k j),(l n)} (g_a)_j (g_b)_n,
//! A_{(k j),(l n)}            = d2 Psi / dF_{k j} dF_{l n}     (dP/dF, D^2 x D^2)
//! ```
//!
//! that is `H_e = V G^T A G` with `G = dvec(F)/dx_e` (`D^2 x D(D+1)`).
//!
//! **Projection on `dP/dF`.** `A` is projected onto the PSD cone
//! (`A_+ = Q max(Lambda, 0) Q^T`, an eigen-decomposition of a `4 x 4` matrix
//! in 2D, `9 x 9` in 3D) and the element Hessian is built from `A_+`:
//! `H_e = V G^T A_+ G` is PSD because `v^T H_e v = V (G v)^T A_+ (G v) >= 0`.
//! Where `A` is PSD already, `H_e` is the exact element Hessian. This is the
//! projection of Teran et al. (2005) and of IPC's reference code on the
//! stress derivative rather than on the `D(D+1)`-square element Hessian: a
//! smaller eigenproblem (`9 x 9` instead of `12 x 12` per tetrahedron) and
//! the same guarantee (a descent direction); the two projections differ
//! (both are PSD, both equal the exact Hessian where `A` is PSD).
//! In practice no `9 x 9` eigen-decomposition runs: a Cholesky test keeps a
//! positive definite `A` as it is, and otherwise `A` is projected block by
//! block in the SVD frame of `F`, with the blocks in closed form from the
//! material (`crate::math::psd` writes this out) and `H_e` built there.
//!
//! Everything is fixed-size: `F`, `P`, `A` and the shape gradients live on
//! the stack, and the results are written straight into the element's slots
//! (`D + 1` gradient vectors and the lower triangle of the symmetric
//! `D(D+1)`-square Hessian, packed: 78 numbers per tetrahedron, not 144),
//! so a pass over the mesh allocates nothing. `F` is computed once per
//! element per pass, and `P` and `dP/dF` come from one call to the material.

use crate::assembly::element_slot_index;
use crate::material::HyperelasticMaterial;
use crate::math::{
    Matrix, SvdFrameProjection, TWIST_PAIRS, Vector, project_stress_derivative_to_psd,
    project_svd_frame_blocks, rotation_svd, svd_frame_blocks_by_rotation,
    symmetrise_and_test_definite,
};
use crate::mesh::{Mesh, RestElement};

/// Largest `D^2` (3D): the stress derivative fits in `MAX_STRAIN^2` numbers.
const MAX_STRAIN: usize = 9;
/// Largest number of vertices of a simplex (a tetrahedron).
const MAX_NODES: usize = 4;

/// The shape-function gradients `g_0 .. g_D` of an element (the first `D + 1` entries).
fn shape_gradients<const D: usize>(dm_inv: &Matrix<D>) -> [Vector<D>; MAX_NODES] {
    let mut g = [Vector::<D>::zeros(); MAX_NODES];
    for a in 1..=D {
        g[a] = dm_inv.row(a - 1).transpose();
        g[0] -= g[a];
    }
    g
}

/// Where one element's derivatives go.
pub struct ElementSlots<'a, const D: usize> {
    /// `D + 1` gradient vectors, one per local vertex.
    pub gradient: &'a mut [Vector<D>],
    /// The lower triangle of the symmetric `D(D+1)`-square Hessian, packed
    /// by columns ([`element_slot_index`]), local unknown `a D + k`.
    pub hessian: &'a mut [f64],
}

/// Writes `scale * dU_e/dx` of element `e` and `scale *` its Hessian into
/// `slots`: PSD-projected through `dP/dF` if `project`, exact otherwise
/// (Newton with projection on demand tries that first; tests compare both).
pub fn element_gradient_and_hessian<const D: usize, M: HyperelasticMaterial<D>>(
    material: &M,
    mesh: &Mesh<D>,
    (e, x, scale): (usize, &[Vector<D>], f64),
    project: bool,
    slots: ElementSlots<'_, D>,
) {
    let ElementSlots { gradient, hessian } = slots;
    let RestElement { dm_inv, volume } = mesh.rest_elements()[e];
    let f = mesh.deformation_gradient(e, x);
    let (p, dp) = material.first_piola_and_derivative(&f);
    let g = shape_gradients(&dm_inv);
    let weight = volume * scale;
    for (a, slot) in gradient.iter_mut().enumerate().take(D + 1) {
        *slot = p * g[a] * weight;
    }

    // A as a column-major D^2 x D^2 matrix, row (k j) = k D + j, column (l n).
    let strain = D * D;
    let mut a_flat = [0.0; MAX_STRAIN * MAX_STRAIN];
    for l in 0..D {
        for n in 0..D {
            let column = &mut a_flat[(l * D + n) * strain..(l * D + n + 1) * strain];
            for k in 0..D {
                for j in 0..D {
                    column[k * D + j] = dp[l][n][(k, j)];
                }
            }
        }
    }
    if project && !symmetrise_and_test_definite::<D>(&mut a_flat[..strain * strain]) {
        // Every material here is isotropic: the block-diagonal projection in
        // the SVD frame (blocks in closed form where the material has them),
        // used without rotating it back.
        let (u, sigma, v) = rotation_svd(&f);
        let blocks = material
            .stress_derivative_in_svd_frame(&sigma)
            .or_else(|| svd_frame_blocks_by_rotation::<D>(&a_flat[..strain * strain], &u, &v));
        if let Some(blocks) = blocks {
            let frame = project_svd_frame_blocks(u, v, &blocks);
            hessian_in_svd_frame(&frame, &g, weight, hessian);
            return;
        }
        project_stress_derivative_to_psd::<D>(&mut a_flat[..strain * strain]);
    }
    hessian_from_stress_derivative::<D>(&a_flat, &g, weight, hessian);
}

/// `H = weight G^T A G` into the packed lower triangle `hessian`, for the
/// column-major `D^2 x D^2` stress derivative `a`.
fn hessian_from_stress_derivative<const D: usize>(
    a_flat: &[f64],
    g: &[Vector<D>; MAX_NODES],
    weight: f64,
    hessian: &mut [f64],
) {
    let strain = D * D;
    // H[(a k), (b l)] = weight sum_j (sum_n A[(k j), (l n)] g_b[n]) g_a[j].
    let size = D * (D + 1);
    for b in 0..=D {
        for l in 0..D {
            let mut w = [0.0; MAX_STRAIN];
            for n in 0..D {
                let column = &a_flat[(l * D + n) * strain..(l * D + n + 1) * strain];
                let gbn = g[b][n] * weight;
                for (wi, ci) in w.iter_mut().zip(column) {
                    *wi += ci * gbn;
                }
            }
            // Column q = (b l) of the lower triangle: rows p = (a k) >= q.
            let q = b * D + l;
            let start = element_slot_index(size, q, q);
            let out = &mut hessian[start..start + size - q];
            for p in q..size {
                let (a, k) = (p / D, p % D);
                let mut sum = 0.0;
                for j in 0..D {
                    sum += w[k * D + j] * g[a][j];
                }
                out[p - q] = sum;
            }
        }
    }
}

/// `H = weight W^T A'_+ W` into the packed lower triangle `hessian`, from
/// the projection in the SVD frame: `W = K^T G` has the column
/// `W[(i j), (a k)] = U_{k i} (V^T g_a)_j` (the image of
/// `dF/dx_{a,k} = e_k g_a^T` in the frame), and `A'_+` is block-diagonal.
fn hessian_in_svd_frame<const D: usize>(
    frame: &SvdFrameProjection<D>,
    g: &[Vector<D>; MAX_NODES],
    weight: f64,
    hessian: &mut [f64],
) {
    let size = D * (D + 1);
    let SvdFrameProjection {
        u,
        v,
        stretch,
        twist,
        ..
    } = frame;
    // Columns of W, and of A'_+ W, one per local unknown (a k).
    let mut w = [[0.0; MAX_STRAIN]; MAX_NODES * 3];
    let mut aw = [[0.0; MAX_STRAIN]; MAX_NODES * 3];
    for a in 0..=D {
        let vg = v.transpose() * g[a];
        for k in 0..D {
            let column = &mut w[a * D + k];
            for i in 0..D {
                for j in 0..D {
                    column[i * D + j] = u[(k, i)] * vg[j];
                }
            }
            let (column, image) = (&w[a * D + k], &mut aw[a * D + k]);
            for i in 0..D {
                let mut sum = 0.0;
                for j in 0..D {
                    sum += stretch[(i, j)] * column[j * D + j];
                }
                image[i * D + i] = sum * weight;
            }
            for (&(p, q), &[s, t, r]) in TWIST_PAIRS.iter().zip(twist).take(D * (D - 1) / 2) {
                let (x, y) = (column[p * D + q], column[q * D + p]);
                image[p * D + q] = (s * x + t * y) * weight;
                image[q * D + p] = (t * x + r * y) * weight;
            }
        }
    }
    let strain = D * D;
    for q in 0..size {
        let start = element_slot_index(size, q, q);
        let out = &mut hessian[start..start + size - q];
        for p in q..size {
            let mut sum = 0.0;
            for r in 0..strain {
                sum += w[p][r] * aw[q][r];
            }
            out[p - q] = sum;
        }
    }
}
