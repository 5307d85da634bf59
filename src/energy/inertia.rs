//! Inertia: `1/2 sum_i m_i |x_i - x_pred_i|^2`, the kinetic part of the incremental potential.

use super::EnergyTerm;
use crate::assembly::SparseHessian;
use crate::math::{Matrix, Vector};

/// The inertia term with lumped masses and the predicted positions `x_pred = x_n + dt v_n`.
#[derive(Debug, Clone)]
pub struct Inertia<const D: usize> {
    masses: Vec<f64>,
    predicted: Vec<Vector<D>>,
}

impl<const D: usize> Inertia<D> {
    /// Inertia with the given lumped masses; the prediction starts at the origin.
    pub fn new(masses: Vec<f64>) -> Self {
        let predicted = vec![Vector::<D>::zeros(); masses.len()];
        Self { masses, predicted }
    }

    /// Sets `x_pred`.
    pub fn set_prediction(&mut self, predicted: &[Vector<D>]) {
        self.predicted.copy_from_slice(predicted);
    }
}

impl<const D: usize> EnergyTerm<D> for Inertia<D> {
    fn name(&self) -> &'static str {
        "inertia"
    }

    fn value(&self, x: &[Vector<D>]) -> f64 {
        x.iter()
            .zip(&self.predicted)
            .zip(&self.masses)
            .map(|((xi, pi), m)| 0.5 * m * (xi - pi).norm_squared())
            .sum()
    }

    fn add_gradient(&self, x: &[Vector<D>], scale: f64, gradient: &mut [Vector<D>]) {
        for (((g, xi), pi), m) in gradient
            .iter_mut()
            .zip(x)
            .zip(&self.predicted)
            .zip(&self.masses)
        {
            *g += (xi - pi) * (scale * m);
        }
    }

    fn add_hessian(&self, _x: &[Vector<D>], scale: f64, hessian: &mut SparseHessian<D>) {
        for (vertex, m) in self.masses.iter().enumerate() {
            hessian.add_vertex_block(vertex, &(Matrix::<D>::identity() * (scale * m)));
        }
    }
}
