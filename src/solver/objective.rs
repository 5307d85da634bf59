//! The incremental potential as a weighted sum of energy terms.

use crate::assembly::SparseHessian;
use crate::energy::EnergyTerm;
use crate::math::Vector;

/// `E(x) = sum_k w_k U_k(x)`: the terms a scene asks for with their weights
/// (1 for inertia, `dt^2` for the potentials).
pub struct Objective<'a, const D: usize> {
    terms: Vec<(&'a dyn EnergyTerm<D>, f64)>,
}

impl<'a, const D: usize> Objective<'a, D> {
    /// An objective from `(term, weight)` pairs.
    pub fn new(terms: Vec<(&'a dyn EnergyTerm<D>, f64)>) -> Self {
        Self { terms }
    }

    /// `E(x)`.
    pub fn value(&self, x: &[Vector<D>]) -> f64 {
        self.terms
            .iter()
            .map(|(term, weight)| weight * term.value(x))
            .sum()
    }

    /// `grad E(x)`, one vector per vertex.
    pub fn gradient(&self, x: &[Vector<D>], gradient: &mut [Vector<D>]) {
        gradient.iter_mut().for_each(|g| *g = Vector::<D>::zeros());
        for (term, weight) in &self.terms {
            term.add_gradient(x, *weight, gradient);
        }
    }

    /// The projected Hessian of `E` at `x`, written into `hessian`.
    pub fn hessian(&self, x: &[Vector<D>], hessian: &mut SparseHessian<D>) {
        hessian.clear();
        for (term, weight) in &self.terms {
            term.add_hessian(x, *weight, hessian);
        }
    }

    /// `grad E(x)` and the projected Hessian in one pass per term (what a
    /// Newton iteration needs; the elasticity computes `F`, `P` and `dP/dF`
    /// once per element for both).
    pub fn gradient_and_hessian(
        &self,
        x: &[Vector<D>],
        gradient: &mut [Vector<D>],
        hessian: &mut SparseHessian<D>,
    ) {
        gradient.iter_mut().for_each(|g| *g = Vector::<D>::zeros());
        hessian.clear();
        for (term, weight) in &self.terms {
            term.add_gradient_and_hessian(x, *weight, gradient, hessian);
        }
    }

    /// The largest feasible fraction of the step `dx` (contact, inversion).
    pub fn max_step(&self, x: &[Vector<D>], dx: &[Vector<D>]) -> f64 {
        self.terms
            .iter()
            .map(|(term, _)| term.max_step(x, dx))
            .fold(1.0, f64::min)
    }
}
