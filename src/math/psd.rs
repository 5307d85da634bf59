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
//! **Isotropic materials** ([`svd_frame_blocks_by_rotation`],
//! [`project_svd_frame_blocks`]).
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
//! fraction of the cost; the element kernel does not even rotate back, it
//! builds `V G^T A_+ G = V W^T A'_+ W` from `W = K^T G` (a rank-one pattern
//! per column) and the sparse blocks. The blocks come in closed form from
//! the material where it has them
//! (`HyperelasticMaterial::stress_derivative_in_svd_frame`: a few dozen
//! operations from `sigma`), otherwise from rotating its `dP/dF` into the
//! frame. Should the rotated `A'` not be block-diagonal (a material that is
//! not isotropic), the full eigen-decomposition runs instead.

use super::Matrix;
use nalgebra::{DMatrix, SMatrix};

/// Entries of the largest stress derivative (`9 x 9`, 3D).
const MAX_STRAIN_SQUARED: usize = 81;

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
        // The eigen-decomposition only when the Cholesky test fails.
        2 => !definite_4(a) && clamp_4(a),
        3 => !definite_9(a) && clamp_9(a),
        _ => unimplemented!("stress derivative of a {D}-dimensional material"),
    }
}

/// `$name(a)` for a column-major `n x n` matrix `a`: symmetrises `a` in
/// place; returns whether it is positive definite (a Cholesky factorisation
/// of a copy on the stack succeeds; it stops at the first pivot that is not
/// positive), in which case it is its own projection.
macro_rules! fixed_definiteness {
    ($name:ident, $n:literal) => {
        fn $name(a: &mut [f64]) -> bool {
            const N: usize = $n;
            let a: &mut [f64; N * N] = a.try_into().expect("an n x n matrix");
            for col in 0..N {
                for row in col + 1..N {
                    let mean = 0.5 * (a[col * N + row] + a[row * N + col]);
                    a[col * N + row] = mean;
                    a[row * N + col] = mean;
                }
            }
            // Lower factor, column by column (left-looking): l[j][i], i >= j.
            let mut l = [0.0; N * N];
            for j in 0..N {
                let mut pivot = a[j * N + j];
                for k in 0..j {
                    pivot -= l[k * N + j] * l[k * N + j];
                }
                if !(pivot > 0.0) {
                    return false;
                }
                let pivot = pivot.sqrt();
                l[j * N + j] = pivot;
                for i in j + 1..N {
                    let mut value = a[j * N + i];
                    for k in 0..j {
                        value -= l[k * N + i] * l[k * N + j];
                    }
                    l[j * N + i] = value / pivot;
                }
            }
            true
        }
    };
}
fixed_definiteness!(definite_4, 4);
fixed_definiteness!(definite_9, 9);

