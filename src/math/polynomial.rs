//! Real polynomials of low degree: evaluation and the first root in an interval.
//!
//! Used to cap line-search steps: `det(D_s + t dD_s)` is a polynomial of degree
//! `D` in `t`, and the first `t > 0` where it vanishes is where an element
//! would invert. Roots are isolated without any closed-form case analysis:
//! between consecutive critical points (the roots of the derivative, found by
//! the same routine recursively) a polynomial is monotone, so a sign change in
//! such a piece brackets exactly one root, which bisection then refines.
//! The polynomial of `det(A + t B)` has closed-form coefficients
//! ([`Polynomial::determinant_of_line`]). Everything is inline (no heap).

use super::{Matrix, determinant};

/// Most coefficients a polynomial here has (degree 3: `det` of a 3 x 3 in `t`).
pub const MAX_COEFFICIENTS: usize = 4;

/// A polynomial `c_0 + c_1 t + ... + c_n t^n` of degree at most 3, stored
/// inline (no heap: the line search builds one per element per iteration).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Polynomial {
    values: [f64; MAX_COEFFICIENTS],
    len: usize,
}

/// At most three real roots, ascending (inline, like [`Polynomial`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Roots {
    values: [f64; MAX_COEFFICIENTS - 1],
    len: usize,
}

impl Roots {
    fn push(&mut self, t: f64) {
        self.values[self.len] = t;
        self.len += 1;
    }

    /// The roots, ascending.
    pub fn as_slice(&self) -> &[f64] {
        &self.values[..self.len]
    }
}

impl Polynomial {
    /// The polynomial with these coefficients, lowest degree first (at most
    /// four: degree 3).
    pub fn new(coefficients: &[f64]) -> Self {
        assert!(
            coefficients.len() <= MAX_COEFFICIENTS,
            "degree {} is above 3",
            coefficients.len().saturating_sub(1)
        );
        let mut values = [0.0; MAX_COEFFICIENTS];
        values[..coefficients.len()].copy_from_slice(coefficients);
        Self {
            values,
            len: coefficients.len(),
        }
    }

    /// `t -> det(a + t b)` for `D x D` matrices (`D <= 3`), in closed form:
    /// `det a + (cof a : b) t + (cof b : a) t^2 + det b t^3` in 3D,
    /// `det a + (cof a : b) t + det b t^2` in 2D, with the cofactor matrix
    /// `cof` (the derivative of the determinant).
    pub fn determinant_of_line<const D: usize>(a: &Matrix<D>, b: &Matrix<D>) -> Self {
        let cofactor_dot = |m: &Matrix<D>, n: &Matrix<D>| -> f64 {
            match D {
                1 => n[(0, 0)],
                2 => {
                    m[(1, 1)] * n[(0, 0)] - m[(1, 0)] * n[(0, 1)] - m[(0, 1)] * n[(1, 0)]
                        + m[(0, 0)] * n[(1, 1)]
                }
                _ => {
                    let mut sum = 0.0;
                    for i in 0..3 {
                        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
                        for j in 0..3 {
                            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
                            let cofactor = m[(i1, j1)] * m[(i2, j2)] - m[(i2, j1)] * m[(i1, j2)];
                            sum += cofactor * n[(i, j)];
                        }
                    }
                    sum
                }
            }
        };
        match D {
            1 => Self::new(&[a[(0, 0)], b[(0, 0)]]),
            2 => Self::new(&[determinant(a), cofactor_dot(a, b), determinant(b)]),
            3 => Self::new(&[
                determinant(a),
                cofactor_dot(a, b),
                cofactor_dot(b, a),
                determinant(b),
            ]),
            _ => unimplemented!("determinant polynomial of a {D} x {D} matrix"),
        }
    }

    /// Coefficients, lowest degree first.
    pub fn coefficients(&self) -> &[f64] {
        &self.values[..self.len]
    }

    /// Coefficients, lowest degree first, to change in place.
    pub fn coefficients_mut(&mut self) -> &mut [f64] {
        &mut self.values[..self.len]
    }

    /// `(p(t) - p(0)) / t`: the coefficients shifted down by one.
    pub fn without_constant(&self) -> Self {
        Self::new(&self.coefficients()[1.min(self.len)..])
    }

