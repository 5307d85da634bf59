//! Advancing a simulation: one step frees the pinned regions whose release time has come, puts the pinned vertices on their paths, then runs a begin-step hook on every term, the integrator's prediction, one minimisation of the incremental potential, and the integrator's velocity update.

use super::{FrameStats, SimError, Simulation, StepStats};
use crate::energy::{EnergyTerm, PARALLEL_MIN_ELEMENTS};
use crate::math::UP_AXIS;
use crate::solver::{Objective, SolverMethod, SolverStats, gradient_descent, newton};
use std::time::Instant;

impl<const D: usize> Simulation<D> {
    /// Advances one step of length `dt` and reports the solver's work and the state reached.
    pub fn step(&mut self) -> Result<StepStats<D>, SimError> {
        let parallel = self.runs_in_parallel();
        on_worker_thread(parallel, || self.step_here())
    }

    /// Whether the passes of a step split across threads (large meshes).
    fn runs_in_parallel(&self) -> bool {
        self.mesh().element_count() >= PARALLEL_MIN_ELEMENTS && rayon::current_num_threads() > 1
    }

    fn step_here(&mut self) -> Result<StepStats<D>, SimError> {
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
        self.release_pins()?;
        let previous = self.positions.clone();
        let end_time = self.time + dt;
        // The scheme starts from x_n (its history and velocity update), even
        // where the solve starts elsewhere.
        self.integrator
            .begin_step(&self.positions, &self.velocities, dt);
        if let Err(reason) = self.move_pinned(end_time) {
            self.positions = previous;
            return Err(SimError::SolverFailure {
                step: self.steps,
                time: self.time,
                reason,
            });
        }
        self.elasticity
            .begin_step(&self.positions, &self.velocities);
        for term in &mut self.effect_terms {
            term.begin_step(&self.positions, &self.velocities);
        }
        if let Some(contact) = &mut self.contact {
            contact.begin_step(&self.positions, &self.velocities);
        }
        self.inertia.set_prediction(self.integrator.predicted());
        let weight = self.integrator.potential_weight(dt);
        self.balance_contact_stiffness(weight);
        let mut terms: Vec<(&mut dyn EnergyTerm<D>, f64)> = vec![(&mut self.inertia, 1.0)];
        terms.push((&mut self.elasticity, weight));
        terms.extend(
            self.effect_terms
                .iter_mut()
                .map(|t| (t.as_mut() as &mut dyn EnergyTerm<D>, weight)),
        );
        if let Some(contact) = &mut self.contact {
            terms.push((contact, weight));
        }
        let mut objective = Objective::new(terms);
        let solver = self.settings.solver;
        let result = match solver.method {
            SolverMethod::Newton => newton(
                &mut objective,
                &mut self.hessian,
                &mut self.positions,
                dt,
                solver.tolerance,
                solver.max_iterations,
            ),
            SolverMethod::GradientDescent { step } => gradient_descent(
                &mut objective,
                self.hessian.free_index(),
                &self.masses,
                &mut self.positions,
                dt,
                step,
                solver.tolerance,
                solver.max_iterations,
            ),
        };
        drop(objective);
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
        // Pinned vertices move at their path's velocity (the schemes' own
        // update would give a secant); they are not unknowns, so their
        // predictions never enter a solve.
        for p in &self.pinned {
            self.velocities[p.vertex] = self.motions[p.motion].velocity_of(&p.rest, end_time);
        }
        self.time += dt;
        self.steps += 1;
        Ok(stats)
    }

    /// Sets the contact stiffness for this step by IPC's balance rule (an
    /// adaptive stiffness only): the gradient of the objective without the
    /// contact at the step's start, `M (x - x~) + w grad U`, against the
    /// barrier's.
    fn balance_contact_stiffness(&mut self, weight: f64) {
        let Some(contact) = &mut self.contact else {
            return;
        };
        if !contact.is_adaptive() {
            return;
        }
        let x = &self.positions;
        let mut gradient = vec![crate::math::Vector::<D>::zeros(); x.len()];
        self.inertia.add_gradient(x, 1.0, &mut gradient);
        self.elasticity.add_gradient(x, weight, &mut gradient);
        for term in &self.effect_terms {
            term.add_gradient(x, weight, &mut gradient);
        }
        contact.balance_stiffness(x, &gradient, weight, self.hessian.free_index());
    }

    /// Frees the vertices of every region whose `release` time has come (the
    /// step starts at or after it, within half a step of round-off): they
    /// become unknowns, from where their path left them and with its
    /// velocity, and the sparse pattern is rebuilt for the new unknowns.
    fn release_pins(&mut self) -> Result<(), SimError> {
        let half_step = 0.5 * self.settings.dt;
        let released = |motion: &super::PinMotion<D>| {
            motion
                .release
                .is_some_and(|release| self.time >= release - half_step)
        };
        if !self
            .pinned
            .iter()
            .any(|p| released(&self.motions[p.motion]))
        {
            return Ok(());
        }
        let motions = &self.motions;
        self.pinned.retain(|p| {
            !motions[p.motion]
                .release
                .is_some_and(|release| self.time >= release - half_step)
        });
        let mut is_pinned = vec![false; self.positions.len()];
        for p in &self.pinned {
            is_pinned[p.vertex] = true;
        }
        let mut next = 0;
        let free_index: Vec<Option<usize>> = is_pinned
            .iter()
            .map(|&pinned| {
                (!pinned).then(|| {
                    next += 1;
                    next - 1
                })
            })
            .collect();
        self.hessian =
            self.hessian
                .with_free_index(free_index)
                .map_err(|e| SimError::SetupFailure {
                    reason: format!("releasing pinned vertices at t = {}: {e}", self.time),
                })?;
        Ok(())
    }

