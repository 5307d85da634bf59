//! The rotation-variant singular value decomposition `F = U diag(sigma) V^T`
//! of a `D x D` matrix, with `U` and `V` rotations (`det U = det V = 1`).
//!
//! The plain SVD has `U`, `V` orthogonal and `sigma >= 0`; when `det F < 0`
//! one of them is a reflection. Isotropic elasticity wants rotations (Irving
//! et al. 2004): the reflection is moved into the last (smallest) singular
//! value, which becomes negative for an inverted element. Fixed-size and on
//! the stack, so it can run per element per Newton iteration without
//! touching the heap: nalgebra's 2 x 2 SVD, and in 3D the Jacobi-and-QR
//! method of McAdams et al. (2011) written out below, which yields rotations
//! and the signed last value directly. (nalgebra's 3 x 3 SVD is the same
//! method with a general symmetric eigensolver and Householder QR: 500 ns
//! per call here, a third of a compressed tetrahedron's whole Hessian.)

use super::{Matrix, Vector, determinant};
use nalgebra::Matrix2;

/// `(U, sigma, V)` with `F = U diag(sigma) V^T`, `U` and `V` rotations and
/// `sigma` sorted by magnitude, largest first (only the last may be negative).
pub fn rotation_svd<const D: usize>(f: &Matrix<D>) -> (Matrix<D>, Vector<D>, Matrix<D>) {
    let (mut u, mut sigma, mut v) = (
        Matrix::<D>::zeros(),
        Vector::<D>::zeros(),
        Matrix::<D>::zeros(),
    );
    match D {
        1 => {
            u[(0, 0)] = 1.0;
            v[(0, 0)] = 1.0;
            sigma[0] = f[(0, 0)];
        }
        2 => {
            // Singular values sorted, largest first; U and V orthogonal.
            let svd = Matrix2::from_column_slice(f.as_slice()).svd(true, true);
            let (Some(u_2), Some(v_t)) = (svd.u, svd.v_t) else {
                unreachable!("both factors were requested")
            };
            u.as_mut_slice().copy_from_slice(u_2.as_slice());
            v.as_mut_slice().copy_from_slice(v_t.transpose().as_slice());
            sigma
                .as_mut_slice()
                .copy_from_slice(svd.singular_values.as_slice());
            // A reflection moves into the last singular value.
            for q in [&mut u, &mut v] {
                if determinant(q) < 0.0 {
                    q.column_mut(D - 1).neg_mut();
                    sigma[D - 1] = -sigma[D - 1];
                }
            }
        }
        3 => {
            // Already rotations, with the sign of det F on the last value.
            let (u_3, sigma_3, v_3) = jacobi_svd3(f.as_slice());
            u.as_mut_slice().copy_from_slice(&u_3);
            v.as_mut_slice().copy_from_slice(&v_3);
            sigma.as_mut_slice().copy_from_slice(&sigma_3);
        }
        _ => unimplemented!("SVD of a {D} x {D} matrix"),
    }
    (u, sigma, v)
}

/// Column-major `3 x 3` matrices as flat arrays, `m[3 j + i]` = entry `(i, j)`.
type Flat3 = [f64; 9];

/// Applies the plane rotation `(c, s)` to columns `p` and `q` of `m`:
/// `m_p <- c m_p - s m_q`, `m_q <- s m_p + c m_q`.
fn rotate_columns(m: &mut Flat3, p: usize, q: usize, c: f64, s: f64) {
    for k in 0..3 {
        let (x, y) = (m[3 * p + k], m[3 * q + k]);
        m[3 * p + k] = c * x - s * y;
        m[3 * q + k] = s * x + c * y;
    }
}

