//! The report's minimiser: fixed-step gradient descent, kept for comparison.
//!
//! The report minimises `E(x) / dt^2 = |x - x_pred|_M^2 / (2 dt^2) + U(x)` by
//! `x <- x - alpha grad(E / dt^2)` with a hand-tuned `alpha` (1e-6).
//!
//! **Stopping rule.** A step stops when the mass-preconditioned gradient,
//! as a velocity, is below the tolerance:
//!
//! ```text
//! max_i |M_i^{-1} grad_i E(x)| / dt  <  tol.
//! ```
//!
//! `M^{-1} grad E` is the step Newton would take if the Hessian were the
//! inertia alone, so this measures the distance to the minimiser in the same
//! units (length/s) as Newton's `|dx|_inf / dt`, and it goes to zero only at
//! the minimiser. (An earlier rule compared the tiny fixed step
//! `alpha grad` with the tolerance and stopped at once: the body never moved.)
//! The only addition to the report's method is that a step is shortened when
//! it would reach the ground or invert an element, so that the energy stays
//! defined.

use super::{Objective, SolveError, SolverStats};
use crate::math::Vector;
use std::time::Instant;

/// Minimises `objective` from `x` in place by fixed-step gradient descent;
/// `masses` are the lumped vertex masses of the inertia term.
#[allow(clippy::too_many_arguments)]
pub fn gradient_descent<const D: usize>(
    objective: &mut Objective<'_, D>,
    free: &[Option<usize>],
    masses: &[f64],
    x: &mut [Vector<D>],
    dt: f64,
    step: f64,
    tolerance: f64,
    max_iterations: usize,
) -> Result<SolverStats, SolveError> {
    let mut stats = SolverStats::default();
    let mut gradient = vec![Vector::<D>::zeros(); x.len()];
    let scale = step / (dt * dt);
    loop {
        let start = Instant::now();
        // No Hessian here, so no pattern to grow: the error cannot occur.
        let _ = objective.begin_iteration(x, None);
        objective.gradient(x, &mut gradient);
        stats.residual = gradient
            .iter()
            .zip(masses)
            .zip(free)
            .filter(|(_, f)| f.is_some())
            .fold(0.0f64, |r, ((g, m), _)| r.max(g.amax() / m))
            / dt;
        stats.times.assembly += start.elapsed();
        if !stats.residual.is_finite() {
            return Err(SolveError::NonFinite("the gradient is not finite"));
        }
        if stats.residual < tolerance {
            stats.converged = true;
            break;
        }
        if stats.iterations == max_iterations {
            break;
        }
        stats.iterations += 1;
        let start = Instant::now();
        for (g, f) in gradient.iter_mut().zip(free) {
            *g = if f.is_some() {
                *g * -scale
            } else {
                Vector::<D>::zeros()
            };
        }
        let t = objective.max_step(x, &gradient);
        for (xi, g) in x.iter_mut().zip(&gradient) {
            *xi += g * t;
        }
        stats.times.line_search += start.elapsed();
    }
    Ok(stats)
}
