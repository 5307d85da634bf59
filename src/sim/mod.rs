//! Time stepping: backward Euler posed as an incremental-potential minimisation.
//!
//! Each step solves (the report's `argmin`)
//!
//! ```text
//! x_{n+1} = argmin_x  1/2 |x - x_pred|_M^2 + dt^2 U(x),    x_pred = x_n + dt v_n,
//! v_{n+1} = (x_{n+1} - x_n) / dt,
//! ```
//!
//! where `U` is the sum of the potential terms the scene asks for (elasticity,
//! gravity, the ground barrier). Its stationarity condition
//! `M (x - x_pred) / dt^2 = -grad U(x)` is exactly backward Euler. Pinned
//! vertices are removed from the unknowns and stay at their rest positions.

mod effects;
mod simulation;
mod stats;

pub use effects::{Effects, Ground, PinRegion};
pub use simulation::{SimError, Simulation, SimulationSettings};
pub use stats::{ElementField, EnergyBreakdown, FrameStats, PhaseTimes, SolverStats, StepStats};
