//! Statistics the time stepper returns to its caller: energies by term, solver work and state measures.

use crate::energy::Blocker;
use crate::math::Vector;
use crate::solver::{PhaseTimes, SolverStats};
use std::time::Duration;

/// Physical energies of a state (not the incremental potential): the kinetic
/// energy and the value of each potential term the scene has, by the term's
/// name, in the simulation's term order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EnergyBreakdown {
    /// Kinetic energy `1/2 v^T M v`.
    pub kinetic: f64,
    /// `(name, value)` of each potential term ("elastic", "gravity", "barrier", ...).
    pub potentials: Vec<(&'static str, f64)>,
}

impl EnergyBreakdown {
    /// Sum of all terms.
    pub fn total(&self) -> f64 {
        // Left to right from the kinetic energy, like a hand-written sum.
        self.potentials
            .iter()
            .fold(self.kinetic, |sum, (_, e)| sum + e)
    }

    /// Every entry as `(name, value)`, `kinetic` first.
    pub fn entries(&self) -> impl Iterator<Item = (&'static str, f64)> + '_ {
        std::iter::once(("kinetic", self.kinetic)).chain(self.potentials.iter().copied())
    }

    /// The value of the entry called `name` (`kinetic` or a term's name).
    pub fn get(&self, name: &str) -> Option<f64> {
        self.entries().find(|(n, _)| *n == name).map(|(_, e)| e)
    }
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

/// What contact did over a frame (a scene with `[effects.contact]` only).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactStats {
    /// The smallest distance between two surface primitives closer than
    /// `d_hat` at the frame's end (`None` when no pair is that close).
    pub min_distance: Option<f64>,
    /// Stencils within `d_hat` at the last iterate.
    pub active_pairs: usize,
    /// Wall time in the broad phase over the frame's steps.
    pub broad_phase: Duration,
    /// Wall time in continuous collision detection.
    pub ccd: Duration,
    /// Wall time computing the active stencils' derivatives and adding them
    /// to the gradient and Hessian.
    pub assembly: Duration,
    /// CCD queries that ran out of their iteration budget (a safe step was used).
    pub ccd_budget_exhausted: usize,
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
    /// Newton iterations whose direction came from the projected Hessian,
    /// summed over the substeps (`solver.projection`).
    pub projected_iterations: usize,
    /// Substeps that hit the iteration cap without meeting the tolerance.
    pub unconverged_steps: usize,
    /// Substeps whose line search stalled (found no decrease) before meeting
    /// the tolerance.
    pub stalled_steps: usize,
    /// Times the Hessian's pattern grew and was analysed again (new contact pairs).
    pub reanalyses: usize,
    /// Substeps that did not converge whole and were retried as shorter steps.
    pub subdivided_steps: usize,
    /// Substeps of a scheme that guards its energy (Newmark) that gained
    /// energy and were taken again as backward-Euler steps.
    pub damped_steps: usize,
    /// For the first stalled substep whose line search had no room at all
    /// (a zero step cap): the term and what blocked it.
    pub blocked_by: Option<(&'static str, Blocker)>,
    /// The largest distance of a prescribed vertex from its path at the end
    /// of a substep (`None` in a scene without moving pinned regions).
    pub boundary_error: Option<f64>,
    /// Contact's measures (`None` without `[effects.contact]`).
    pub contact: Option<ContactStats>,
    /// The work friction has taken out of the bodies since the start, at
    /// the frame's end (`None` in a scene without friction).
    pub friction_dissipated: Option<f64>,
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