    /// Value at `t` (Horner).
    pub fn eval(&self, t: f64) -> f64 {
        self.coefficients()
            .iter()
            .rev()
            .fold(0.0, |acc, c| acc * t + c)
    }

    /// The derivative.
    pub fn derivative(&self) -> Self {
        let mut derivative = Self::new(&[]);
        for (k, c) in self.coefficients().iter().enumerate().skip(1) {
            derivative.values[k - 1] = k as f64 * c;
            derivative.len = k;
        }
        derivative
    }

    /// All roots in `[lo, hi]` where the sign changes, ascending.
    pub fn sign_changes_in(&self, lo: f64, hi: f64) -> Roots {
        let degree = self
            .coefficients()
            .iter()
            .rposition(|c| *c != 0.0)
            .unwrap_or(0);
        let mut roots = Roots::default();
        if degree == 0 {
            return roots;
        }
        let mut breaks = [0.0; MAX_COEFFICIENTS + 1];
        breaks[0] = lo;
        let critical = self.derivative().sign_changes_in(lo, hi);
        breaks[1..=critical.len].copy_from_slice(critical.as_slice());
        breaks[critical.len + 1] = hi;
        for piece in breaks[..critical.len + 2].windows(2) {
            let (mut a, mut b) = (piece[0], piece[1]);
            let (fa, fb) = (self.eval(a), self.eval(b));
            if fa == 0.0 {
                if roots.as_slice().last() != Some(&a) {
                    roots.push(a);
                }
                continue;
            }
            if fa.signum() == fb.signum() {
                continue;
            }
            for _ in 0..200 {
                let mid = 0.5 * (a + b);
                if mid <= a || mid >= b {
                    break;
                }
                if self.eval(mid).signum() == fa.signum() {
                    a = mid;
                } else {
                    b = mid;
                }
            }
            roots.push(b);
        }
        roots
    }
}

/// The first `t` in `(0, hi]` where `p` reaches zero or changes sign, if any.
pub fn first_root_in(p: &Polynomial, hi: f64) -> Option<f64> {
    p.sign_changes_in(0.0, hi)
        .as_slice()
        .iter()
        .copied()
        .find(|&t| t > 0.0)
        .or_else(|| (p.eval(hi) == 0.0).then_some(hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_roots_of_a_cubic_in_order() {
        // (t - 0.2)(t - 0.5)(t - 0.9)
        let p = Polynomial::new(&[-0.09, 0.73, -1.6, 1.0]);
        let roots = p.sign_changes_in(0.0, 1.0);
        assert_eq!(roots.as_slice().len(), 3);
        for (r, expected) in roots.as_slice().iter().zip([0.2, 0.5, 0.9]) {
            assert!((r - expected).abs() < 1e-12, "{r} vs {expected}");
        }
        assert!((first_root_in(&p, 1.0).unwrap() - 0.2).abs() < 1e-12);
    }

    #[test]
    fn no_root_when_positive() {
        let p = Polynomial::new(&[1.0, -1.0, 1.0]);
        assert_eq!(first_root_in(&p, 1.0), None);
        let q = Polynomial::new(&[1.0, -4.0, 4.0]); // (1 - 2t)^2, touches at 0.5
        assert!(q.eval(0.5).abs() < 1e-15);
    }

    #[test]
    fn determinant_of_a_line_of_matrices_in_closed_form() {
        let a = Matrix::<3>::new(1.0, 0.2, -0.3, 0.4, 1.5, 0.1, -0.2, 0.3, 0.9);
        let b = Matrix::<3>::new(-0.5, 0.1, 0.7, 0.2, -1.1, 0.3, 0.6, -0.4, 0.2);
        let p = Polynomial::determinant_of_line(&a, &b);
        for t in [0.0, 0.3, 1.0, -2.0, 3.7] {
            let expected = determinant(&(a + b * t));
            assert!((p.eval(t) - expected).abs() < 1e-12 * (1.0 + expected.abs()));
        }
        let (a2, b2) = (
            Matrix::<2>::new(1.0, 0.2, -0.3, 0.8),
            Matrix::<2>::new(0.4, -1.0, 0.5, 0.1),
        );
        let q = Polynomial::determinant_of_line(&a2, &b2);
        for t in [0.0, 0.5, 2.0] {
            let expected = determinant(&(a2 + b2 * t));
            assert!((q.eval(t) - expected).abs() < 1e-13);
        }
    }
}
