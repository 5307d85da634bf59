//! The rotation-variant singular value decomposition `F = U diag(sigma) V^T`
//! of a `D x D` matrix, with `U` and `V` rotations (`det U = det V = 1`).
//!
//! The plain SVD has `U`, `V` orthogonal and `sigma >= 0`; when `det F < 0`
//! one of them is a reflection. Isotropic elasticity wants rotations (Irving
//! et al. 2004): the reflection is moved into the last (smallest) singular
//! value, which becomes negative for an inverted element. Fixed-size and on
//! the stack (nalgebra's 2 x 2 and 3 x 3 SVDs), so it can run per element
//! per Newton iteration without touching the heap.

use super::{Matrix, Vector, determinant};
use nalgebra::{Matrix2, Matrix3};

/// `(U, sigma, V)` with `F = U diag(sigma) V^T`, `U` and `V` rotations and
/// `sigma` sorted by magnitude, largest first (only the last may be negative).
pub fn rotation_svd<const D: usize>(f: &Matrix<D>) -> (Matrix<D>, Vector<D>, Matrix<D>) {
    let (mut u, mut sigma, mut v) = (
        Matrix::<D>::zeros(),
        Vector::<D>::zeros(),
        Matrix::<D>::zeros(),
    );
    macro_rules! decompose {
        ($matrix:ty) => {{
            // Singular values sorted, largest first.
            let svd = <$matrix>::from_column_slice(f.as_slice()).svd(true, true);
            let (Some(u_d), Some(v_t)) = (svd.u, svd.v_t) else {
                unreachable!("both factors were requested")
            };
            u.as_mut_slice().copy_from_slice(u_d.as_slice());
            v.as_mut_slice().copy_from_slice(v_t.transpose().as_slice());
            sigma
                .as_mut_slice()
                .copy_from_slice(svd.singular_values.as_slice());
        }};
    }
    match D {
        1 => {
            u[(0, 0)] = 1.0;
            v[(0, 0)] = 1.0;
            sigma[0] = f[(0, 0)];
            return (u, sigma, v);
        }
        2 => decompose!(Matrix2<f64>),
        3 => decompose!(Matrix3<f64>),
        _ => unimplemented!("SVD of a {D} x {D} matrix"),
    }
    if is_reflection(&u) {
        u.column_mut(D - 1).neg_mut();
        sigma[D - 1] = -sigma[D - 1];
    }
    if is_reflection(&v) {
        v.column_mut(D - 1).neg_mut();
        sigma[D - 1] = -sigma[D - 1];
    }
    (u, sigma, v)
}

/// Whether the orthogonal `q` has determinant -1 (closed form for 2 x 2 and 3 x 3).
fn is_reflection<const D: usize>(q: &Matrix<D>) -> bool {
    let det = match D {
        2 => q[(0, 0)] * q[(1, 1)] - q[(0, 1)] * q[(1, 0)],
        3 => {
            let column = |j: usize| nalgebra::Vector3::new(q[(0, j)], q[(1, j)], q[(2, j)]);
            column(0).cross(&column(1)).dot(&column(2))
        }
        _ => determinant(q),
    };
    det < 0.0
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
}
