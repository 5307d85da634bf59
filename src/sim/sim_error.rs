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
    /// Two surface primitives start closer than the contact distance (or
    /// crossing): bodies that start intersecting (bad input).
    #[error(
        "{bodies} start {distance:.3e} apart ({first} and {second}), closer than the contact \
         distance d_hat = {activation:.3e}: contact needs every pair of surface primitives \
         farther apart than d_hat at the start (move the bodies apart, or lower \
         effects.contact.distance)"
    )]
    ContactAtStart {
        /// "body 0 and body 1", or "parts of body 0".
        bodies: String,
        /// The first primitive ("vertex 12").
        first: String,
        /// The second primitive ("triangle (3, 4, 7)").
        second: String,
        /// Their distance (0 where they cross).
        distance: f64,
        /// `d_hat`.
        activation: f64,
    },
    /// A body starts wholly inside another (no surfaces cross, but one
    /// encloses the other; bad input).
    #[error(
        "{inner} starts inside {outer} (its surface vertex {vertex} is enclosed by the surface \
         of {outer}): contact needs them apart at the start; move {inner} out"
    )]
    BodyInsideBody {
        /// The enclosed body ("body 1", "obstacle 0 (obstacles[0])").
        inner: String,
        /// The enclosing body.
        outer: String,
        /// A surface vertex of the enclosed body.
        vertex: usize,
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
            SimError::InvalidSetting { .. }
                | SimError::BelowGround { .. }
                | SimError::ContactAtStart { .. }
                | SimError::BodyInsideBody { .. }
        )
    }
}
