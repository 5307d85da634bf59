//! Projection of a symmetric matrix onto the positive semi-definite cone.
//!
//! With the eigen-decomposition `H = Q diag(lambda) Q^T`, the nearest PSD matrix
//! in the Frobenius norm is `Q diag(max(lambda, 0)) Q^T` (Teran et al. 2005;
//! the "projected Newton" of IPC).
//!
//! The elasticity projects the stress derivative `dP/dF`, a `D^2 x D^2`
//! matrix ([`project_stress_derivative_to_psd`]: fixed-size, on the stack, a
//! Cholesky attempt first so that a positive definite matrix skips the
//! eigen-decomposition); its element Hessians `V G^T [dP/dF]_+ G` are then PSD,
//! the global matrix is PSD and, with the mass matrix added, positive
//! definite: the Newton direction is always a descent direction.
//! [`project_to_psd`] projects a matrix of any size (tests, analysis).

use nalgebra::{DMatrix, SMatrix};

/// Replaces `h` by its projection onto the PSD cone. Returns whether any
/// eigenvalue had to be clamped.
pub fn project_to_psd(h: &mut DMatrix<f64>) -> bool {
    let symmetric = (&*h + h.transpose()) * 0.5;
    let eigen = symmetric.clone().symmetric_eigen();
    if eigen.eigenvalues.iter().all(|&l| l >= 0.0) {
        *h = symmetric;
        return false;
    }
    let clamped = eigen.eigenvalues.map(|l| l.max(0.0));
    *h = &eigen.eigenvectors * DMatrix::from_diagonal(&clamped) * eigen.eigenvectors.transpose();
    true
}

/// Replaces the column-major `D^2 x D^2` matrix `a` (the stress derivative
/// `dP/dF` of a `D`-dimensional material) by the projection of its symmetric
/// part onto the PSD cone, without touching the heap. Returns whether any
/// eigenvalue had to be clamped.
pub fn project_stress_derivative_to_psd<const D: usize>(a: &mut [f64]) -> bool {
    match D {
        1 => {
            let clamped = a[0] < 0.0;
            a[0] = a[0].max(0.0);
            clamped
        }
        2 => project_4(a),
        3 => project_9(a),
        _ => unimplemented!("stress derivative of a {D}-dimensional material"),
    }
}

/// Symmetrises `a` in place; returns whether it is positive definite (a
/// Cholesky factorisation succeeds), in which case it is its own projection.
macro_rules! fixed_projection {
    ($name:ident, $n:literal) => {
        fn $name(a: &mut [f64]) -> bool {
            let m = SMatrix::<f64, $n, $n>::from_column_slice(a);
            let symmetric = (m + m.transpose()) * 0.5;
            if symmetric.cholesky().is_some() {
                a.copy_from_slice(symmetric.as_slice());
                return false;
            }
            let eigen = symmetric.symmetric_eigen();
            if eigen.eigenvalues.iter().all(|&l| l >= 0.0) {
                a.copy_from_slice(symmetric.as_slice());
                return false;
            }
            let q = eigen.eigenvectors;
            let clamped = eigen.eigenvalues.map(|l| l.max(0.0));
            let projected = q * SMatrix::<f64, $n, $n>::from_diagonal(&clamped) * q.transpose();
            a.copy_from_slice(projected.as_slice());
            true
        }
    };
}
fixed_projection!(project_4, 4);
fixed_projection!(project_9, 9);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clamps_negative_eigenvalues_and_keeps_psd_unchanged() {
        let mut h = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]); // eigenvalues 3, -1
        assert!(project_to_psd(&mut h));
        let expected = DMatrix::from_row_slice(2, 2, &[1.5, 1.5, 1.5, 1.5]);
        assert!((h - expected).norm() < 1e-12);
        let mut spd = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]);
        let before = spd.clone();
        assert!(!project_to_psd(&mut spd));
        assert_eq!(spd, before);
    }

    #[test]
    fn fixed_size_projection_equals_the_dynamic_one() {
        // An indefinite symmetric 4 x 4 and 9 x 9 (entries from a fixed rule).
        for n in [4usize, 9] {
            let entry = |i: usize, j: usize| ((i * 7 + j * 3) % 11) as f64 - 5.0;
            let dense = DMatrix::from_fn(n, n, |i, j| entry(i, j) + entry(j, i));
            let mut expected = dense.clone();
            assert!(project_to_psd(&mut expected));
            let mut flat = dense.as_slice().to_vec();
            let clamped = if n == 4 {
                project_stress_derivative_to_psd::<2>(&mut flat)
            } else {
                project_stress_derivative_to_psd::<3>(&mut flat)
            };
            assert!(clamped);
            let got = DMatrix::from_column_slice(n, n, &flat);
            assert!((got - &expected).amax() < 1e-10 * expected.amax());
            // A positive definite matrix is returned unchanged.
            let spd = &dense * dense.transpose() + DMatrix::identity(n, n);
            let mut flat = spd.as_slice().to_vec();
            let clamped = if n == 4 {
                project_stress_derivative_to_psd::<2>(&mut flat)
            } else {
                project_stress_derivative_to_psd::<3>(&mut flat)
            };
            assert!(!clamped);
            assert_eq!(DMatrix::from_column_slice(n, n, &flat), spd);
        }
    }
}
