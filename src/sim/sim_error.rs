//! Errors of building or stepping a simulation: failures while working, never
//! bad input (the scene validator refuses that before a simulation is built).

/// Errors of building or stepping a simulation.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// Setting up the solver failed although the input was valid (for
    /// example the symbolic analysis of the sparse factorisation).
    #[error("setting up the solver failed: {reason}")]
    SetupFailure {
        /// What went wrong.
        reason: String,
    },
    /// The nonlinear solver failed in a way it could not recover from.
    #[error("the solver failed at step {step} (t = {time:.6} s): {reason}")]
    SolverFailure {
        /// Step index (0-based) that failed.
        step: usize,
        /// Simulated time at the start of that step.
        time: f64,
        /// What went wrong.
        reason: String,
    },
}
