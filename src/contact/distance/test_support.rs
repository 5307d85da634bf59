//! Test helpers: a seeded pseudo-random generator and central finite
//! differences of [`StencilDerivatives`].

use super::StencilDerivatives;
use crate::math::{Vector2, Vector3};
use nalgebra::{SMatrix, SVector};

/// SplitMix64: tiny, deterministic, good enough to scatter test points.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// Uniform in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        lo + (hi - lo) * (z >> 11) as f64 / (1u64 << 53) as f64
    }

    pub fn vector2(&mut self, scale: f64) -> Vector2 {
        Vector2::from_fn(|_, _| self.uniform(-scale, scale))
    }

    pub fn vector3(&mut self, scale: f64) -> Vector3 {
        Vector3::from_fn(|_, _| self.uniform(-scale, scale))
    }

    /// A unit vector perpendicular to `axis`.
    pub fn perpendicular(&mut self, axis: &Vector3) -> Vector3 {
        loop {
            let v = self.vector3(1.0).cross(axis);
            if v.norm() > 0.1 {
                return v.normalize();
            }
        }
    }
}

/// Stacks points into one coordinate vector (point `a`'s axis `k` at `a D + k`).
pub fn stack<const D: usize, const N: usize>(points: &[SVector<f64, D>]) -> SVector<f64, N> {
    assert_eq!(points.len() * D, N);
    SVector::from_fn(|i, _| points[i / D][i % D])
}

/// Point `a` of a stacked coordinate vector.
pub fn point<const D: usize, const N: usize>(x: &SVector<f64, N>, a: usize) -> SVector<f64, D> {
    x.fixed_rows::<D>(a * D).into_owned()
}

/// Largest entry of `|approx - exact|` over `max(|exact|_inf, 1)`.
fn relative_error<const R: usize, const C: usize>(
    approx: &SMatrix<f64, R, C>,
    exact: &SMatrix<f64, R, C>,
) -> f64 {
    (approx - exact).amax() / exact.amax().max(1.0)
}

/// Checks `derivatives(x)` against `value(x)` and central differences
/// (step `h`): value to 1e-12, value -> gradient and gradient -> Hessian to
/// `tolerance` (relative to the largest entry, or 1). Returns the
/// derivatives at `x`.
pub fn check_finite_differences<const N: usize>(
    x: &SVector<f64, N>,
    value: impl Fn(&SVector<f64, N>) -> f64,
    derivatives: impl Fn(&SVector<f64, N>) -> StencilDerivatives<N>,
    h: f64,
    tolerance: f64,
) -> StencilDerivatives<N> {
    let d = derivatives(x);
    let v = value(x);
    assert!(
        (d.value - v).abs() <= 1e-12 * v.abs().max(1e-300),
        "value {} vs {}",
        d.value,
        v
    );
    let mut fd_gradient = SVector::<f64, N>::zeros();
    let mut fd_hessian = SMatrix::<f64, N, N>::zeros();
    for i in 0..N {
        let mut plus = *x;
        let mut minus = *x;
        plus[i] += h;
        minus[i] -= h;
        fd_gradient[i] = (value(&plus) - value(&minus)) / (2.0 * h);
        let column = (derivatives(&plus).gradient - derivatives(&minus).gradient) / (2.0 * h);
        fd_hessian.set_column(i, &column);
    }
    let gradient_error = relative_error(&fd_gradient, &d.gradient);
    assert!(
        gradient_error < tolerance,
        "gradient error {gradient_error:e} at x = {x:?}\nanalytic {:?}\nfd {:?}",
        d.gradient,
        fd_gradient
    );
    let hessian_error = relative_error(&fd_hessian, &d.hessian);
    assert!(
        hessian_error < tolerance,
        "Hessian error {hessian_error:e} at x = {x:?}\nanalytic {}\nfd {}",
        d.hessian,
        fd_hessian
    );
    let asymmetry = relative_error(&d.hessian.transpose(), &d.hessian);
    assert!(asymmetry < 1e-12, "asymmetric Hessian: {asymmetry:e}");
    d
}
