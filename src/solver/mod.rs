//! Nonlinear solvers for the incremental potential: Newton (the Hessian projected always or on demand) and the report's gradient descent.

/// Which minimiser to run each step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SolverMethod {
    /// Newton: element Hessians PSD-projected always or on demand
    /// ([`Projection`]), sparse Cholesky, backtracking line search with
    /// contact- and inversion-aware step caps.
    Newton,
    /// The report's method: `x <- x - step * grad E(x)` with a fixed step (the
    /// report used 1e-6), kept for comparison.
    GradientDescent {
        /// Fixed step length `alpha`.
        step: f64,
    },
}

/// Which Hessian Newton factorises (`solver.projection`).
///
/// The default is [`Projection::OnDemand`], measured on the hard-case suite
/// and the built-in scenes (`docs/physics.md`): never more bad steps than
/// projecting always, 420 k against 785 k Newton iterations over the suite
/// (the StVK twist 7,265 against 308,514), and 1.13 to 1.53 times less CPU
/// time on the built-in and benchmark scenes, where the iteration counts
/// hardly differ but the unprojected assembly skips the projection's work.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Projection {
    /// Every iteration assembles the Hessian with each element's stress
    /// derivative projected onto the PSD cone (projected Newton).
    Always,
    /// Each iteration tries the unprojected Hessian first and assembles the
    /// projected one only when that is not positive definite (its Cholesky
    /// factorisation fails) or its direction is not a descent direction
    /// (Longva et al. 2023, "Pitfalls of Projection": project-on-demand
    /// Newton).
    #[default]
    OnDemand,
}

/// Solver settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSettings {
    /// The minimiser (default: Newton).
    pub method: SolverMethod,
    /// Convergence tolerance, in length/s (default: 1e-4; a scene without
    /// `solver.tolerance` gets `1e-3` times its bodies' bounding-box
    /// diagonal, `scene::DEFAULT_RELATIVE_TOLERANCE`): Newton stops when
    /// `|dx|_inf / dt` falls below it, gradient descent when
    /// `|M^-1 grad E|_inf / dt` does (see `gradient_descent.rs`).
    pub tolerance: f64,
    /// Iteration cap per step (default: 50).
    pub max_iterations: usize,
    /// Which Hessian Newton factorises (default: [`Projection::OnDemand`]).
    pub projection: Projection,
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
            projection: Projection::OnDemand,
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
pub use newton::{NewtonSettings, newton};
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
