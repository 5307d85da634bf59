//! Gravity: `U = -sum_i m_i g . x_i`, a linear potential (zero Hessian).

use super::EnergyTerm;
use crate::assembly::SparseHessian;
use crate::math::Vector;

/// Uniform gravitational acceleration acting on lumped masses.
#[derive(Debug, Clone)]
pub struct Gravity<const D: usize> {
    masses: Vec<f64>,
    acceleration: Vector<D>,
}

impl<const D: usize> Gravity<D> {
    /// Gravity `acceleration` (length/s^2) acting on `masses`.
    pub fn new(masses: Vec<f64>, acceleration: Vector<D>) -> Self {
        Self {
            masses,
            acceleration,
        }
    }
}

impl<const D: usize> EnergyTerm<D> for Gravity<D> {
    fn name(&self) -> &'static str {
        "gravity"
    }

    fn value(&self, x: &[Vector<D>]) -> f64 {
        -x.iter()
            .zip(&self.masses)
            .map(|(xi, m)| m * self.acceleration.dot(xi))
            .sum::<f64>()
    }

    fn add_gradient(&self, _x: &[Vector<D>], scale: f64, gradient: &mut [Vector<D>]) {
        for (g, m) in gradient.iter_mut().zip(&self.masses) {
            *g -= self.acceleration * (scale * m);
        }
    }

    fn add_hessian(&self, _x: &[Vector<D>], _scale: f64, _hessian: &mut SparseHessian<D>) {}
}
