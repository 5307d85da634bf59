//! What the nonlinear solver did in one time step: iteration counts, outcome and time per phase.

use std::time::Duration;

/// Wall time spent in each phase of the solver.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PhaseTimes {
    /// Gradient and Hessian assembly, including PSD projection.
    pub assembly: Duration,
    /// Sparse Cholesky numeric factorisation.
    pub factorisation: Duration,
    /// Triangular solves with the factor (and the right-hand side's copies).
    pub solve: Duration,
    /// Line search (step capping, energy evaluations).
    pub line_search: Duration,
}

impl std::ops::AddAssign for PhaseTimes {
    fn add_assign(&mut self, other: Self) {
        self.assembly += other.assembly;
        self.factorisation += other.factorisation;
        self.solve += other.solve;
        self.line_search += other.line_search;
    }
}

/// What the nonlinear solver did in one time step.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SolverStats {
    /// Newton (or gradient-descent) iterations.
    pub iterations: usize,
    /// Sparse linear solves.
    pub linear_solves: usize,
    /// Line-search backtracks (step halvings).
    pub backtracks: usize,
    /// Times the Hessian's pattern grew (new contact pairs) and its symbolic
    /// factorisation was redone.
    pub reanalyses: usize,
    /// Whether the tolerance was met before the iteration cap.
    pub converged: bool,
    /// Whether the solve stopped early because the line search found no
    /// decrease along the search direction (it did not meet the tolerance,
    /// and it did not hit the iteration cap either).
    pub stalled: bool,
    /// Final convergence measure of the last iteration (see
    /// [`SolverSettings::tolerance`](super::SolverSettings::tolerance)).
    pub residual: f64,
    /// Wall time per phase.
    pub times: PhaseTimes,
}

impl SolverStats {
    /// Whether the step hit the iteration cap without meeting the tolerance
    /// (a stalled step is not counted here).
    pub fn hit_iteration_cap(&self) -> bool {
        !self.converged && !self.stalled
    }
}
