//! Projection of a symmetric matrix onto the positive semi-definite cone.
//!
//! With the eigen-decomposition `H = Q diag(lambda) Q^T`, the nearest PSD matrix
//! in the Frobenius norm is `Q diag(max(lambda, 0)) Q^T` (Teran et al. 2005;
//! the "projected Newton" of IPC). Element Hessians are projected before
//! assembly, so the global matrix is PSD and, with the mass matrix added,
//! positive definite: the Newton direction is always a descent direction.

use nalgebra::DMatrix;

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
}
