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
//!
//! **Isotropic materials** ([`project_isotropic_stress_derivative_to_psd`]).
//! With the rotation-variant SVD `F = U Sigma V^T` (`U`, `V` rotations), an
//! isotropic energy has `dP/dF(F)[U dS V^T] = U dP/dF(Sigma)[dS] V^T`, so in
//! the basis `K = U (x) V` (`K_{(k j),(a b)} = U_{k a} V_{j b}`) the stress
//! derivative `A' = K^T A K` is that at the diagonal `Sigma`, which is
//! block-diagonal (Smith et al. 2019, "Analytic eigensystems for isotropic
//! distortion energies"): one `D x D` block coupling the stretches
//! `(a a)`, and one `2 x 2` block per pair `{(a b), (b a)}` (the twist and
//! flip modes). Projecting the blocks (closed form for `2 x 2`) and rotating
//! back, `A_+ = K A'_+ K^T`, is the same projection as the full
//! eigen-decomposition (it does not depend on the orthonormal basis), at a
//! fraction of the cost. Should `A'` not be block-diagonal (a material that
//! is not isotropic), the full eigen-decomposition runs instead.

use super::Matrix;
use nalgebra::{DMatrix, Matrix2, Matrix3, SMatrix};

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

/// Projects the symmetric `2 x 2` `[[p, q], [q, r]]` onto the PSD cone in
/// closed form; returns the projection and whether anything was clamped.
fn project_2x2(p: f64, q: f64, r: f64) -> ([f64; 3], bool) {
    let mean = 0.5 * (p + r);
    let radius = (0.25 * (p - r) * (p - r) + q * q).sqrt();
    let (high, low) = (mean + radius, mean - radius);
    if low >= 0.0 {
        return ([p, q, r], false);
    }
    if high <= 0.0 {
        return ([0.0; 3], true);
    }
    // Keep the eigenvalue `high` with its unit eigenvector `(c, s)`.
    let (c, s) = if p >= r {
        let (x, y) = (high - r, q);
        let n = x.hypot(y);
        (x / n, y / n)
    } else {
        let (x, y) = (q, high - p);
        let n = x.hypot(y);
        (x / n, y / n)
    };
    ([high * c * c, high * c * s, high * s * s], true)
}

/// A rotation-variant SVD of `f`: `(U, sigma, V)` with `U`, `V` rotations.
macro_rules! rotation_svd {
    ($f:expr, $matrix:ty) => {{
        let svd = <$matrix>::from_column_slice($f).svd(true, true);
        let (mut u, mut v_t) = (svd.u.expect("U asked for"), svd.v_t.expect("V asked for"));
        let last = u.ncols() - 1;
        if u.determinant() < 0.0 {
            u.column_mut(last).neg_mut();
        }
        if v_t.determinant() < 0.0 {
            v_t.row_mut(last).neg_mut();
        }
        (u, v_t.transpose())
    }};
}

macro_rules! isotropic_projection {
    ($name:ident, $d:literal, $n:literal, $matrix:ty, $full:ident) => {
        fn $name(a: &mut [f64], f: &[f64]) -> bool {
            let (u, v) = rotation_svd!(f, $matrix);
            let k = SMatrix::<f64, $n, $n>::from_fn(|row, col| {
                u[(row / $d, col / $d)] * v[(row % $d, col % $d)]
            });
            let m = SMatrix::<f64, $n, $n>::from_column_slice(a);
            let rotated = k.transpose() * ((m + m.transpose()) * 0.5) * k;
            // Block structure: (a a) with (b b); (a b) with itself and (b a).
            let same_block = |i: usize, j: usize| {
                let (a, b, c, d) = (i / $d, i % $d, j / $d, j % $d);
                (a == b && c == d) || (a == c && b == d) || (a == d && b == c)
            };
            let mut off_block = 0.0;
            for j in 0..$n {
                for i in 0..$n {
                    if !same_block(i, j) {
                        off_block += rotated[(i, j)] * rotated[(i, j)];
                    }
                }
            }
            if off_block > 1e-20 * rotated.norm_squared() {
                return $full(a);
            }
            let mut projected = SMatrix::<f64, $n, $n>::zeros();
            let mut clamped = false;
            // The stretch block, D x D over the diagonal entries (a a).
            let stretch = <$matrix>::from_fn(|i, j| rotated[(i * $d + i, j * $d + j)]);
            let stretch = if stretch.cholesky().is_some() {
                stretch
            } else {
                let eigen = stretch.symmetric_eigen();
                if eigen.eigenvalues.iter().any(|&l| l < 0.0) {
                    clamped = true;
                    let q = eigen.eigenvectors;
                    q * <$matrix>::from_diagonal(&eigen.eigenvalues.map(|l| l.max(0.0)))
                        * q.transpose()
                } else {
                    stretch
                }
            };
            for i in 0..$d {
                for j in 0..$d {
                    projected[(i * $d + i, j * $d + j)] = stretch[(i, j)];
                }
            }
            // The twist/flip blocks over (a b), (b a).
            for a in 0..$d {
                for b in a + 1..$d {
                    let (i, j) = (a * $d + b, b * $d + a);
                    let ([p, q, r], c) =
                        project_2x2(rotated[(i, i)], rotated[(i, j)], rotated[(j, j)]);
                    clamped |= c;
                    projected[(i, i)] = p;
                    projected[(i, j)] = q;
                    projected[(j, i)] = q;
                    projected[(j, j)] = r;
                }
            }
            let back = k * projected * k.transpose();
            a.copy_from_slice(back.as_slice());
            clamped
        }
    };
}
isotropic_projection!(project_isotropic_4, 2, 4, Matrix2<f64>, project_4);
isotropic_projection!(project_isotropic_9, 3, 9, Matrix3<f64>, project_9);

/// Like [`project_stress_derivative_to_psd`], for the stress derivative
/// `a` of an isotropic material at `f`: through the block-diagonal form in
/// the SVD frame of `f` (see the module documentation), falling back to the
/// full eigen-decomposition if `a` is not block-diagonal there.
pub fn project_isotropic_stress_derivative_to_psd<const D: usize>(
    a: &mut [f64],
    f: &Matrix<D>,
) -> bool {
    match D {
        2 => project_isotropic_4(a, f.as_slice()),
        3 => project_isotropic_9(a, f.as_slice()),
        _ => project_stress_derivative_to_psd::<D>(a),
    }
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
