//! Nonlinear solvers for the incremental potential: projected Newton and the report's gradient descent.

/// Which minimiser to run each step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SolverMethod {
    /// Projected Newton: PSD-projected element Hessians, sparse Cholesky,
    /// backtracking line search with contact- and inversion-aware step caps.
    Newton,
    /// The report's method: `x <- x - step * grad E(x)` with a fixed step (the
    /// report used 1e-6), kept for comparison.
    GradientDescent {
        /// Fixed step length `alpha`.
        step: f64,
    },
}

/// Solver settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSettings {
    /// The minimiser (default: Newton).
    pub method: SolverMethod,
    /// Convergence tolerance, in length/s (default: 1e-4): Newton stops when
    /// `|dx|_inf / dt` falls below it, gradient descent when
    /// `|M^-1 grad E|_inf / dt` does (see `gradient_descent.rs`).
    pub tolerance: f64,
    /// Iteration cap per step (default: 50).
    pub max_iterations: usize,
    /// How many times a step that does not converge may be halved and
    /// retried (default: 4, down to `dt / 16`); 0 keeps every step whole.
    pub max_subdivisions: usize,
    /// Friction's velocity threshold `eps_v`, in length/s: slip slower than
    /// this is static friction, smoothed (`None`: 1e-3 times the bodies'
    /// bounding-box diagonal per second). Only scenes with friction use it.
    pub friction_velocity: Option<f64>,
    /// Solves per step with friction (default: 1): each pass after the
    /// first takes friction's normal forces and tangents again at the last
    /// solution and solves again.
    pub friction_iterations: usize,
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            method: SolverMethod::Newton,
            tolerance: 1e-4,
            max_iterations: 50,
            max_subdivisions: 4,
            friction_velocity: None,
            friction_iterations: 1,
        }
    }
}

mod gradient_descent;
mod newton;
mod objective;
mod solver_stats;

pub use gradient_descent::gradient_descent;
pub use newton::newton;
pub use objective::Objective;
pub use solver_stats::{PhaseTimes, SolverStats};

use crate::assembly::FactorisationError;

/// Why a step's minimisation could not be carried out.
#[derive(Debug, Clone, thiserror::Error)]
pub enum SolveError {
    /// An energy or gradient became infinite or NaN.
    #[error("{0}")]
    NonFinite(&'static str),
    /// The linear solve failed.
    #[error(transparent)]
    Factorisation(FactorisationError),
}