/// `$name(a)` for a symmetric column-major `n x n` matrix `a`: replaces it
/// by `Q max(Lambda, 0) Q^T` (its eigen-decomposition, fixed-size, on the
/// stack); returns whether any eigenvalue was negative (else `a` is left as
/// it is).
macro_rules! fixed_clamp {
    ($name:ident, $n:literal) => {
        fn $name(a: &mut [f64]) -> bool {
            let eigen = SMatrix::<f64, $n, $n>::from_column_slice(a).symmetric_eigen();
            if eigen.eigenvalues.iter().all(|&l| l >= 0.0) {
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
fixed_clamp!(clamp_3, 3);
fixed_clamp!(clamp_4, 4);
fixed_clamp!(clamp_9, 9);

/// Replaces the column-major `D^2 x D^2` stress derivative `a` by its
/// symmetric part and says whether that is positive definite, in which case
/// it is its own PSD projection (the cheap first test before any
/// eigen-decomposition or SVD).
pub fn symmetrise_and_test_definite<const D: usize>(a: &mut [f64]) -> bool {
    match D {
        2 => definite_4(a),
        3 => definite_9(a),
        _ => false,
    }
}

/// Projects the symmetric `2 x 2` `[[p, q], [q, r]]` onto the PSD cone in
/// closed form, as `[p, q, r]`.
fn project_2x2(p: f64, q: f64, r: f64) -> [f64; 3] {
    let mean = 0.5 * (p + r);
    let radius = (0.25 * (p - r) * (p - r) + q * q).sqrt();
    let (high, low) = (mean + radius, mean - radius);
    if low >= 0.0 {
        return [p, q, r];
    }
    if high <= 0.0 {
        return [0.0; 3];
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
    [high * c * c, high * c * s, high * s * s]
}

/// The PSD projection of an isotropic material's stress derivative in the
/// SVD frame of `F = U diag(sigma) V^T` (see the module documentation):
/// `[dP/dF]_+ = K A'_+ K^T` with `K = U (x) V` and `A'_+` block-diagonal,
/// kept as its blocks so that element Hessians can be built from it without
/// rotating it back (`G^T K A'_+ K^T G = W^T A'_+ W`, `W = K^T G`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SvdFrameProjection<const D: usize> {
    /// The left rotation `U`.
    pub u: Matrix<D>,
    /// The right rotation `V`.
    pub v: Matrix<D>,
    /// The projected stretch block, over the strain components `(a a)`.
    pub stretch: Matrix<D>,
    /// The projected twist/flip blocks `[[p, q], [q, r]]` stored as
    /// `[p, q, r]`, over `((a b), (b a))` for the pairs `a < b` in the order
    /// `(0 1), (0 2), (1 2)` (the first `D (D - 1) / 2` are used).
    pub twist: [[f64; 3]; 3],
}

/// The pairs `a < b` of strain indices, in the order of [`SvdFrameProjection::twist`].
pub const TWIST_PAIRS: [(usize, usize); 3] = [(0, 1), (0, 2), (1, 2)];

/// `U^T M V` for the `D x D` matrix `M` read by `entry(k, j)`.
fn rotate_into_frame<const D: usize>(
    u: &Matrix<D>,
    v: &Matrix<D>,
    entry: impl Fn(usize, usize) -> f64,
) -> Matrix<D> {
    u.transpose() * Matrix::<D>::from_fn(entry) * v
}

/// Projects a symmetric `D x D` matrix onto the PSD cone.
fn project_small<const D: usize>(m: &Matrix<D>) -> Matrix<D> {
    if m.cholesky().is_some() {
        return *m;
    }
    let mut out = *m;
    match D {
        1 => out[(0, 0)] = m[(0, 0)].max(0.0),
        2 => {
            let [p, q, r] = project_2x2(m[(0, 0)], m[(0, 1)], m[(1, 1)]);
            out.as_mut_slice().copy_from_slice(&[p, q, q, r]);
        }
        3 => {
            clamp_3(out.as_mut_slice());
        }
        _ => unimplemented!("projection of a {D} x {D} block"),
    }
    out
}

/// The blocks of an isotropic material's stress derivative in the SVD frame
/// of `F = U diag(sigma) V^T` (Smith et al. 2019), before projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SvdFrameBlocks<const D: usize> {
    /// `A'_{(a a),(b b)}`, the block coupling the stretches.
    pub stretch: Matrix<D>,
    /// `[A'_{(a b),(a b)}, A'_{(a b),(b a)}, A'_{(b a),(b a)}]` for the pairs
    /// of [`TWIST_PAIRS`] (the first `D (D - 1) / 2` are used).
    pub twist: [[f64; 3]; 3],
}

/// The blocks of the stress derivative `a` (column-major `D^2 x D^2`, row
/// `(k j) = k D + j`, column `(l n)`) in the frame of the rotations `u`,
/// `v`: `A' = K^T A K`, `K = U (x) V`, formed as a tensor rotation, `U^T M V`
/// on each `D x D` column and then each row of `A` (`4 D^5` multiplications,
/// 972 in 3D, not the `2 D^6 = 1458` of two dense products). `None` when `A'`
/// is not block-diagonal (the material is not isotropic): then the full
/// eigen-decomposition ([`project_stress_derivative_to_psd`]) is needed.
/// For materials that do not give their blocks in closed form.
pub fn svd_frame_blocks_by_rotation<const D: usize>(
    a: &[f64],
    u: &Matrix<D>,
    v: &Matrix<D>,
) -> Option<SvdFrameBlocks<D>> {
    let n = D * D;
    // C = K^T A, column by column; then A' = C K, row by row.
    let mut c = [0.0; MAX_STRAIN_SQUARED];
    for col in 0..n {
        let column = &a[col * n..col * n + n];
        let r = rotate_into_frame(u, v, |k, j| column[k * D + j]);
        for i in 0..D {
            for j in 0..D {
                c[col * n + i * D + j] = r[(i, j)];
            }
        }
    }
    let mut rotated = [0.0; MAX_STRAIN_SQUARED];
    for row in 0..n {
        let r = rotate_into_frame(u, v, |k, l| c[(k * D + l) * n + row]);
        for i in 0..D {
            for j in 0..D {
                rotated[(i * D + j) * n + row] = r[(i, j)];
            }
        }
    }
    // Symmetric part of A' at (row, col).
    let at = |row: usize, col: usize| 0.5 * (rotated[col * n + row] + rotated[row * n + col]);
    // Block structure: (a a) with (b b); (a b) with itself and (b a).
    let same_block = |i: usize, j: usize| {
        let (a, b, c, d) = (i / D, i % D, j / D, j % D);
        (a == b && c == d) || (a == c && b == d) || (a == d && b == c)
    };
    let (mut off_block, mut total) = (0.0, 0.0);
    for col in 0..n {
        for row in 0..n {
            let value = rotated[col * n + row];
            total += value * value;
            if !same_block(row, col) {
                off_block += value * value;
            }
        }
    }
    if off_block > 1e-20 * total {
        return None;
    }
    let mut twist = [[0.0; 3]; 3];
    for (t, &(a, b)) in TWIST_PAIRS.iter().enumerate().take(D * (D - 1) / 2) {
        let (i, j) = (a * D + b, b * D + a);
        twist[t] = [at(i, i), at(i, j), at(j, j)];
    }
    Some(SvdFrameBlocks {
        stretch: Matrix::<D>::from_fn(|i, j| at(i * D + i, j * D + j)),
        twist,
    })
}

/// Projects the blocks of a stress derivative in the frame `u`, `v` onto
/// the PSD cone, block by block (closed form for the `2 x 2` twist blocks):
/// the projection of the whole `dP/dF`, kept in the frame.
pub fn project_svd_frame_blocks<const D: usize>(
    u: Matrix<D>,
    v: Matrix<D>,
    blocks: &SvdFrameBlocks<D>,
) -> SvdFrameProjection<D> {
    let mut twist = [[0.0; 3]; 3];
    for (t, &[p, q, r]) in blocks.twist.iter().enumerate().take(D * (D - 1) / 2) {
        twist[t] = project_2x2(p, q, r);
    }
    SvdFrameProjection {
        u,
        v,
        stretch: project_small(&blocks.stretch),
        twist,
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