    /// Puts every pinned vertex on its path at time `t`: the start of the
    /// solve. A region that moves displaces its vertices before the solve,
    /// and the line search's guards need a feasible start. When the free
    /// vertices at `x_n` would leave an element with `J <= 0`, the solve
    /// starts from the scheme's prediction `x~` for the free vertices
    /// instead (any feasible start is valid: the minimiser does not depend
    /// on it). A move that puts a pinned vertex on or below the ground, or
    /// that inverts an element from both starts, is refused with the reason.
    fn move_pinned(&mut self, t: f64) -> Result<(), String> {
        let moving = self.motions.iter().any(|m| m.is_moving_at(self.time));
        if !moving {
            return Ok(());
        }
        for p in &self.pinned {
            self.positions[p.vertex] = self.motions[p.motion].position(&p.rest, t);
        }
        if let Some(ground) = self.ground_height
            && let Some(p) = self
                .pinned
                .iter()
                .find(|p| !(self.positions[p.vertex][UP_AXIS] > ground))
        {
            return Err(format!(
                "the prescribed motion of the pinned vertices puts vertex {} at height {} \
                 at t = {t:.6} s, on or below the ground at {ground}: a pinned region must \
                 not be driven into the ground",
                p.vertex, self.positions[p.vertex][UP_AXIS]
            ));
        }
        let j = self.elasticity.min_volume_ratio(&self.positions);
        if j > 0.0 {
            return Ok(());
        }
        // The free vertices at x_n leave an element next to a region
        // inverted: start the solve from the scheme's prediction instead (the
        // free vertices carried along by their velocity), if that is feasible.
        let predicted = self.integrator.predicted();
        for (v, free) in self.hessian.free_index().iter().enumerate() {
            if free.is_some() {
                self.positions[v] = predicted[v];
            }
        }
        let above_ground = self
            .ground_height
            .is_none_or(|h| self.positions.iter().all(|x| x[UP_AXIS] > h));
        let j_predicted = self.elasticity.min_volume_ratio(&self.positions);
        if above_ground && j_predicted > 0.0 {
            return Ok(());
        }
        Err(format!(
            "the prescribed motion of the pinned vertices to t = {t:.6} s inverts an \
             element before the solve (smallest volume ratio J = {j}, and {j_predicted} \
             with the free vertices at their predicted positions): the pinned regions \
             move too far in one step for the free vertices next to them; use a smaller \
             time step or a slower motion"
        ))
    }

    /// Advances `substeps` steps and summarises them as one output frame.
    pub fn advance_frame(&mut self, substeps: usize) -> Result<FrameStats<D>, SimError> {
        let parallel = self.runs_in_parallel();
        on_worker_thread(parallel, || self.advance_frame_here(substeps))
    }

    fn advance_frame_here(&mut self, substeps: usize) -> Result<FrameStats<D>, SimError> {
        let start = Instant::now();
        let mut totals = SolverStats::default();
        let (mut unconverged_steps, mut stalled_steps) = (0, 0);
        let contact_before = self.contact.as_ref().map(|c| c.counters());
        for _ in 0..substeps {
            let step = self.solve_step()?;
            totals.iterations += step.iterations;
            totals.linear_solves += step.linear_solves;
            totals.backtracks += step.backtracks;
            totals.reanalyses += step.reanalyses;
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
        frame.reanalyses = totals.reanalyses;
        if let (Some(stats), Some(contact), Some(before)) =
            (&mut frame.contact, &self.contact, contact_before)
        {
            let after = contact.counters();
            stats.broad_phase = after.broad_phase - before.broad_phase;
            stats.ccd = after.ccd - before.ccd;
            stats.ccd_budget_exhausted = after.ccd_budget_exhausted - before.ccd_budget_exhausted;
        }
        frame.times = totals.times;
        frame.wall_time = start.elapsed();
        Ok(frame)
    }
}

/// Runs `work` on a thread of rayon's pool and waits for it, if `parallel`
/// (else here). Called from a thread outside the pool (the program's main
/// thread), every parallel pass inside a step would otherwise be injected
/// into the pool on its own and the caller put to sleep until it is done, a
/// cross-thread hand-off per pass (about a dozen per Newton iteration); from
/// inside the pool a pass splits with a plain `join`. That took the 40 x 40
/// square drop from 5.4 to 4.7 ms per step. A step of a small mesh, whose
/// passes all run on the calling thread, stays where it is (one hand-off
/// per step would cost it 10%). The results are the same either way (every
/// parallel sum has a fixed order).
fn on_worker_thread<R: Send>(parallel: bool, work: impl FnOnce() -> R + Send) -> R {
    if parallel && rayon::current_thread_index().is_none() {
        rayon::scope(|_| work())
    } else {
        work()
    }
}
