//! The augmented-Lagrangian term that pulls prescribed vertices onto their path within the solve.
//!
//! A pinned region that moves is normally placed on its path before the
//! solve and its vertices are not unknowns. When that placement is not
//! feasible (the move would invert an element beside the region, or push
//! a surface through another, before the free vertices could follow), the
//! vertices are moved only as far as is feasible and become unknowns of the
//! step, pulled the rest of the way by
//!
//! ```text
//! A(x) = sum_v m_v (rho/2 |x_v - x^_v|^2 - lambda_v . (x_v - x^_v))
//! grad_v A = m_v (rho (x_v - x^_v) - lambda_v),     hess_v A = rho m_v I,
//! ```
//!
//! (`x^_v` the target, `m_v` the lumped mass, so `rho` is a dimensionless
//! stiffness relative to the inertia term), the method of multipliers of
//! IPC (Li et al. 2020, §4.2; ipc-sim/IPC's `AugmentedLagrangian`): after
//! each solve `lambda_v <- lambda_v - rho (x_v - x^_v)` (at the
//! constrained minimiser `m_v lambda_v` is the reaction force), and `rho`,
//! from [`INITIAL_STIFFNESS`] = 1e6, doubles up to [`MAX_STIFFNESS`] = 1e8
//! when the largest error did not at least halve. The line search's
//! feasibility caps and CCD see these vertices move like any other, so no
//! element is inverted and no surface crossed on the way.

use super::EnergyTerm;
use crate::assembly::SparseHessian;
use crate::math::{Matrix, Vector};

/// The penalty stiffness `rho` a step starts with.
pub const INITIAL_STIFFNESS: f64 = 1e6;
/// The largest `rho`.
pub const MAX_STIFFNESS: f64 = 1e8;

/// `A(x)` for a set of prescribed vertices and their targets.
#[derive(Debug, Clone)]
pub struct PrescribedMotion<const D: usize> {
    /// `(vertex, target x^_v, mass m_v)`.
    vertices: Vec<(usize, Vector<D>, f64)>,
    /// `lambda_v`, one per entry of `vertices`.
    multipliers: Vec<Vector<D>>,
    stiffness: f64,
    last_error: f64,
}

impl<const D: usize> PrescribedMotion<D> {
    /// The term for `(vertex, target, mass)` triples, `lambda = 0`, `rho = 1e6`.
    pub fn new(vertices: Vec<(usize, Vector<D>, f64)>) -> Self {
        let multipliers = vec![Vector::<D>::zeros(); vertices.len()];
        Self {
            vertices,
            multipliers,
            stiffness: INITIAL_STIFFNESS,
            last_error: f64::INFINITY,
        }
    }

    /// The largest distance `|x_v - x^_v|` of a prescribed vertex from its target.
    pub fn largest_error(&self, x: &[Vector<D>]) -> f64 {
        self.vertices
            .iter()
            .map(|(v, target, _)| (x[*v] - target).norm())
            .fold(0.0, f64::max)
    }

    /// The `(vertex, target, mass)` triples.
    pub fn vertices(&self) -> &[(usize, Vector<D>, f64)] {
        &self.vertices
    }

    /// The current `rho`.
    pub fn stiffness(&self) -> f64 {
        self.stiffness
    }

    /// After a solve at `x`: updates the multipliers, and doubles `rho` (up
    /// to `MAX_STIFFNESS` = 1e8) if the largest error did not at least halve
    /// since the last update.
    pub fn update(&mut self, x: &[Vector<D>]) {
        let error = self.largest_error(x);
        for ((v, target, _), lambda) in self.vertices.iter().zip(&mut self.multipliers) {
            *lambda -= (x[*v] - target) * self.stiffness;
        }
        if error > 0.5 * self.last_error {
            self.stiffness = (2.0 * self.stiffness).min(MAX_STIFFNESS);
        }
        self.last_error = error;
    }
}

impl<const D: usize> EnergyTerm<D> for PrescribedMotion<D> {
    fn name(&self) -> &'static str {
        "prescribed motion"
    }

    fn value(&self, x: &[Vector<D>]) -> f64 {
        self.vertices
            .iter()
            .zip(&self.multipliers)
            .map(|((v, target, mass), lambda)| {
                let d = x[*v] - target;
                mass * (0.5 * self.stiffness * d.norm_squared() - lambda.dot(&d))
            })
            .sum()
    }

    fn add_gradient(&self, x: &[Vector<D>], scale: f64, gradient: &mut [Vector<D>]) {
        for ((v, target, mass), lambda) in self.vertices.iter().zip(&self.multipliers) {
            gradient[*v] += ((x[*v] - target) * self.stiffness - lambda) * (scale * mass);
        }
    }

    fn add_hessian(&self, _x: &[Vector<D>], scale: f64, hessian: &mut SparseHessian<D>) {
        for (v, _, mass) in &self.vertices {
            hessian.add_vertex_block(
                *v,
                &(Matrix::<D>::identity() * (scale * mass * self.stiffness)),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One vertex pulled against a constant force `f`: the multiplier
    /// converges to the reaction and the error to 0, with `rho` fixed.
    #[test]
    fn the_multiplier_update_removes_the_penalty_error() {
        let target = Vector::<2>::new(1.0, 2.0);
        let mass = 0.5;
        let mut term = PrescribedMotion::new(vec![(0, target, mass)]);
        let force = Vector::<2>::new(0.0, -1e3);
        // argmin A(x) - f.x: m (rho (x - x^) - lambda) = f.
        let solve = |term: &PrescribedMotion<2>| {
            let lambda = term.multipliers[0];
            target + (force / mass + lambda) / term.stiffness()
        };
        let mut errors = Vec::new();
        for _ in 0..3 {
            let x = [solve(&term)];
            errors.push(term.largest_error(&x));
            term.update(&x);
        }
        assert!((errors[0] - 1e3 / mass / INITIAL_STIFFNESS).abs() < 1e-12);
        assert!(errors[1] < 1e-12 * errors[0], "{errors:?}");
        assert!((term.multipliers[0] + force / mass).norm() < 1e-9);
    }
}
