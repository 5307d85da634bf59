//! Advancing a simulation: one step is a begin-step hook on every term, the integrator's prediction, one minimisation of the incremental potential, and the integrator's velocity update.

use super::{FrameStats, SimError, Simulation, StepStats};
use crate::energy::EnergyTerm;
use crate::solver::{Objective, SolverMethod, SolverStats, gradient_descent, newton};
use std::time::Instant;

impl<const D: usize> Simulation<D> {
    /// Advances one step of length `dt` and reports the solver's work and the state reached.
    pub fn step(&mut self) -> Result<StepStats<D>, SimError> {
        let solver = self.solve_step()?;
        let state = self.frame_stats();
        Ok(StepStats {
            solver,
            time: state.time,
            energy: state.energy,
            centre_of_mass: state.centre_of_mass,
            min_height: state.min_height,
            min_volume_ratio: state.min_volume_ratio,
        })
    }

    /// Advances one step; only the solver's statistics (no state measures).
    fn solve_step(&mut self) -> Result<SolverStats, SimError> {
        let dt = self.settings.dt;
        let previous = self.positions.clone();
        self.elasticity
            .begin_step(&self.positions, &self.velocities);
        for term in &mut self.effect_terms {
            term.begin_step(&self.positions, &self.velocities);
        }
        self.integrator
            .begin_step(&self.positions, &self.velocities, dt);
        self.inertia.set_prediction(self.integrator.predicted());
        let weight = self.integrator.potential_weight(dt);
        let mut terms: Vec<(&dyn EnergyTerm<D>, f64)> = vec![(&self.inertia, 1.0)];
        terms.push((&self.elasticity, weight));
        terms.extend(self.effect_terms.iter().map(|t| (t.as_ref(), weight)));
        let objective = Objective::new(terms);
        let solver = self.settings.solver;
        let result = match solver.method {
            SolverMethod::Newton => newton(
                &objective,
                &mut self.hessian,
                &mut self.positions,
                dt,
                solver.tolerance,
                solver.max_iterations,
            ),
            SolverMethod::GradientDescent { step } => gradient_descent(
                &objective,
                self.hessian.free_index(),
                &self.masses,
                &mut self.positions,
                dt,
                step,
                solver.tolerance,
                solver.max_iterations,
            ),
        };
        let failure = |reason: String| SimError::SolverFailure {
            step: self.steps,
            time: self.time,
            reason,
        };
        let stats = match result {
            Ok(stats) => stats,
            Err(e) => {
                self.positions = previous;
                return Err(failure(e.to_string()));
            }
        };
        if let Some(vertex) = self
            .positions
            .iter()
            .position(|x| !x.iter().all(|v| v.is_finite()))
        {
            self.positions = previous;
            return Err(failure(format!("vertex {vertex} left the finite numbers")));
        }
        self.integrator
            .end_step(&self.positions, &mut self.velocities, dt);
        self.time += dt;
        self.steps += 1;
        Ok(stats)
    }

    /// Advances `substeps` steps and summarises them as one output frame.
    pub fn advance_frame(&mut self, substeps: usize) -> Result<FrameStats<D>, SimError> {
        let start = Instant::now();
        let mut totals = SolverStats::default();
        let (mut unconverged_steps, mut stalled_steps) = (0, 0);
        for _ in 0..substeps {
            let step = self.solve_step()?;
            totals.iterations += step.iterations;
            totals.linear_solves += step.linear_solves;
            totals.backtracks += step.backtracks;
            totals.times += step.times;
            unconverged_steps += usize::from(step.hit_iteration_cap());
            stalled_steps += usize::from(step.stalled);
        }
        let mut frame = self.frame_stats();
        frame.iterations = totals.iterations;
        frame.linear_solves = totals.linear_solves;
        frame.backtracks = totals.backtracks;
        frame.unconverged_steps = unconverged_steps;
        frame.stalled_steps = stalled_steps;
        frame.times = totals.times;
        frame.wall_time = start.elapsed();
        Ok(frame)
    }
}
