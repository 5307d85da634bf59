//! The simulation state and its stepper.

use super::{Effects, ElementField, EnergyBreakdown, FrameStats, StepStats};
use crate::material::Material;
use crate::math::Vector;
use crate::mesh::Mesh;
use crate::solver::SolverSettings;

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
        Self { dt: 1.0 / 300.0, solver: SolverSettings::default() }
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
    _todo: std::marker::PhantomData<[(); D]>,
}

#[allow(unused_variables, missing_docs)]
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
        todo!()
    }
    /// The mesh (rest configuration and connectivity).
    pub fn mesh(&self) -> &Mesh<D> {
        todo!()
    }
    /// Current vertex positions.
    pub fn positions(&self) -> &[Vector<D>] {
        todo!()
    }
    /// Current vertex velocities.
    pub fn velocities(&self) -> &[Vector<D>] {
        todo!()
    }
    /// Simulated time, in seconds.
    pub fn time(&self) -> f64 {
        todo!()
    }
    /// Number of steps taken.
    pub fn step_count(&self) -> usize {
        todo!()
    }
    /// The ground barrier stiffness in use (`None` without a ground).
    pub fn barrier_stiffness(&self) -> Option<f64> {
        todo!()
    }
    /// Advances one step of length `dt`.
    pub fn step(&mut self) -> Result<StepStats, SimError> {
        todo!()
    }
    /// Advances `substeps` steps and summarises them as one output frame.
    pub fn advance_frame(&mut self, substeps: usize) -> Result<FrameStats<D>, SimError> {
        todo!()
    }
    /// Physical energies of the current state.
    pub fn energies(&self) -> EnergyBreakdown {
        todo!()
    }
    /// A per-element scalar at the current positions.
    pub fn element_field(&self, field: ElementField) -> Vec<f64> {
        todo!()
    }
}
