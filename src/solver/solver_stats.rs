//! What the nonlinear solver did in one time step: iteration counts, outcome and time per phase.

use crate::energy::Blocker;
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
    /// The part of assembly spent growing the Hessian's pattern for new
    /// contact pairs and analysing it again (`reanalyses`).
    pub pattern_growth: Duration,
}

impl std::ops::AddAssign for PhaseTimes {
    fn add_assign(&mut self, other: Self) {
        self.assembly += other.assembly;
        self.factorisation += other.factorisation;
        self.solve += other.solve;
        self.line_search += other.line_search;
        self.pattern_growth += other.pattern_growth;
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
    /// Iterations whose direction came from the projected Hessian: every
    /// one with [`Projection::Always`](super::Projection::Always); with
    /// projection on demand, those whose unprojected Hessian was not
    /// positive definite or gave no descent direction.
    pub projected_iterations: usize,
    /// Times the Hessian's pattern grew (new contact pairs) and its symbolic
    /// factorisation was redone.
    pub reanalyses: usize,
    /// Whether the tolerance was met before the iteration cap.
    pub converged: bool,
    /// Whether the solve stopped early because the line search found no
    /// decrease along the search direction (it did not meet the tolerance,
    /// and it did not hit the iteration cap either).
    pub stalled: bool,
    /// Whether the step was taken back and advanced as shorter steps
    /// (`solver.max_subdivisions`); the counts then cover every attempt.
    pub subdivided: bool,
    /// Steps that gained energy and were taken again damped (a scheme that
    /// guards its energy, Newmark); summed over the parts of a divided step.
    pub damped_steps: usize,
    /// The largest distance of a prescribed vertex from its path at the end
    /// of the step, for a step whose moving regions had to be pulled onto
    /// their path within the solve (`None` otherwise: they were put on it).
    pub constraint_error: Option<f64>,
    /// What left the line search no room at all (a zero step cap), with
    /// its term's name, if that is why the step stalled.
    pub blocked_by: Option<(&'static str, Blocker)>,
    /// Final convergence measure of the last iteration (see
    /// [`SolverSettings::tolerance`](super::SolverSettings::tolerance)).
    pub residual: f64,
    /// Wall time per phase.
    pub times: PhaseTimes,
}

impl SolverStats {
    /// Adds the counts and times of `other` (one more solve of the same step).
    pub fn accumulate(&mut self, other: &SolverStats) {
        self.iterations += other.iterations;
        self.linear_solves += other.linear_solves;
        self.backtracks += other.backtracks;
        self.projected_iterations += other.projected_iterations;
        self.reanalyses += other.reanalyses;
        self.damped_steps += other.damped_steps;
        self.times += other.times;
    }

    /// A step taken as two halves after the attempt `failed` (`None` if it
    /// ended in an error): the work of all three, converged if both halves
    /// did, stalled if it did not and a half stalled.
    pub fn subdivided(
        failed: Option<SolverStats>,
        first: SolverStats,
        second: SolverStats,
    ) -> Self {
        let mut total = failed.unwrap_or_default();
        total.accumulate(&first);
        total.accumulate(&second);
        total.converged = first.converged && second.converged;
        total.stalled = !total.converged && (first.stalled || second.stalled);
        total.subdivided = true;
        total.residual = first.residual.max(second.residual);
        total.blocked_by = first.blocked_by.or(second.blocked_by);
        total.constraint_error = match (first.constraint_error, second.constraint_error) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        };
        total
    }

    /// Whether the step hit the iteration cap without meeting the tolerance
    /// (a stalled step is not counted here).
    pub fn hit_iteration_cap(&self) -> bool {
        !self.converged && !self.stalled
    }
}
