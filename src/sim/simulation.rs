//! The simulation state (mesh, masses, positions, velocities, time), its energy terms and integrator, and the measures of a state.

use super::{ContactStats, EnergyBreakdown, FrameStats, Obstacle, PinMotion, SimulationSettings};
use crate::assembly::SparseHessian;
use crate::energy::{
    BodyElasticity, ContactBarrier, ElementField, EnergyTerm, Friction, GroundBarrier, Inertia,
};
use crate::integrator::TimeIntegrator;
use crate::math::Vector;
use crate::mesh::Mesh;
use std::sync::Arc;

/// An elastic body with its effects, advanced in time by a time integrator.
///
/// Built by [`Simulation::new`] (`simulation_setup.rs`), advanced by
/// [`Simulation::step`] and [`Simulation::advance_frame`] (`stepping.rs`).
pub struct Simulation<const D: usize> {
    pub(super) mesh: Arc<Mesh<D>>,
    pub(super) masses: Vec<f64>,
    pub(super) positions: Vec<Vector<D>>,
    pub(super) velocities: Vec<Vector<D>>,
    pub(super) time: f64,
    pub(super) steps: usize,
    pub(super) settings: SimulationSettings,
    /// The kinetic part of the incremental potential (its prediction is the integrator's).
    pub(super) inertia: Inertia<D>,
    /// The strain energy of every body: always present.
    pub(super) elasticity: BodyElasticity<D>,
    /// The potential terms of the scene's effects that act on every vertex
    /// alike (gravity), in order.
    pub(super) effect_terms: Vec<Box<dyn EnergyTerm<D>>>,
    /// Contact with the ground (`None` without `[effects.ground]`).
    pub(super) ground: Option<GroundBarrier>,
    pub(super) integrator: Box<dyn TimeIntegrator<D>>,
    /// Contact between and within bodies (`None` without `[effects.contact]`).
    pub(super) contact: Option<ContactBarrier<D>>,
    /// Friction on the ground and between bodies (`None` without a
    /// `friction` coefficient above 0): in every solve, but dissipative, so
    /// not among the potentials.
    pub(super) friction: Option<Friction<D>>,
    /// The work friction has taken out of the bodies since the start.
    pub(super) friction_dissipated: f64,
    pub(super) hessian: SparseHessian<D>,
    /// The Hessian whose unknowns include the vertices of the moving
    /// regions, for steps that pull them onto their path within the solve
    /// (built on first use).
    pub(super) prescribed_hessian: Option<SparseHessian<D>>,
    /// The motions of the pinned regions (the effects' first, then the bodies').
    pub(super) motions: Vec<PinMotion<D>>,
    /// Every pinned vertex with its rest position and motion.
    pub(super) pinned: Vec<PinnedVertex<D>>,
    /// The obstacles; their vertices follow the bodies' in the position
    /// array, each pinned to its obstacle's path (`motions` after the
    /// regions').
    pub(super) obstacles: Vec<Obstacle<D>>,
    /// The mass an obstacle's vertex has in the augmented Lagrangian that
    /// pulls it onto its path (it has no physical mass): the bodies' mean
    /// vertex mass.
    pub(super) obstacle_constraint_mass: f64,
    /// The lowest total energy reached since work was last done on the
    /// bodies, for a scheme that guards its energy (`energy_guard.rs`;
    /// `None` until its first step, and after a step with moving regions).
    pub(super) energy_ceiling: Option<f64>,
}

/// A pinned vertex: it follows `motions[motion]` from its rest position.
#[derive(Debug, Clone, Copy)]
pub(super) struct PinnedVertex<const D: usize> {
    pub vertex: usize,
    pub rest: Vector<D>,
    pub motion: usize,
}

impl<const D: usize> Simulation<D> {
    /// The mesh (rest configuration and connectivity).
    pub fn mesh(&self) -> &Mesh<D> {
        &self.mesh
    }

    /// Lumped vertex masses (the bodies' vertices, in the mesh's order).
    pub fn masses(&self) -> &[f64] {
        self.of_bodies(&self.masses)
    }

    /// Current vertex positions (the bodies' vertices, in the mesh's order).
    pub fn positions(&self) -> &[Vector<D>] {
        self.of_bodies(&self.positions)
    }

    /// Current vertex velocities (the bodies' vertices, in the mesh's order).
    pub fn velocities(&self) -> &[Vector<D>] {
        self.of_bodies(&self.velocities)
    }

    /// The obstacles (`[[obstacles]]`), in the scene's order.
    pub fn obstacles(&self) -> &[Obstacle<D>] {
        &self.obstacles
    }

    /// The current positions of the obstacles' vertices: obstacle after
    /// obstacle, each in its mesh's order.
    pub fn obstacle_positions(&self) -> &[Vector<D>] {
        &self.positions[self.mesh.vertex_count()..]
    }

    /// The positions of everything drawn: the bodies' vertices, then the
    /// obstacles' (as [`Self::obstacle_positions`]).
    pub fn drawn_positions(&self) -> &[Vector<D>] {
        &self.positions
    }

