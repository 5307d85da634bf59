//! The simulation state and its stepper.

use super::{Effects, ElementField, EnergyBreakdown, FrameStats, SolverStats, StepStats};
use crate::energy::{Elasticity, EnergyTerm, Gravity, GroundBarrier, Inertia};
use crate::material::Material;
use crate::math::{UP_AXIS, Vector};
use crate::mesh::Mesh;
use crate::solver::{
    Objective, SolverMethod, SolverSettings, SparseHessian, gradient_descent, newton,
};
use std::sync::Arc;
use std::time::Instant;

/// Settings of the time integrator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimulationSettings {
    /// Length of one (sub)step, in seconds (default: 1/300).
    pub dt: f64,
    /// Nonlinear solver settings.
    pub solver: SolverSettings,
}

impl Default for SimulationSettings {
    fn default() -> Self {
        Self {
            dt: 1.0 / 300.0,
            solver: SolverSettings::default(),
        }
    }
}

/// Errors of building or stepping a simulation.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// A setting is out of range.
    #[error("invalid setting `{key}`: {reason}")]
    InvalidSetting {
        /// The setting's name.
        key: &'static str,
        /// Why it is invalid.
        reason: String,
    },
    /// A vertex starts on or below the ground.
    #[error("vertex {vertex} starts at height {height} which is not above the ground at {ground}")]
    BelowGround {
        /// Vertex index.
        vertex: usize,
        /// Its height.
        height: f64,
        /// Ground height.
        ground: f64,
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

/// An elastic body with its effects, advanced in time by backward Euler.
pub struct Simulation<const D: usize> {
    mesh: Arc<Mesh<D>>,
    masses: Vec<f64>,
    positions: Vec<Vector<D>>,
    velocities: Vec<Vector<D>>,
    time: f64,
    steps: usize,
    settings: SimulationSettings,
    inertia: Inertia<D>,
    elasticity: Elasticity<D>,
    gravity: Option<Gravity<D>>,
    barrier: Option<GroundBarrier>,
    ground_height: Option<f64>,
    hessian: SparseHessian<D>,
}

fn invalid(key: &'static str, reason: impl Into<String>) -> SimError {
    SimError::InvalidSetting {
        key,
        reason: reason.into(),
    }
}

impl<const D: usize> Simulation<D> {
    /// Builds a simulation of `mesh` made of `material` with `density` (mass per
    /// unit rest volume), starting at rest positions with `initial_velocity`.
    pub fn new(
        mesh: Mesh<D>,
        material: Material,
        density: f64,
        effects: Effects<D>,
        settings: SimulationSettings,
        initial_velocity: Vector<D>,
    ) -> Result<Self, SimError> {
        if !(density > 0.0 && density.is_finite()) {
            return Err(invalid(
                "density",
                format!("must be positive and finite, got {density}"),
            ));
        }
        if !(settings.dt > 0.0 && settings.dt.is_finite()) {
            return Err(invalid(
                "dt",
                format!("must be positive and finite, got {}", settings.dt),
            ));
        }
        if !(settings.solver.tolerance > 0.0) {
            return Err(invalid(
                "tolerance",
                format!("must be positive, got {}", settings.solver.tolerance),
            ));
        }
        if settings.solver.max_iterations == 0 {
            return Err(invalid("max_iterations", "must be at least 1"));
        }
        if let SolverMethod::GradientDescent { step } = settings.solver.method
            && !(step > 0.0 && step.is_finite())
        {
            return Err(invalid(
                "step",
                format!("must be positive and finite, got {step}"),
            ));
        }
        let mesh = Arc::new(mesh);
        let masses = mesh.lumped_masses(density);
        let positions = mesh.rest_positions().to_vec();
        let pinned = |x: &Vector<D>| {
            effects
                .pinned
                .is_some_and(|r| (0..D).all(|k| x[k] >= r.min[k] && x[k] <= r.max[k]))
        };
        let mut free_count = 0;
        let free_index: Vec<Option<usize>> = positions
            .iter()
            .map(|x| {
                (!pinned(x)).then(|| {
                    free_count += 1;
                    free_count - 1
                })
            })
            .collect();
        if effects.pinned.is_some() && free_count == positions.len() {
            return Err(invalid("pinned", "the pinned region holds no vertex"));
        }
        if free_count == 0 {
            return Err(invalid(
                "pinned",
                "every vertex is pinned: nothing can move",
            ));
        }
        let velocities: Vec<Vector<D>> = free_index
            .iter()
            .map(|f| {
                if f.is_some() {
                    initial_velocity
                } else {
                    Vector::<D>::zeros()
                }
            })
            .collect();
        let mut barrier = None;
        if let Some(ground) = effects.ground {
            if !(ground.activation_distance > 0.0 && ground.activation_distance.is_finite()) {
                return Err(invalid(
                    "a",
                    format!(
                        "the barrier width must be positive, got {}",
                        ground.activation_distance
                    ),
                ));
            }
            if let Some((vertex, x)) = positions
                .iter()
                .enumerate()
                .find(|(_, x)| !(x[UP_AXIS] > ground.height))
            {
                return Err(SimError::BelowGround {
                    vertex,
                    height: x[UP_AXIS],
                    ground: ground.height,
                });
            }
            let stiffness = match ground.stiffness {
                Some(kappa) if kappa > 0.0 && kappa.is_finite() => kappa,
                Some(kappa) => {
                    return Err(invalid(
                        "kappa",
                        format!("must be positive and finite, got {kappa}"),
                    ));
                }
                None => GroundBarrier::default_stiffness(
                    ground.height,
                    ground.activation_distance,
                    &masses,
                    &positions,
                    &velocities,
                    effects.gravity,
                ),
            };
            barrier = Some(GroundBarrier::new(
                ground.height,
                ground.activation_distance,
                stiffness,
            ));
        }
        let hessian =
            SparseHessian::new(&mesh, free_index).map_err(|e| SimError::SolverFailure {
                step: 0,
                time: 0.0,
                reason: e.to_string(),
            })?;
        Ok(Self {
            inertia: Inertia::new(masses.clone()),
            elasticity: Elasticity::new(mesh.clone(), material),
            gravity: effects.gravity.map(|g| Gravity::new(masses.clone(), g)),
            barrier,
            ground_height: effects.ground.map(|g| g.height),
            mesh,
            masses,
            positions,
            velocities,
            time: 0.0,
            steps: 0,
            settings,
            hessian,
        })
    }

    /// The mesh (rest configuration and connectivity).
    pub fn mesh(&self) -> &Mesh<D> {
        &self.mesh
    }

    /// Lumped vertex masses.
    pub fn masses(&self) -> &[f64] {
        &self.masses
    }

    /// Current vertex positions.
    pub fn positions(&self) -> &[Vector<D>] {
        &self.positions
    }

    /// Current vertex velocities.
    pub fn velocities(&self) -> &[Vector<D>] {
        &self.velocities
    }

    /// Simulated time, in seconds.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Number of steps taken.
    pub fn step_count(&self) -> usize {
        self.steps
    }

    /// The settings in use.
    pub fn settings(&self) -> &SimulationSettings {
        &self.settings
    }

    /// The ground barrier stiffness in use (`None` without a ground).
    pub fn barrier_stiffness(&self) -> Option<f64> {
        self.barrier.as_ref().map(GroundBarrier::stiffness)
    }

    /// Which vertices are unknowns (`Some(index)`) and which are pinned (`None`).
    pub fn free_index(&self) -> &[Option<usize>] {
        self.hessian.free_index()
    }

    /// The potential terms this scene has (elasticity first, then its effects).
    pub fn potentials(&self) -> Vec<&dyn EnergyTerm<D>> {
        let mut terms: Vec<&dyn EnergyTerm<D>> = vec![&self.elasticity];
        if let Some(gravity) = &self.gravity {
            terms.push(gravity);
        }
        if let Some(barrier) = &self.barrier {
            terms.push(barrier);
        }
        terms
    }

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
        let predicted: Vec<Vector<D>> = previous
            .iter()
            .zip(&self.velocities)
            .map(|(x, v)| x + v * dt)
            .collect();
        self.inertia.set_prediction(&predicted);
        let mut terms: Vec<(&dyn EnergyTerm<D>, f64)> = vec![(&self.inertia, 1.0)];
        terms.extend(
            [
                Some(&self.elasticity as &dyn EnergyTerm<D>),
                self.gravity.as_ref().map(|g| g as _),
                self.barrier.as_ref().map(|b| b as _),
            ]
            .into_iter()
            .flatten()
            .map(|term| (term, dt * dt)),
        );
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
        for ((v, x), x0) in self
            .velocities
            .iter_mut()
            .zip(&self.positions)
            .zip(&previous)
        {
            *v = (x - x0) / dt;
        }
        self.time += dt;
        self.steps += 1;
        Ok(stats)
    }

    /// Advances `substeps` steps and summarises them as one output frame.
    pub fn advance_frame(&mut self, substeps: usize) -> Result<FrameStats<D>, SimError> {
        let start = Instant::now();
        let mut totals = SolverStats::default();
        let mut unconverged_steps = 0;
        for _ in 0..substeps {
            let step = self.solve_step()?;
            totals.iterations += step.iterations;
            totals.linear_solves += step.linear_solves;
            totals.backtracks += step.backtracks;
            totals.times += step.times;
            unconverged_steps += usize::from(!step.converged);
        }
        let mut frame = self.frame_stats();
        frame.iterations = totals.iterations;
        frame.linear_solves = totals.linear_solves;
        frame.backtracks = totals.backtracks;
        frame.unconverged_steps = unconverged_steps;
        frame.times = totals.times;
        frame.wall_time = start.elapsed();
        Ok(frame)
    }

    /// Statistics of the current state with zero solver counts (e.g. frame 0).
    pub fn frame_stats(&self) -> FrameStats<D> {
        let total_mass: f64 = self.masses.iter().sum();
        let centre_of_mass = self
            .positions
            .iter()
            .zip(&self.masses)
            .map(|(x, m)| x * *m)
            .sum::<Vector<D>>()
            / total_mass;
        FrameStats {
            time: self.time,
            iterations: 0,
            linear_solves: 0,
            backtracks: 0,
            unconverged_steps: 0,
            energy: self.energies(),
            centre_of_mass,
            min_height: self.ground_height.map(|h| {
                self.positions
                    .iter()
                    .map(|x| x[UP_AXIS] - h)
                    .fold(f64::INFINITY, f64::min)
            }),
            min_volume_ratio: self.elasticity.min_volume_ratio(&self.positions),
            times: Default::default(),
            wall_time: Default::default(),
        }
    }

    /// Physical energies of the current state.
    pub fn energies(&self) -> EnergyBreakdown {
        let x = &self.positions;
        EnergyBreakdown {
            kinetic: self
                .velocities
                .iter()
                .zip(&self.masses)
                .map(|(v, m)| 0.5 * m * v.norm_squared())
                .sum(),
            elastic: self.elasticity.value(x),
            gravity: self.gravity.as_ref().map_or(0.0, |g| g.value(x)),
            barrier: self
                .barrier
                .as_ref()
                .map_or(0.0, |b| EnergyTerm::<D>::value(b, x)),
        }
    }

    /// A per-element scalar at the current positions.
    pub fn element_field(&self, field: ElementField) -> Vec<f64> {
        self.elasticity.element_field(&self.positions, field)
    }
}
