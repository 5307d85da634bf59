//! Dimension aliases: the one place where 2D and 3D differ by name.
//!
//! Everything else in the crate is generic over `const D: usize` and speaks of
//! [`Vector<D>`] and [`Matrix<D>`]; it never branches on the dimension. A linear
//! simplex in `D` dimensions has `D + 1` vertices (a triangle in 2D, a
//! tetrahedron in 3D).

use nalgebra::{DMatrix, SMatrix, SVector};

/// A point or displacement in `D` dimensions.
pub type Vector<const D: usize> = SVector<f64, D>;
/// A `D x D` matrix (deformation gradient, stress, rest-shape matrix).
pub type Matrix<const D: usize> = SMatrix<f64, D, D>;
/// A 2D vector.
pub type Vector2 = Vector<2>;
/// A 3D vector.
pub type Vector3 = Vector<3>;
/// A dense matrix of run-time size (used for element Hessians of size
/// `D(D+1) x D(D+1)`).
pub type DenseMatrix = DMatrix<f64>;

/// The fourth-order tensor dP/dF, stored as `D x D` blocks:
/// `tensor[k][l]` is the matrix dP/dF_kl.
pub type StressDerivative<const D: usize> = [[Matrix<D>; D]; D];

/// Number of vertices of a simplex in dimension `d`.
pub const fn simplex_vertices(d: usize) -> usize {
    d + 1
}

/// The vertical axis: y in 2D and in 3D (3D scenes are y-up, as in the report).
pub const UP_AXIS: usize = 1;

/// The cofactor matrix `cof F = dJ/dF` (`= J F^{-T}` where `F` is
/// invertible), defined for every `F`. In 3D its columns are
/// `f_1 x f_2, f_2 x f_0, f_0 x f_1` for the columns `f_i` of `F`.
pub fn cofactor<const D: usize>(f: &Matrix<D>) -> Matrix<D> {
    match D {
        1 => Matrix::<D>::from_element(1.0),
        2 => Matrix::<D>::from_fn(|i, j| {
            let sign = if (i + j) % 2 == 0 { 1.0 } else { -1.0 };
            sign * f[(1 - i, 1 - j)]
        }),
        3 => Matrix::<D>::from_fn(|i, j| {
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
            f[(i1, j1)] * f[(i2, j2)] - f[(i2, j1)] * f[(i1, j2)]
        }),
        _ => unimplemented!("cofactor of a {D} x {D} matrix"),
    }
}

/// Determinant of a `D x D` matrix (`D <= 3`), expanded along the first
/// row: `det F = sum_j F_0j (cof F)_0j`, in closed form.
///
/// nalgebra's own `determinant` needs a typenum bound that a generic
/// `const D: usize` cannot name, so the crate keeps this one. It is called
/// for every element in every energy evaluation: the closed form costs a
/// handful of multiplications where elimination with pivoting branched.
pub fn determinant<const D: usize>(m: &Matrix<D>) -> f64 {
    match D {
        1 => m[(0, 0)],
        2 => m[(0, 0)] * m[(1, 1)] - m[(0, 1)] * m[(1, 0)],
        3 => {
            m[(0, 0)] * (m[(1, 1)] * m[(2, 2)] - m[(2, 1)] * m[(1, 2)])
                + m[(0, 1)] * (m[(1, 2)] * m[(2, 0)] - m[(2, 2)] * m[(1, 0)])
                + m[(0, 2)] * (m[(1, 0)] * m[(2, 1)] - m[(2, 0)] * m[(1, 1)])
        }
        _ => unimplemented!("determinant of a {D} x {D} matrix"),
    }
}

/// Inverse of a small square matrix by Gauss-Jordan elimination with partial
/// pivoting (`None` when singular), allocation-free. Used where an inverse
/// must be as exact as elimination makes it (rest shapes: a box's `D_m^{-1}`
/// comes out exact, so an undeformed body has exactly `F = I` and zero
/// energy); the materials' hot loops use the cofactor instead
/// (`F^{-T} = cof F / det F`).
pub fn inverse<const D: usize>(m: &Matrix<D>) -> Option<Matrix<D>> {
    let mut a = *m;
    let mut inv = Matrix::<D>::identity();
    for col in 0..D {
        let pivot = (col..D)
            .max_by(|&i, &j| a[(i, col)].abs().total_cmp(&a[(j, col)].abs()))
            .unwrap_or(col);
        if a[(pivot, col)] == 0.0 || !a[(pivot, col)].is_finite() {
            return None;
        }
        a.swap_rows(pivot, col);
        inv.swap_rows(pivot, col);
        let scale = 1.0 / a[(col, col)];
        for c in 0..D {
            a[(col, c)] *= scale;
            inv[(col, c)] *= scale;
        }
        for row in 0..D {
            if row != col {
                let factor = a[(row, col)];
                for c in 0..D {
                    a[(row, c)] -= factor * a[(col, c)];
                    inv[(row, c)] -= factor * inv[(col, c)];
                }
            }
        }
    }
    inv.iter().all(|v| v.is_finite()).then_some(inv)
}

mod polynomial;
mod psd;
mod svd;

pub use polynomial::{Polynomial, first_root_in};
pub use psd::{
    SvdFrameBlocks, SvdFrameProjection, TWIST_PAIRS, project_stress_derivative_to_psd,
    project_svd_frame_blocks, project_to_psd, svd_frame_blocks_by_rotation,
    symmetrise_and_test_definite,
};
pub use svd::rotation_svd;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn determinant_and_inverse_of_a_pivoting_matrix() {
        // A zero leading entry forces a row swap.
        let m = Matrix::<3>::new(0.0, 2.0, 1.0, 1.0, 0.0, 3.0, 4.0, -1.0, 0.5);
        let expected_det = 0.0 * (0.0 * 0.5 + 3.0) - 2.0 * (1.0 * 0.5 - 12.0) + 1.0 * (-1.0 - 0.0);
        assert!((determinant(&m) - expected_det).abs() < 1e-12);
        let inv = inverse(&m).unwrap();
        assert!((inv * m - Matrix::<3>::identity()).amax() < 1e-12);
        assert_eq!(inverse(&Matrix::<2>::new(1.0, 2.0, 2.0, 4.0)), None);
    }
}
