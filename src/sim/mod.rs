//! Time stepping: the simulation state, its energy terms and integrator, advanced step by step and measured per frame.
//!
//! Each step minimises the incremental potential of the scene's time
//! integrator (see [`crate::integrator`]); for backward Euler (the report's
//! `argmin`)
//!
//! ```text
//! x_{n+1} = argmin_x  1/2 |x - x_pred|_M^2 + dt^2 U(x),    x_pred = x_n + dt v_n,
//! v_{n+1} = (x_{n+1} - x_n) / dt,
//! ```
//!
//! where `U` is the sum of the potential terms the scene asks for (elasticity,
//! gravity, the ground barrier, the contact barrier between and within bodies). Its stationarity condition
//! `M (x - x_pred) / dt^2 = -grad U(x)` is exactly backward Euler. Pinned
//! vertices are removed from the unknowns; at the start of each step they are
//! put on their region's prescribed path (`pin_region.rs`), or, where that
//! move is not feasible, moved part of the way and pulled onto the path
//! within the solve (`energy::PrescribedMotion`); after the solve they get
//! the path's velocity.
//!
//! Files: `simulation.rs` (the state and its measures), `body.rs` (one body
//! of a scene), `pin_region.rs` (a pinned region and its rigid path),
//! `simulation_setup.rs` (joining the bodies' meshes and
//! building the list of terms from the scene's effects, trusting the
//! validated scene), `contact_setup.rs` (the ground, contact and friction
//! terms), `start_problem.rs` (whether the bodies and obstacles start
//! apart: asked once by the scene validator), `effects.rs`, `obstacle.rs` (a surface bodies collide with,
//! moved along a rigid path),
//! `stepping.rs` (one step, one frame), `energy_guard.rs` (a Newmark step
//! that would gain energy is taken again damped), `stats.rs` (what a step reports),
//! `sim_error.rs`.

mod body;
mod contact_setup;
mod effects;
mod energy_guard;
mod obstacle;
mod pin_region;
mod sim_error;
mod simulation;
mod simulation_setup;
mod start_problem;
mod stats;
mod stepping;

pub use body::Body;
pub use contact_setup::DEFAULT_FRICTION_VELOCITY;
pub use effects::{Contact, Effects, Ground};
pub use obstacle::Obstacle;
pub use pin_region::{PinMotion, PinRegion, rotate};
pub use sim_error::SimError;
pub use simulation::Simulation;
pub use simulation_setup::automatic_ground_stiffness;
pub use start_problem::{Collider, StartProblem, start_problem};
pub use stats::{ContactStats, EnergyBreakdown, FrameStats, StepStats};

use crate::integrator::IntegratorKind;
use crate::solver::SolverSettings;

/// Settings of the time stepping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimulationSettings {
    /// Length of one (sub)step, in seconds (default: 1/300).
    pub dt: f64,
    /// The time integrator (default: backward Euler).
    pub integrator: IntegratorKind,
    /// Nonlinear solver settings.
    pub solver: SolverSettings,
}

impl Default for SimulationSettings {
    fn default() -> Self {
        Self {
            dt: 1.0 / 300.0,
            integrator: IntegratorKind::default(),
            solver: SolverSettings::default(),
        }
    }
}
