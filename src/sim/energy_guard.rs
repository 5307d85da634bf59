//! The energy guard of a scheme that does not dissipate (Newmark): a step that would leave more energy than the bodies have had is taken again as a dissipative step.
//!
//! A closed system (no moving pinned region doing work on it) cannot gain
//! energy: its total `E = 1/2 v^T M v + U(x)` (kinetic plus every potential
//! term) never rises above the lowest value it has reached. The trapezoidal
//! rule keeps `E` for converged steps of smooth problems, but not at a stiff
//! barrier impact (`integrator::Newmark` says why), where it can throw a body
//! out faster than it came. So, for a scheme that
//! [`guards_energy`](crate::integrator::TimeIntegrator::guards_energy), each
//! step is checked:
//!
//! ```text
//! E_{n+1} <= E_low + ENERGY_SLACK * (1/2 v^T M v + sum_i |U_i(x)|)   (at x_n, v_n)
//! ```
//!
//! with `E_low` the lowest total energy accepted since the last step with
//! moving regions (the ceiling). A step that breaks it is taken back and
//! taken again as a damped (backward-Euler) step, whose energy becomes the
//! new ceiling, and counted (`damped_steps` in `stats.csv`). The slack is
//! for Newmark's own energy error on smooth motion, which oscillates at
//! `O(dt^2)` about the true value: each damped step dissipates, so a slack
//! below that oscillation ratchets the energy down. Measured: the free
//! vibration of `tests/integration/integrators.rs` (20 steps per period)
//! strays by 2.9e-3 of its energy unguarded; with a slack of 1e-3 the guard
//! damped it to 64% in 10 periods, with 1e-2 it never acts there. On the box
//! thrown at the ground at 50 units/s (total energy 1252; a Neo-Hookean body
//! ringing in flight after the impact, frames 20 to 119) a slack of 1e-4
//! damped 17 steps in flight and kept 149, 1e-3 7 steps and 159, 1e-2 4
//! steps and 200; unguarded the energy reached 6.9e8 and the solve failed.
//! The default scene over 3000 frames damps 18 of its 30,000 steps. So 1e-2,
//! the health check's limit (`app::run_health`: a rise of 1% is a failure). Steps
//! with moving pinned regions are not checked (the regions do work) and
//! reset the ceiling. Dissipative schemes (backward Euler, BDF2) pay
//! nothing: no energy is evaluated for them.

use super::Simulation;
use crate::sim::SimError;
use crate::solver::SolverStats;

/// The energy a step may end above the ceiling, as a fraction of the sum of
/// the magnitudes of the energies at its start.
pub const ENERGY_SLACK: f64 = 1e-2;

impl<const D: usize> Simulation<D> {
    /// One attempt at a step of length `dt` ([`Simulation::attempt_step`]),
    /// taken again damped if it gains energy (see the module doc).
    pub(super) fn attempt_guarded_step(&mut self, dt: f64) -> Result<SolverStats, SimError> {
        if !self.integrator.guards_energy() {
            return self.attempt_step(dt);
        }
        if self.moving_regions().iter().any(|&m| m) {
            self.energy_ceiling = None;
            return self.attempt_step(dt);
        }
        let (energy, magnitude) = self.energy_and_magnitude();
        let ceiling = self.energy_ceiling.unwrap_or(energy).min(energy);
        let start = self.step_start();
        let attempt = self.attempt_step(dt)?;
        let (reached, _) = self.energy_and_magnitude();
        if reached <= ceiling + ENERGY_SLACK * magnitude {
            self.energy_ceiling = Some(ceiling.min(reached));
            return Ok(attempt);
        }
        self.restore(start);
        self.integrator.damp_next_step();
        let mut damped = self.attempt_step(dt)?;
        damped.accumulate(&attempt);
        damped.damped_steps += 1;
        self.energy_ceiling = Some(self.energy_and_magnitude().0);
        Ok(damped)
    }

    /// The total energy of the current state and the sum of the magnitudes
    /// of its parts.
    fn energy_and_magnitude(&self) -> (f64, f64) {
        let energies = self.energies();
        let magnitude = energies.entries().map(|(_, e)| e.abs()).sum();
        (energies.total(), magnitude)
    }
}
