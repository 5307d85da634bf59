//! Newton's method with a feasibility-capped backtracking line search, the
//! Hessian projected always or on demand.
//!
//! Each iteration assembles `g = grad E(x)` and a Hessian `H`, solves
//! `H dx = -g` by sparse Cholesky, takes the step, and stops when
//! `|dx|_inf / dt < tol` (a velocity, so the tolerance does not depend on the
//! time step). A step whose line search finds no decrease before that is
//! reported as stalled ([`SolverStats::stalled`]), not as converged.
//!
//! **Which Hessian** ([`Projection`]). Projected Newton assembles every
//! element's Hessian from its stress derivative projected onto the PSD cone,
//! so `H` is positive definite and `dx` a descent direction at every
//! iterate; but where the exact Hessian is already positive definite the
//! projection still perturbs it, and Newton then converges only linearly
//! (a box hitting the ground at 500 units/s: full steps accepted and the
//! residual falling by a factor of about 0.89 per iteration). With
//! projection on demand (Longva et al. 2023, "Pitfalls of Projection") an
//! iteration assembles the unprojected Hessian first; only if its Cholesky
//! factorisation meets a non-positive pivot, or `g . dx` is not negative,
//! is the projected Hessian assembled and factorised instead (counted in
//! [`SolverStats::projected_iterations`]). The gradient is the same either
//! way, and so is the stopping test.
//!
//! The line search starts at `t = min(1, t_max)`, where `t_max`
//! is the largest step every term allows (no vertex reaches the ground, no
//! surface reaches another, no element of a material that forbids inversion
//! loses more than a fixed fraction of its volume), and halves `t` until the Armijo condition
//! `E(x + t dx) <= E(x) + c t g.dx` holds (`c = 1e-4`). Energy values carry
//! round-off of order `eps |E|`, so the test allows that much slack; without it
//! a converging solve could stall a few ulps short of the tolerance.

use super::{Objective, Projection, SolveError, SolverStats};
use crate::assembly::SparseHessian;
use crate::math::Vector;
use std::time::Instant;

/// Armijo sufficient-decrease constant.
const ARMIJO: f64 = 1e-4;
/// Round-off slack of energy comparisons, relative to `|E|`.
const ENERGY_ROUND_OFF: f64 = 1e-13;
/// Backtracks before the line search gives up on an iteration.
const MAX_BACKTRACKS: usize = 60;

/// What [`newton`] needs of the solver settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonSettings {
    /// Stop when `|dx|_inf / dt` falls below this (length/s).
    pub tolerance: f64,
    /// Iteration cap.
    pub max_iterations: usize,
    /// Which Hessian to factorise.
    pub projection: Projection,
}

/// Minimises `objective` from `x` in place by Newton's method with the
/// Hessian projected as `settings.projection` says.
pub fn newton<const D: usize>(
    objective: &mut Objective<'_, D>,
    hessian: &mut SparseHessian<D>,
    x: &mut [Vector<D>],
    dt: f64,
    settings: NewtonSettings,
) -> Result<SolverStats, SolveError> {
    let NewtonSettings {
        tolerance,
        max_iterations,
        projection,
    } = settings;
    let on_demand = projection == Projection::OnDemand;
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
        if on_demand {
            objective.gradient_and_unprojected_hessian(x, &mut gradient, hessian);
        } else {
            objective.gradient_and_hessian(x, &mut gradient, hessian);
        }
        stats.times.assembly += start.elapsed();
        hessian.gather_free(&gradient, &mut flat);
        if flat.iter().any(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite("the gradient is not finite"));
        }

        // On demand: the unprojected Hessian's direction if it is positive
        // definite and the direction descends; the projected one otherwise.
        let mut slope = f64::NAN;
        if on_demand {
            let start = Instant::now();
            let definite = hessian.factorise_if_positive_definite();
            stats.times.factorisation += start.elapsed();
            if definite {
                slope =
                    solve_for_direction(hessian, &gradient, &mut flat, &mut direction, &mut stats);
            }
        }
        if !(slope < 0.0) {
            if on_demand {
                let start = Instant::now();
                objective.hessian(x, hessian);
                stats.times.assembly += start.elapsed();
            }
            let start = Instant::now();
            hessian.factorise().map_err(SolveError::Factorisation)?;
            stats.times.factorisation += start.elapsed();
            stats.projected_iterations += 1;
            slope = solve_for_direction(hessian, &gradient, &mut flat, &mut direction, &mut stats);
        }
        stats.residual = flat.iter().fold(0.0f64, |m, v| m.max(v.abs())) / dt;

        let start = Instant::now();
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

/// Solves `H dx = -g` with the factor just made (`flat` is scratch of the
/// free unknowns' size), spreads `dx` into `direction` and returns the slope
/// `g . dx`.
fn solve_for_direction<const D: usize>(
    hessian: &mut SparseHessian<D>,
    gradient: &[Vector<D>],
    flat: &mut [f64],
    direction: &mut [Vector<D>],
    stats: &mut SolverStats,
) -> f64 {
    let start = Instant::now();
    hessian.gather_free(gradient, flat);
    flat.iter_mut().for_each(|v| *v = -*v);
    hessian.solve(flat);
    hessian.scatter_free(flat, direction);
    stats.linear_solves += 1;
    stats.times.solve += start.elapsed();
    gradient
        .iter()
        .zip(direction.iter())
        .map(|(g, d)| g.dot(d))
        .sum()
}
