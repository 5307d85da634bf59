//! Advancing a simulation: one step frees the pinned regions whose release time has come, puts the moving pinned vertices on their paths (as far as is feasible; the rest within the solve, by an augmented Lagrangian), then runs a begin-step hook on every term, the integrator's prediction, one minimisation of the incremental potential and the integrator's velocity update; a step that does not converge is retried as two half steps.

use super::{FrameStats, SimError, Simulation, StepStats};
use crate::energy::{EnergyTerm, PARALLEL_MIN_ELEMENTS, PrescribedMotion};
use crate::integrator::TimeIntegrator;
use crate::math::Vector;
use crate::solver::{
    NewtonSettings, Objective, SolveError, SolverMethod, SolverStats, gradient_descent, newton,
};
use std::time::Instant;

/// How close to its path a prescribed vertex must come in a step, as a
/// fraction of the step's largest prescribed displacement, before it is
/// put on the path (IPC's 1e-3).
pub const PATH_TOLERANCE: f64 = 1e-3;
/// The most augmented-Lagrangian rounds (solves) of one step.
pub const MAX_CONSTRAINT_ROUNDS: usize = 8;

/// The state a step starts from, to take an attempt back.
pub(super) struct StepStart<const D: usize> {
    positions: Vec<Vector<D>>,
    velocities: Vec<Vector<D>>,
    integrator: Box<dyn TimeIntegrator<D>>,
    time: f64,
    friction_dissipated: f64,
}