    /// The bodies' part of a per-vertex array (obstacles' vertices follow).
    fn of_bodies<'a, T>(&self, all: &'a [T]) -> &'a [T] {
        &all[..self.mesh.vertex_count()]
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

    /// Whether every body's material allows inversion (stable Neo-Hookean,
    /// fixed corotated): an inverted element is then a state the material
    /// recovers from, not a failure.
    pub fn allows_inversion(&self) -> bool {
        self.elasticity
            .materials()
            .iter()
            .all(|m| !m.forbids_inversion())
    }

    /// Whether nothing does work on the bodies: no pinned region moves at
    /// any time (its total energy then cannot rise).
    pub fn is_closed(&self) -> bool {
        !self.motions.iter().any(|m| m.is_moving())
    }

    /// The ground's barrier (`None` without `[effects.ground]`).
    pub fn ground(&self) -> Option<&GroundBarrier> {
        self.ground.as_ref()
    }

    /// Which vertices are unknowns (`Some(index)`) and which are pinned (`None`).
    pub fn free_index(&self) -> &[Option<usize>] {
        self.of_bodies(self.hessian.free_index())
    }

    /// The potential terms this scene has (elasticity first, then its
    /// effects, the ground, the contact barrier last).
    pub fn potentials(&self) -> Vec<&dyn EnergyTerm<D>> {
        std::iter::once(&self.elasticity as &dyn EnergyTerm<D>)
            .chain(self.effect_terms.iter().map(|t| t.as_ref()))
            .chain(self.ground.iter().map(|g| g as &dyn EnergyTerm<D>))
            .chain(self.contact.iter().map(|c| c as &dyn EnergyTerm<D>))
            .collect()
    }

    /// The potential terms other than the elasticity, mutably, in the
    /// order of [`Self::potentials`].
    pub(super) fn effect_terms_mut(&mut self) -> Vec<&mut dyn EnergyTerm<D>> {
        let mut terms: Vec<&mut dyn EnergyTerm<D>> = self
            .effect_terms
            .iter_mut()
            .map(|t| t.as_mut() as &mut dyn EnergyTerm<D>)
            .collect();
        if let Some(ground) = &mut self.ground {
            terms.push(ground);
        }
        if let Some(contact) = &mut self.contact {
            terms.push(contact);
        }
        terms
    }

    /// The contact term (`None` without `[effects.contact]`).
    pub fn contact(&self) -> Option<&ContactBarrier<D>> {
        self.contact.as_ref()
    }

    /// The contact force on every vertex, `-kappa grad B` (`None` without contact).
    pub fn contact_forces(&self) -> Option<Vec<Vector<D>>> {
        self.contact
            .as_ref()
            .map(|c| self.of_bodies(&c.forces(&self.positions)).to_vec())
    }

    /// The friction term (`None` in a scene without friction).
    pub fn friction(&self) -> Option<&Friction<D>> {
        self.friction.as_ref()
    }

    /// The friction force on every vertex over the last step (`None`
    /// without friction): the lagged stencils' `-grad D` at the current
    /// positions.
    pub fn friction_forces(&self) -> Option<Vec<Vector<D>>> {
        self.friction
            .as_ref()
            .map(|f| self.of_bodies(&f.forces(&self.positions)).to_vec())
    }

    /// The work friction has taken out of the bodies since the start
    /// (`None` without friction).
    pub fn friction_dissipated(&self) -> Option<f64> {
        self.friction.as_ref().map(|_| self.friction_dissipated)
    }

    /// The names of the energy entries of every frame's breakdown, in order:
    /// `kinetic`, then each potential term's name.
    pub fn energy_names(&self) -> Vec<&'static str> {
        std::iter::once("kinetic")
            .chain(self.potentials().iter().map(|t| t.name()))
            .collect()
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
            projected_iterations: 0,
            unconverged_steps: 0,
            stalled_steps: 0,
            reanalyses: 0,
            subdivided_steps: 0,
            damped_steps: 0,
            blocked_by: None,
            boundary_error: self.motions.iter().any(|m| m.is_moving()).then_some(0.0),
            contact: self.contact_stats(),
            friction_dissipated: self.friction_dissipated(),
            energy: self.energies(),
            centre_of_mass,
            min_height: self.ground.as_ref().map(|g| g.min_height(&self.positions)),
            min_volume_ratio: self.elasticity.min_volume_ratio(&self.positions),
            times: Default::default(),
            wall_time: Default::default(),
        }
    }

    /// Contact's measures at the current state (`None` without
    /// `[effects.contact]`): the smallest distance among the pairs of
    /// surface primitives within `d_hat` and the vertices within the
    /// ground's barrier width, and the number of active pairs.
    fn contact_stats(&self) -> Option<ContactStats> {
        let contact = self.contact.as_ref()?;
        let (pair_distance, active_pairs) = contact.proximity(&self.positions);
        let ground_distance = self.ground.as_ref().and_then(|g| {
            let height = g.min_height(&self.positions);
            (height < g.width()).then_some(height)
        });
        let min_distance = match (pair_distance, ground_distance) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        Some(ContactStats {
            min_distance,
            active_pairs,
            ..Default::default()
        })
    }

    /// Physical energies of the current state: kinetic, and each potential
    /// term by name (from the terms themselves).
    pub fn energies(&self) -> EnergyBreakdown {
        let x = &self.positions;
        EnergyBreakdown {
            kinetic: self
                .velocities
                .iter()
                .zip(&self.masses)
                .map(|(v, m)| 0.5 * m * v.norm_squared())
                .sum(),
            potentials: self
                .potentials()
                .iter()
                .map(|term| (term.name(), term.value(x)))
                .collect(),
        }
    }

    /// A per-element scalar at the current positions.
    pub fn element_field(&self, field: ElementField) -> Vec<f64> {
        self.elasticity.element_field(&self.positions, field)
    }
}
