//! The incremental potential as a weighted sum of energy terms.

use crate::assembly::{FactorisationError, SparseHessian};
use crate::energy::{Blocker, EnergyTerm};
use crate::math::Vector;
use std::time::{Duration, Instant};

/// `E(x) = sum_k w_k U_k(x)`: the terms a scene asks for with their weights
/// (1 for inertia, `dt^2` for the potentials).
pub struct Objective<'a, const D: usize> {
    terms: Vec<(&'a mut dyn EnergyTerm<D>, f64)>,
    coupled_pairs: Vec<(usize, usize)>,
}

/// What [`Objective::begin_iteration`] found.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct IterationStart {
    /// Some term's energy changed as a function (its stiffness rose): `E(x)`
    /// must be evaluated again.
    pub energy_changed: bool,
    /// The Hessian's pattern grew and was analysed again.
    pub reanalysed: bool,
    /// Wall time spent making the pattern hold the coupled pairs (growing
    /// it, when `reanalysed`).
    pub pattern_growth: Duration,
}

impl<'a, const D: usize> Objective<'a, D> {
    /// An objective from `(term, weight)` pairs.
    pub fn new(terms: Vec<(&'a mut dyn EnergyTerm<D>, f64)>) -> Self {
        Self {
            terms,
            coupled_pairs: Vec::new(),
        }
    }

    /// Starts a solver iteration at `x`: every term's
    /// [`EnergyTerm::begin_iteration`], then the pairs the terms couple are
    /// put into `hessian`'s pattern (re-analysed only if a pair is new;
    /// `None` for a solver without a Hessian).
    pub fn begin_iteration(
        &mut self,
        x: &[Vector<D>],
        hessian: Option<&mut SparseHessian<D>>,
    ) -> Result<IterationStart, FactorisationError> {
        let mut start = IterationStart::default();
        self.coupled_pairs.clear();
        for (term, _) in &mut self.terms {
            start.energy_changed |= term.begin_iteration(x);
            term.coupled_pairs(&mut self.coupled_pairs);
        }
        if let Some(hessian) = hessian
            && !self.coupled_pairs.is_empty()
        {
            let clock = Instant::now();
            start.reanalysed = hessian.include_pairs(self.coupled_pairs.iter().copied())?;
            start.pattern_growth = clock.elapsed();
        }
        Ok(start)
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

    /// [`Self::gradient_and_hessian`] with each term's unprojected Hessian
    /// ([`EnergyTerm::add_gradient_and_unprojected_hessian`]: the exact
    /// elastic Hessian; the contact barrier's stays projected per stencil).
    pub fn gradient_and_unprojected_hessian(
        &self,
        x: &[Vector<D>],
        gradient: &mut [Vector<D>],
        hessian: &mut SparseHessian<D>,
    ) {
        gradient.iter_mut().for_each(|g| *g = Vector::<D>::zeros());
        hessian.clear();
        for (term, weight) in &self.terms {
            term.add_gradient_and_unprojected_hessian(x, *weight, gradient, hessian);
        }
    }

    /// The largest feasible fraction of the step `dx` (contact, inversion).
    /// Called once per line search, before the trial points.
    pub fn max_step(&mut self, x: &[Vector<D>], dx: &[Vector<D>]) -> f64 {
        self.terms
            .iter_mut()
            .map(|(term, _)| term.max_step(x, dx))
            .fold(1.0, f64::min)
    }

    /// The first term's answer to what leaves no step along `dx`, after
    /// [`Self::max_step`] came out 0.
    pub fn blocker(
        &mut self,
        x: &[Vector<D>],
        dx: &[Vector<D>],
    ) -> Option<(&'static str, Blocker)> {
        self.terms
            .iter_mut()
            .find_map(|(term, _)| Some((term.name(), term.blocker(x, dx)?)))
    }
}