/// Prescribed vertices that could not be put on their path before the
/// solve: the term that pulls them, and how close they must come.
struct LaggingVertices<const D: usize> {
    term: PrescribedMotion<D>,
    tolerance: f64,
}

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
        let start = self.time;
        let stats = self.advance_by(dt, 0)?;
        // Frames stay on their schedule however the step was divided.
        self.time = start + dt;
        self.steps += 1;
        Ok(stats)
    }

    /// Advances by `dt`, `depth` halvings below the scene's step: a step
    /// that does not converge (iteration cap, a stalled line search, a
    /// failed solve) is taken back and retried as two half steps, down to
    /// `solver.max_subdivisions` halvings; only a step that fails at the
    /// deepest level is kept unconverged (or its error returned).
    fn advance_by(&mut self, dt: f64, depth: usize) -> Result<SolverStats, SimError> {
        let start = self.step_start();
        let deepest = depth >= self.settings.solver.max_subdivisions;
        let failed = match self.attempt_guarded_step(dt) {
            Ok(stats) if stats.converged || deepest => return Ok(stats),
            Err(error) if deepest => {
                self.restore(start);
                return Err(error);
            }
            Ok(stats) => Some(stats),
            Err(_) => None,
        };
        let time = start.time;
        self.restore(start);
        let half = 0.5 * dt;
        let first = self.advance_by(half, depth + 1)?;
        self.time = time + half;
        let second = self.advance_by(half, depth + 1)?;
        Ok(SolverStats::subdivided(failed, first, second))
    }

    /// The state now, to come back to.
    pub(super) fn step_start(&self) -> StepStart<D> {
        StepStart {
            positions: self.positions.clone(),
            velocities: self.velocities.clone(),
            integrator: self.integrator.boxed_clone(),
            time: self.time,
            friction_dissipated: self.friction_dissipated,
        }
    }

    pub(super) fn restore(&mut self, start: StepStart<D>) {
        self.positions = start.positions;
        self.velocities = start.velocities;
        self.integrator = start.integrator;
        self.time = start.time;
        self.friction_dissipated = start.friction_dissipated;
    }

    /// One attempt at a step of length `dt` from the current state: the
    /// prescribed vertices placed (as far as is feasible), the terms'
    /// begin-step hooks, the integrator's prediction, the minimisation
    /// (with the augmented-Lagrangian rounds where a prescribed vertex
    /// lags), the velocity update.
    pub(super) fn attempt_step(&mut self, dt: f64) -> Result<SolverStats, SimError> {
        let end_time = self.time + dt;
        let failure = |sim: &Self, reason: String| SimError::SolverFailure {
            step: sim.steps,
            time: sim.time,
            reason,
        };
        // The scheme starts from x_n (its history and velocity update), even
        // where the solve starts elsewhere.
        self.integrator
            .begin_step(&self.positions, &self.velocities, dt);
        let x_start = self.friction.is_some().then(|| self.positions.clone());
        let lagging = match self.place_prescribed(end_time) {
            Ok(lagging) => lagging,
            Err(reason) => return Err(failure(self, reason)),
        };
        self.elasticity
            .begin_step(&self.positions, &self.velocities);
        let (x, v) = (self.positions.clone(), self.velocities.clone());
        for term in self.effect_terms_mut() {
            term.begin_step(&x, &v);
        }
        self.inertia.set_prediction(self.integrator.predicted());
        let weight = self.integrator.potential_weight(dt);
        self.balance_contact_stiffness(weight);
        if let Some(x_start) = &x_start {
            self.lag_friction(x_start, x_start, dt);
        }
        let mut stats = match lagging {
            None => self.minimise(weight, dt, None),
            Some(lagging) => self.minimise_with_prescribed(weight, dt, lagging),
        }
        .map_err(|e| failure(self, e.to_string()))?;
        if let Some(x_start) = &x_start {
            for _ in 1..self.settings.solver.friction_iterations {
                if !stats.converged {
                    break;
                }
                let solution = self.positions.clone();
                self.lag_friction(&solution, x_start, dt);
                let pass = self
                    .minimise(weight, dt, None)
                    .map_err(|e| failure(self, e.to_string()))?;
                stats.accumulate(&pass);
                stats.converged = pass.converged;
                stats.stalled = pass.stalled;
                stats.residual = pass.residual;
                stats.blocked_by = stats.blocked_by.or(pass.blocked_by);
            }
        }
        if let Some(friction) = &self.friction {
            self.friction_dissipated += friction.dissipated(&self.positions);
        }
        if let Some(vertex) = self
            .positions
            .iter()
            .position(|x| !x.iter().all(|v| v.is_finite()))
        {
            return Err(failure(
                self,
                format!("vertex {vertex} left the finite numbers"),
            ));
        }
        self.integrator
            .end_step(&self.positions, &mut self.velocities, dt);
        // Pinned vertices move at their path's velocity (the schemes' own
        // update would give a secant); they are not unknowns, so their
        // predictions never enter a solve.
        for p in &self.pinned {
            self.velocities[p.vertex] = self.motions[p.motion].velocity_of(&p.rest, end_time);
        }
        self.time = end_time;
        Ok(stats)
    }

    /// One minimisation of the step's incremental potential from the
    /// current positions, with the prescribed-motion term `prescribed` as
    /// an extra term (its vertices then unknowns: the solve uses the
    /// Hessian whose unknowns include them).
    fn minimise(
        &mut self,
        weight: f64,
        dt: f64,
        prescribed: Option<&mut PrescribedMotion<D>>,
    ) -> Result<SolverStats, SolveError> {
        let hessian = match (&prescribed, &mut self.prescribed_hessian) {
            (Some(_), Some(hessian)) => hessian,
            _ => &mut self.hessian,
        };
        let mut terms: Vec<(&mut dyn EnergyTerm<D>, f64)> = vec![(&mut self.inertia, 1.0)];
        terms.push((&mut self.elasticity, weight));
        terms.extend(
            self.effect_terms
                .iter_mut()
                .map(|t| (t.as_mut() as &mut dyn EnergyTerm<D>, weight)),
        );
        if let Some(ground) = &mut self.ground {
            terms.push((ground, weight));
        }
        if let Some(contact) = &mut self.contact {
            terms.push((contact, weight));
        }
        if let Some(friction) = &mut self.friction {
            terms.push((friction, weight));
        }
        if let Some(prescribed) = prescribed {
            terms.push((prescribed, 1.0));
        }
        let mut objective = Objective::new(terms);
        let solver = self.settings.solver;
        match solver.method {
            SolverMethod::Newton => newton(
                &mut objective,
                hessian,
                &mut self.positions,
                dt,
                NewtonSettings {
                    tolerance: solver.tolerance,
                    max_iterations: solver.max_iterations,
                    projection: solver.projection,
                },
            ),
            SolverMethod::GradientDescent { step } => gradient_descent(
                &mut objective,
                hessian.free_index(),
                &self.masses,
                &mut self.positions,
                dt,
                step,
                solver.tolerance,
                solver.max_iterations,
            ),
        }
    }

    /// The augmented-Lagrangian rounds of a step whose prescribed vertices
    /// could not be put on their path before the solve (`energy::
    /// PrescribedMotion` writes the method out): solve, and until every
    /// prescribed vertex is within [`PATH_TOLERANCE`] of its step's
    /// displacement from its target, update the multipliers (and the
    /// stiffness) and solve again, at most [`MAX_CONSTRAINT_ROUNDS`] times.
    /// Once within tolerance the vertices are put on their path exactly, if
    /// that last move is feasible. The step converges only if the solves
    /// did and the path was reached.
    fn minimise_with_prescribed(
        &mut self,
        weight: f64,
        dt: f64,
        lagging: LaggingVertices<D>,
    ) -> Result<SolverStats, SolveError> {
        self.ensure_prescribed_hessian()
            .map_err(SolveError::Factorisation)?;
        let LaggingVertices {
            mut term,
            tolerance,
        } = lagging;
        let mut total = SolverStats::default();
        let mut reached = false;
        for _ in 0..MAX_CONSTRAINT_ROUNDS {
            let stats = self.minimise(weight, dt, Some(&mut term))?;
            total.accumulate(&stats);
            total.residual = stats.residual;
            if !stats.converged {
                total.stalled = stats.stalled;
                break;
            }
            if term.largest_error(&self.positions) <= tolerance {
                reached = true;
                break;
            }
            term.update(&self.positions);
        }
        if reached {
            let mut direction = vec![Vector::<D>::zeros(); self.positions.len()];
            for &(v, target, _) in term.vertices() {
                direction[v] = target - self.positions[v];
            }
            if self.feasible_fraction(&direction) >= 1.0 {
                for &(v, target, _) in term.vertices() {
                    self.positions[v] = target;
                }
            }
        }
        total.converged = reached;
        total.constraint_error = Some(term.largest_error(&self.positions));
        Ok(total)
    }

    /// The Hessian whose unknowns include the vertices of every region
    /// moving now, built on first use and kept while those vertices stay
    /// the same (pins released rebuild it).
    fn ensure_prescribed_hessian(&mut self) -> Result<(), crate::assembly::FactorisationError> {
        let moving = self.moving_regions();
        let mut prescribed_free = vec![false; self.positions.len()];
        for p in self.pinned.iter().filter(|p| moving[p.motion]) {
            prescribed_free[p.vertex] = true;
        }
        let free_index = number_unknowns(
            self.hessian
                .free_index()
                .iter()
                .zip(&prescribed_free)
                .map(|(free, &prescribed)| free.is_some() || prescribed),
        );
        if self
            .prescribed_hessian
            .as_ref()
            .is_some_and(|h| h.free_index() == free_index.as_slice())
        {
            return Ok(());
        }
        self.prescribed_hessian = Some(self.hessian.with_free_index(free_index)?);
        Ok(())
    }

    /// For each pinned region, whether it moves in the step starting now.
    pub(super) fn moving_regions(&self) -> Vec<bool> {
        self.motions
            .iter()
            .map(|m| m.is_moving_at(self.time))
            .collect()
    }

    /// The largest fraction of the move `direction` every term allows
    /// (elements kept from inverting where the material forbids it, the
    /// ground and other surfaces not reached).
    fn feasible_fraction(&mut self, direction: &[Vector<D>]) -> f64 {
        let x = self.positions.clone();
        let mut cap = self.elasticity.max_step(&x, direction);
        for term in self.effect_terms_mut() {
            cap = cap.min(term.max_step(&x, direction));
        }
        cap
    }

    /// Freezes friction's stencils for a solve of a step of length `dt`:
    /// normal forces, closest points and normals at `lagged`, slip measured
    /// from the step's start `x_start` (the ground's vertices within its
    /// barrier, the contact's active stencils, each with its `mu`).
    fn lag_friction(&mut self, lagged: &[Vector<D>], x_start: &[Vector<D>], dt: f64) {
        let Some(friction) = &mut self.friction else {
            return;
        };
        let settings = friction.settings();
        let mut stencils = Vec::new();
        if let Some(ground) = self.ground.as_ref().filter(|_| settings.ground > 0.0) {
            ground.friction_stencils(lagged, x_start, settings.ground, &mut stencils);
        }
        if let Some(contact) = self
            .contact
            .as_mut()
            .filter(|c| c.has_friction(settings.contact))
        {
            contact.friction_stencils(lagged, x_start, settings.contact, &mut stencils);
        }
        friction.lag(stencils, dt);
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
        if !contact.is_active() {
            // No barrier gradient to balance against: the rest's gradient
            // is not needed (the rule's answer without an active stencil).
            contact.balance_stiffness(x, None, weight, self.hessian.free_index());
            return;
        }
        let mut gradient = vec![crate::math::Vector::<D>::zeros(); x.len()];
        self.inertia.add_gradient(x, 1.0, &mut gradient);
        self.elasticity.add_gradient(x, weight, &mut gradient);
        for term in &self.effect_terms {
            term.add_gradient(x, weight, &mut gradient);
        }
        contact.balance_stiffness(x, Some(&gradient), weight, self.hessian.free_index());
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
        let free_index = number_unknowns(is_pinned.iter().map(|&pinned| !pinned));
        self.prescribed_hessian = None;
        self.hessian =
            self.hessian
                .with_free_index(free_index)
                .map_err(|e| SimError::SetupFailure {
                    reason: format!("releasing pinned vertices at t = {}: {e}", self.time),
                })?;
        Ok(())
    }

    /// Puts the vertices of every moving region on their path at time `t`,
    /// the start of the solve, if every term allows that move (no element
    /// of a material that forbids inversion loses too much volume, no
    /// surface reached); otherwise moves them as far as is feasible and
    /// returns them as lagging, to be pulled the rest of the way within the
    /// solve ([`Self::minimise_with_prescribed`]). Regions that hold still
    /// are not touched (their vertices stay at rest, bit for bit). A move
    /// whose target puts a pinned vertex on or below the ground is refused
    /// with the reason.
    fn place_prescribed(&mut self, t: f64) -> Result<Option<LaggingVertices<D>>, String> {
        let moving = self.moving_regions();
        if !moving.iter().any(|&m| m) {
            return Ok(None);
        }
        let mut direction = vec![Vector::<D>::zeros(); self.positions.len()];
        let mut targets = Vec::new();
        let mut displacement = 0.0f64;
        for p in self.pinned.iter().filter(|p| moving[p.motion]) {
            let target = self.motions[p.motion].position(&p.rest, t);
            if let Some(problem) = self
                .ground
                .as_ref()
                .and_then(|g| g.prescribed_position_problem(p.vertex, &target))
            {
                return Err(format!(
                    "the prescribed motion of the pinned vertices {problem} at t = {t:.6} s: \
                     a pinned region must not be driven into the ground"
                ));
            }
            direction[p.vertex] = target - self.positions[p.vertex];
            displacement = displacement.max(direction[p.vertex].norm());
            let mass = if self.masses[p.vertex] > 0.0 {
                self.masses[p.vertex]
            } else {
                self.obstacle_constraint_mass
            };
            targets.push((p.vertex, target, mass));
        }
        let fraction = self.feasible_fraction(&direction);
        if fraction >= 1.0 {
            for &(v, target, _) in &targets {
                self.positions[v] = target;
            }
            return Ok(None);
        }
        for &(v, _, _) in &targets {
            self.positions[v] += direction[v] * fraction;
        }
        Ok(Some(LaggingVertices {
            term: PrescribedMotion::new(targets),
            tolerance: PATH_TOLERANCE * displacement,
        }))
    }

    /// Advances `substeps` steps and summarises them as one output frame.
    pub fn advance_frame(&mut self, substeps: usize) -> Result<FrameStats<D>, SimError> {
        let parallel = self.runs_in_parallel();
        on_worker_thread(parallel, || self.advance_frame_here(substeps))
    }

    fn advance_frame_here(&mut self, substeps: usize) -> Result<FrameStats<D>, SimError> {
        let start = Instant::now();
        let mut totals = SolverStats::default();
        let (mut unconverged_steps, mut stalled_steps, mut subdivided_steps) = (0, 0, 0);
        let mut damped_steps = 0;
        let mut blocked_by = None;
        let mut boundary_error: Option<f64> = None;
        let contact_before = self.contact.as_ref().map(|c| c.counters());
        for _ in 0..substeps {
            let step = self.solve_step()?;
            totals.iterations += step.iterations;
            totals.linear_solves += step.linear_solves;
            totals.backtracks += step.backtracks;
            totals.projected_iterations += step.projected_iterations;
            totals.reanalyses += step.reanalyses;
            totals.times += step.times;
            unconverged_steps += usize::from(step.hit_iteration_cap());
            stalled_steps += usize::from(step.stalled);
            subdivided_steps += usize::from(step.subdivided);
            damped_steps += step.damped_steps;
            if step.stalled && blocked_by.is_none() {
                blocked_by = step.blocked_by;
            }
            if let Some(error) = step.constraint_error {
                boundary_error = Some(boundary_error.map_or(error, |e| e.max(error)));
            }
        }
        let mut frame = self.frame_stats();
        frame.iterations = totals.iterations;
        frame.linear_solves = totals.linear_solves;
        frame.backtracks = totals.backtracks;
        frame.projected_iterations = totals.projected_iterations;
        frame.unconverged_steps = unconverged_steps;
        frame.stalled_steps = stalled_steps;
        frame.reanalyses = totals.reanalyses;
        frame.subdivided_steps = subdivided_steps;
        frame.damped_steps = damped_steps;
        frame.blocked_by = blocked_by;
        if let Some(error) = boundary_error {
            frame.boundary_error = Some(error);
        }
        if let (Some(stats), Some(contact), Some(before)) =
            (&mut frame.contact, &self.contact, contact_before)
        {
            let after = contact.counters();
            stats.broad_phase = after.broad_phase - before.broad_phase;
            stats.ccd = after.ccd - before.ccd;
            stats.assembly = after.assembly - before.assembly;
            stats.ccd_budget_exhausted = after.ccd_budget_exhausted - before.ccd_budget_exhausted;
        }
        frame.times = totals.times;
        frame.wall_time = start.elapsed();
        Ok(frame)
    }
}

/// The unknowns' numbering of a free index: `Some(k)` for the `k`-th vertex
/// that `is_unknown`, `None` for the others.
fn number_unknowns(is_unknown: impl Iterator<Item = bool>) -> Vec<Option<usize>> {
    let mut next = 0;
    is_unknown
        .map(|unknown| {
            unknown.then(|| {
                next += 1;
                next - 1
            })
        })
        .collect()
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
