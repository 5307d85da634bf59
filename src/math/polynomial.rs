//! Real polynomials of low degree: evaluation and the first root in an interval.
//!
//! Used to cap line-search steps: `det(D_s + t dD_s)` is a polynomial of degree
//! `D` in `t`, and the first `t > 0` where it vanishes is where an element
//! would invert. Roots are isolated without any closed-form case analysis:
//! between consecutive critical points (the roots of the derivative, found by
//! the same routine recursively) a polynomial is monotone, so a sign change in
//! such a piece brackets exactly one root, which bisection then refines.

/// A polynomial `c_0 + c_1 t + ... + c_n t^n`.
#[derive(Debug, Clone, PartialEq)]
pub struct Polynomial {
    /// Coefficients, lowest degree first.
    pub coefficients: Vec<f64>,
}

impl Polynomial {
    /// The polynomial of degree `<= degree` through `(t_k, f(t_k))` for
    /// `t_k = 0, 1, .., degree` (exact for polynomials of that degree, up to round-off).
    pub fn interpolate(degree: usize, f: impl Fn(f64) -> f64) -> Self {
        let n = degree + 1;
        let vandermonde =
            nalgebra::DMatrix::from_fn(n, n, |row, col| (row as f64).powi(col as i32));
        let values = nalgebra::DVector::from_fn(n, |row, _| f(row as f64));
        let coefficients = vandermonde
            .lu()
            .solve(&values)
            .expect("Vandermonde matrix on distinct nodes is invertible");
        Self {
            coefficients: coefficients.iter().copied().collect(),
        }
    }

    /// Value at `t` (Horner).
    pub fn eval(&self, t: f64) -> f64 {
        self.coefficients
            .iter()
            .rev()
            .fold(0.0, |acc, c| acc * t + c)
    }

    /// The derivative.
    pub fn derivative(&self) -> Self {
        Self {
            coefficients: self
                .coefficients
                .iter()
                .enumerate()
                .skip(1)
                .map(|(k, c)| k as f64 * c)
                .collect(),
        }
    }

    /// All roots in `[lo, hi]` where the sign changes, ascending.
    pub fn sign_changes_in(&self, lo: f64, hi: f64) -> Vec<f64> {
        let degree = self
            .coefficients
            .iter()
            .rposition(|c| *c != 0.0)
            .unwrap_or(0);
        if degree == 0 {
            return Vec::new();
        }
        let mut breaks = vec![lo];
        breaks.extend(self.derivative().sign_changes_in(lo, hi));
        breaks.push(hi);
        let mut roots = Vec::new();
        for piece in breaks.windows(2) {
            let (mut a, mut b) = (piece[0], piece[1]);
            let (fa, fb) = (self.eval(a), self.eval(b));
            if fa == 0.0 {
                if roots.last() != Some(&a) {
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
        .into_iter()
        .find(|&t| t > 0.0)
        .or_else(|| (p.eval(hi) == 0.0).then_some(hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_roots_of_a_cubic_in_order() {
        // (t - 0.2)(t - 0.5)(t - 0.9)
        let p = Polynomial::interpolate(3, |t| (t - 0.2) * (t - 0.5) * (t - 0.9));
        let roots = p.sign_changes_in(0.0, 1.0);
        assert_eq!(roots.len(), 3);
        for (r, expected) in roots.iter().zip([0.2, 0.5, 0.9]) {
            assert!((r - expected).abs() < 1e-12, "{r} vs {expected}");
        }
        assert!((first_root_in(&p, 1.0).unwrap() - 0.2).abs() < 1e-12);
    }

    #[test]
    fn no_root_when_positive() {
        let p = Polynomial {
            coefficients: vec![1.0, -1.0, 1.0],
        };
        assert_eq!(first_root_in(&p, 1.0), None);
        let q = Polynomial {
            coefficients: vec![1.0, -4.0, 4.0],
        }; // (1 - 2t)^2, touches at 0.5
        assert!(q.eval(0.5).abs() < 1e-15);
    }
}