/// The `3 x 3` rotation-variant SVD of McAdams et al. (2011) in double
/// precision: cyclic Jacobi on `S = F^T F` gives `V` (a product of plane
/// rotations), its columns are sorted by `|F v_i|` (a swap negates one column,
/// so `V` stays a rotation), and Givens QR of `B = F V` gives the rotation `U`
/// and the diagonal `R = U^T F V`, whose entries are `sigma` (the last has
/// the sign of `det F`). Exact Jacobi rotations converge quadratically; the
/// sweeps stop when the off-diagonal of `S` is at round-off.
fn jacobi_svd3(f: &[f64]) -> (Flat3, [f64; 3], Flat3) {
    let at = |m: &Flat3, i: usize, j: usize| m[3 * j + i];
    let mut s: Flat3 = [0.0; 9];
    for i in 0..3 {
        for j in 0..3 {
            s[3 * j + i] = (0..3).map(|k| f[3 * i + k] * f[3 * j + k]).sum();
        }
    }
    let scale = s.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut v: Flat3 = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    const PAIRS: [(usize, usize); 3] = [(0, 1), (0, 2), (1, 2)];
    for _sweep in 0..16 {
        let off = at(&s, 0, 1).abs() + at(&s, 0, 2).abs() + at(&s, 1, 2).abs();
        if !(off > f64::EPSILON * scale) {
            break;
        }
        for (p, q) in PAIRS {
            let spq = at(&s, p, q);
            if spq == 0.0 {
                continue;
            }
            // The rotation that zeroes S_pq: t = tan(theta), the smaller root.
            let theta = (at(&s, q, q) - at(&s, p, p)) / (2.0 * spq);
            // (`sqrt`, not `hypot`, a slow library call: `theta^2` may
            // overflow to infinity, which gives `t = 0`, the right limit.)
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let sn = t * c;
            // S <- J^T S J, V <- V J.
            rotate_columns(&mut s, p, q, c, sn);
            for k in 0..3 {
                let (x, y) = (s[3 * k + p], s[3 * k + q]);
                s[3 * k + p] = c * x - sn * y;
                s[3 * k + q] = sn * x + c * y;
            }
            rotate_columns(&mut v, p, q, c, sn);
        }
    }
    // B = F V, columns sorted by norm, largest first.
    let mut b: Flat3 = [0.0; 9];
    for i in 0..3 {
        for j in 0..3 {
            b[3 * j + i] = (0..3).map(|k| f[3 * k + i] * v[3 * j + k]).sum();
        }
    }
    let norm = |m: &Flat3, j: usize| (0..3).map(|k| m[3 * j + k] * m[3 * j + k]).sum::<f64>();
    let mut rho = [norm(&b, 0), norm(&b, 1), norm(&b, 2)];
    for (p, q) in PAIRS {
        if rho[p] < rho[q] {
            for m in [&mut b, &mut v] {
                for k in 0..3 {
                    let x = m[3 * p + k];
                    m[3 * p + k] = m[3 * q + k];
                    m[3 * q + k] = -x;
                }
            }
            rho.swap(p, q);
        }
    }
    // Givens QR: zero b_10, b_20, b_21 with rotations of rows; U collects them.
    let mut u: Flat3 = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    for (p, q) in PAIRS {
        let (x, y) = (b[3 * p + p], b[3 * p + q]);
        let r = (x * x + y * y).sqrt();
        let (c, sn) = if r == 0.0 { (1.0, 0.0) } else { (x / r, y / r) };
        for k in 0..3 {
            let (bp, bq) = (b[3 * k + p], b[3 * k + q]);
            b[3 * k + p] = c * bp + sn * bq;
            b[3 * k + q] = c * bq - sn * bp;
        }
        rotate_columns(&mut u, p, q, c, -sn);
    }
    (u, [b[0], b[4], b[8]], v)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check<const D: usize>(f: Matrix<D>) {
        let (u, sigma, v) = rotation_svd(&f);
        let back = u * Matrix::<D>::from_diagonal(&sigma) * v.transpose();
        assert!((back - f).amax() < 1e-12 * f.amax().max(1.0), "{f}");
        for r in [u, v] {
            assert!((r.transpose() * r - Matrix::<D>::identity()).amax() < 1e-12);
            assert!((determinant(&r) - 1.0).abs() < 1e-12);
        }
        for i in 1..D {
            assert!(sigma[i - 1] >= sigma[i].abs() - 1e-12, "{sigma}");
        }
        assert_eq!(sigma[D - 1] < 0.0, determinant(&f) < 0.0, "{sigma}");
    }

    #[test]
    fn rotations_and_a_signed_last_value_reproduce_the_matrix() {
        check(Matrix::<2>::new(1.2, 0.3, -0.1, 0.8));
        check(Matrix::<2>::new(-1.2, 0.3, 0.1, 0.8)); // inverted
        check(Matrix::<3>::new(
            1.1, 0.2, 0.0, -0.3, 0.9, 0.1, 0.05, 0.0, 1.3,
        ));
        check(Matrix::<3>::new(
            1.1, 0.2, 0.0, -0.3, 0.9, 0.1, 0.05, 0.0, -1.3,
        )); // inverted
        check(Matrix::<3>::identity());
        check(Matrix::<3>::new(
            0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        )); // a reflection
    }

    /// The 3 x 3 decomposition on matrices built as `R_1 diag(sigma) R_2`
    /// from known singular values: repeated ones (the rest state), nearly
    /// flat and inverted elements, and extreme stretch. The values must match
    /// (the signed last one included) and the factors reproduce `F`.
    #[test]
    fn jacobi_decomposition_recovers_known_singular_values() {
        let rotation =
            |a: f64, b: f64, c: f64| *nalgebra::Rotation3::from_euler_angles(a, b, c).matrix();
        let cases: [[f64; 3]; 9] = [
            [1.0, 1.0, 1.0],
            [1.0 + 1e-9, 1.0, 1.0 - 1e-9],
            [2.0, 2.0, 0.5],
            [1.5, 1.0, 1e-9],
            [1.2, 0.9, -0.3],
            [1.0, 1.0, -1.0],
            [50.0, 1.0, 0.02],
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
        ];
        for (n, values) in cases.into_iter().enumerate() {
            for k in 0..8 {
                let t = (n * 8 + k) as f64;
                let f = rotation(0.3 * t, 1.1 - 0.2 * t, 0.7 * t)
                    * Matrix::<3>::from_diagonal(&Vector::<3>::from(values))
                    * rotation(-0.5 * t, 0.4 + 0.1 * t, 2.0 - 0.3 * t);
                let (u, sigma, v) = rotation_svd(&f);
                let back = u * Matrix::<3>::from_diagonal(&sigma) * v.transpose();
                let scale = values[0].abs().max(1.0);
                assert!((back - f).amax() < 1e-13 * scale, "{values:?}: {f}");
                for r in [u, v] {
                    assert!((r.transpose() * r - Matrix::<3>::identity()).amax() < 1e-13);
                    assert!((determinant(&r) - 1.0).abs() < 1e-13);
                }
                for i in 0..3 {
                    assert!(
                        (sigma[i] - values[i]).abs() < 1e-12 * scale,
                        "{values:?}: got {sigma}"
                    );
                }
            }
        }
    }
}
