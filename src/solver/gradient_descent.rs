//! The report's minimiser: fixed-step gradient descent, kept for comparison.
//!
//! The report minimises `E(x) / dt^2 = |x - x_pred|_M^2 / (2 dt^2) + U(x)` by
//! `x <- x - alpha grad(E / dt^2)` with a hand-tuned `alpha` (1e-6). The same
//! stopping rule as Newton applies (`|dx|_inf / dt < tol`). The only addition
//! is that a step is shortened when it would reach the ground or invert an
//! element, so that the energy stays defined.

use super::{Objective, SolveError, SolverStats};
use crate::math::Vector;
use std::time::Instant;

/// Minimises `objective` from `x` in place by fixed-step gradient descent.
pub fn gradient_descent<const D: usize>(
    objective: &Objective<'_, D>,
    free: &[Option<usize>],
    x: &mut [Vector<D>],
    dt: f64,
    step: f64,
    tolerance: f64,
    max_iterations: usize,
) -> Result<SolverStats, SolveError> {
    let mut stats = SolverStats::default();
    let mut gradient = vec![Vector::<D>::zeros(); x.len()];
    let scale = step / (dt * dt);
    while stats.iterations < max_iterations {
        stats.iterations += 1;
        let start = Instant::now();
        objective.gradient(x, &mut gradient);
        for (g, f) in gradient.iter_mut().zip(free) {
            *g = if f.is_some() {
                *g * -scale
            } else {
                Vector::<D>::zeros()
            };
        }
        stats.times.assembly += start.elapsed();
        if gradient.iter().any(|g| !g.iter().all(|v| v.is_finite())) {
            return Err(SolveError::NonFinite("the gradient is not finite"));
        }
        stats.residual = gradient.iter().fold(0.0f64, |m, g| m.max(g.amax())) / dt;
        if stats.residual < tolerance {
            stats.converged = true;
            break;
        }
        let start = Instant::now();
        let t = objective.max_step(x, &gradient);
        for (xi, g) in x.iter_mut().zip(&gradient) {
            *xi += g * t;
        }
        stats.times.line_search += start.elapsed();
    }
    Ok(stats)
}
