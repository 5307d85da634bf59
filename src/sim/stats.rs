//! Statistics the time stepper returns to its caller.

use crate::math::Vector;
use std::time::Duration;

/// Wall time spent in each phase of the solver.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PhaseTimes {
    /// Gradient and Hessian assembly, including PSD projection.
    pub assembly: Duration,
    /// Sparse Cholesky (numeric) factorisation and solve.
    pub factorisation: Duration,
    /// Line search (step capping, energy evaluations).
    pub line_search: Duration,
}

impl std::ops::AddAssign for PhaseTimes {
    fn add_assign(&mut self, other: Self) {
        self.assembly += other.assembly;
        self.factorisation += other.factorisation;
        self.line_search += other.line_search;
    }
}

/// Physical energies of a state (not the incremental potential).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EnergyBreakdown {
    /// Kinetic energy `1/2 v^T M v`.
    pub kinetic: f64,
    /// Elastic strain energy.
    pub elastic: f64,
    /// Gravitational potential energy `-sum m_i g . x_i` (0 without gravity).
    pub gravity: f64,
    /// Ground barrier energy (0 without a ground).
    pub barrier: f64,
}

impl EnergyBreakdown {
    /// Sum of all terms.
    pub fn total(&self) -> f64 {
        self.kinetic + self.elastic + self.gravity + self.barrier
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
    /// Whether the tolerance was met before the iteration cap.
    pub converged: bool,
    /// Final `|dx|_inf / dt` of the last iteration.
    pub residual: f64,
    /// Wall time per phase.
    pub times: PhaseTimes,
}

/// What one time step did, and the state it reached.
#[derive(Debug, Clone, PartialEq)]
pub struct StepStats<const D: usize> {
    /// The solver's counts and timings.
    pub solver: SolverStats,
    /// Simulated time at the end of the step, in seconds.
    pub time: f64,
    /// Energies at the end of the step.
    pub energy: EnergyBreakdown,
    /// Centre of mass.
    pub centre_of_mass: Vector<D>,
    /// Minimum vertex height above the ground (`None` without a ground).
    pub min_height: Option<f64>,
    /// Minimum volume ratio `J = det F` over all elements.
    pub min_volume_ratio: f64,
}

/// Statistics of one output frame (several substeps), measured at its end.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameStats<const D: usize> {
    /// Simulated time at the end of the frame, in seconds.
    pub time: f64,
    /// Newton iterations summed over the frame's substeps.
    pub iterations: usize,
    /// Linear solves summed over the substeps.
    pub linear_solves: usize,
    /// Line-search backtracks summed over the substeps.
    pub backtracks: usize,
    /// Substeps that hit the iteration cap without meeting the tolerance.
    pub unconverged_steps: usize,
    /// Energies at the end of the frame.
    pub energy: EnergyBreakdown,
    /// Centre of mass.
    pub centre_of_mass: Vector<D>,
    /// Minimum vertex height above the ground (`None` without a ground).
    pub min_height: Option<f64>,
    /// Minimum volume ratio `J = det F` over all elements.
    pub min_volume_ratio: f64,
    /// Wall time per phase summed over the substeps.
    pub times: PhaseTimes,
    /// Total wall time spent simulating the frame.
    pub wall_time: Duration,
}

/// A per-element scalar for colouring and analysis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ElementField {
    /// Strain-energy density `Psi(F)`.
    #[default]
    EnergyDensity,
    /// Von Mises equivalent of the Cauchy stress.
    VonMises,
    /// Volume ratio `J = det F`.
    VolumeRatio,
}
