//! Projected Newton with a feasibility-capped backtracking line search.
//!
//! Each iteration assembles `g = grad E(x)` and the PSD-projected Hessian `H`,
//! solves `H dx = -g` by sparse Cholesky, takes the step, and stops when
//! `|dx|_inf / dt < tol` (a velocity, so the tolerance does not depend on the
//! time step). A step whose line search finds no decrease before that is
//! reported as stalled ([`SolverStats::stalled`]), not as converged.
//!
//! The line search starts at `t = min(1, t_max)`, where `t_max`
//! is the largest step every term allows (no vertex reaches the ground, no
//! surface reaches another, no element of a material that forbids inversion
//! loses more than a fixed fraction of its volume), and halves `t` until the Armijo condition
//! `E(x + t dx) <= E(x) + c t g.dx` holds (`c = 1e-4`). Energy values carry
//! round-off of order `eps |E|`, so the test allows that much slack; without it
//! a converging solve could stall a few ulps short of the tolerance.

use super::{Objective, SolveError, SolverStats};
use crate::assembly::SparseHessian;
use crate::math::Vector;
use std::time::Instant;

/// Armijo sufficient-decrease constant.
const ARMIJO: f64 = 1e-4;
/// Round-off slack of energy comparisons, relative to `|E|`.
const ENERGY_ROUND_OFF: f64 = 1e-13;
/// Backtracks before the line search gives up on an iteration.
const MAX_BACKTRACKS: usize = 60;

/// Minimises `objective` from `x` in place by projected Newton.
pub fn newton<const D: usize>(
    objective: &mut Objective<'_, D>,
    hessian: &mut SparseHessian<D>,
    x: &mut [Vector<D>],
    dt: f64,
    tolerance: f64,
    max_iterations: usize,
) -> Result<SolverStats, SolveError> {
    let n = x.len();
    let mut stats = SolverStats::default();
    let mut gradient = vec![Vector::<D>::zeros(); n];
    let mut direction = vec![Vector::<D>::zeros(); n];
    let mut flat = vec![0.0; hessian.dofs()];
    let mut trial = x.to_vec();
    let mut energy = objective.value(x);
    if !energy.is_finite() {
        return Err(SolveError::NonFinite(
            "the starting state has infinite or undefined energy",
        ));
    }
    while stats.iterations < max_iterations {
        stats.iterations += 1;
        let start = Instant::now();
        let iteration = objective
            .begin_iteration(x, Some(hessian))
            .map_err(SolveError::Factorisation)?;
        stats.times.pattern_growth += iteration.pattern_growth;
        if iteration.reanalysed {
            stats.reanalyses += 1;
            if flat.len() != hessian.dofs() {
                flat.resize(hessian.dofs(), 0.0);
            }
        }
        if iteration.energy_changed {
            energy = objective.value(x);
        }
        objective.gradient_and_hessian(x, &mut gradient, hessian);
        stats.times.assembly += start.elapsed();

        let start = Instant::now();
        hessian.gather_free(&gradient, &mut flat);
        flat.iter_mut().for_each(|v| *v = -*v);
        if flat.iter().any(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite("the gradient is not finite"));
        }
        let mut solve_time = start.elapsed();

        let start = Instant::now();
        hessian.factorise().map_err(SolveError::Factorisation)?;
        stats.times.factorisation += start.elapsed();

        let start = Instant::now();
        hessian.solve(&mut flat);
        hessian.scatter_free(&flat, &mut direction);
        stats.linear_solves += 1;
        solve_time += start.elapsed();
        stats.times.solve += solve_time;

        stats.residual = flat.iter().fold(0.0f64, |m, v| m.max(v.abs())) / dt;

        let start = Instant::now();
        let slope: f64 = gradient.iter().zip(&direction).map(|(g, d)| g.dot(d)).sum();
        let mut t = objective.max_step(x, &direction);
        let mut accepted = false;
        // A zero cap (no term's caps are zero by design: round-off at a
        // contact) leaves no step: the step is reported as stalled.
        let backtracks = if t > 0.0 { MAX_BACKTRACKS + 1 } else { 0 };
        if !(t > 0.0) {
            stats.blocked_by = objective.blocker(x, &direction);
        }
        for _ in 0..backtracks {
            for ((xt, xi), di) in trial.iter_mut().zip(x.iter()).zip(&direction) {
                *xt = xi + di * t;
            }
            let trial_energy = objective.value(&trial);
            if trial_energy <= energy + ARMIJO * t * slope + ENERGY_ROUND_OFF * energy.abs() {
                x.copy_from_slice(&trial);
                energy = trial_energy;
                accepted = true;
                break;
            }
            t *= 0.5;
            stats.backtracks += 1;
        }
        stats.times.line_search += start.elapsed();
        // The direction is always applied before the test, so a loose
        // tolerance still moves the body (one Newton step per time step).
        if stats.residual < tolerance {
            stats.converged = true;
            break;
        }
        if !accepted {
            // No decrease is possible along a descent direction before the
            // tolerance was met: the line search stalled (round-off at the
            // minimum, or a feasibility cap that leaves no room, e.g. an
            // element that would have to flatten further). Stop without
            // moving and report it.
            stats.stalled = true;
            break;
        }
    }
    Ok(stats)
}
