//! Errors of building or stepping a simulation.

/// Errors of building or stepping a simulation.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// A setting is out of range (bad input).
    #[error("invalid setting `{key}`: {reason}")]
    InvalidSetting {
        /// The setting's name.
        key: &'static str,
        /// Why it is invalid.
        reason: String,
    },
    /// A vertex starts on or below the ground (bad input).
    #[error("vertex {vertex} starts at height {height} which is not above the ground at {ground}")]
    BelowGround {
        /// Vertex index.
        vertex: usize,
        /// Its height.
        height: f64,
        /// Ground height.
        ground: f64,
    },
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

impl SimError {
    /// Whether the error comes from the input (a setting, the initial state)
    /// rather than from a failure while working.
    pub fn is_bad_input(&self) -> bool {
        matches!(
            self,
            SimError::InvalidSetting { .. } | SimError::BelowGround { .. }
        )
    }
}
