//! Contact between and within bodies: IPC's barrier summed over the stencils of surface primitives closer than `d_hat`.
//!
//! The term is
//!
//! ```text
//! U_contact(x) = kappa sum_k m_k(x) b(s_k(x); s_hat),      s_k = d_k^2,  s_hat = d_hat^2,
//! ```
//!
//! over the contact stencils `k` of the collision mesh (2D point-edge; 3D
//! point-triangle and edge-edge, the latter mollified), with IPC's clamped
//! log barrier `b` ([`crate::contact::barrier`]): zero beyond `d_hat`,
//! infinite at contact. The line search never lets a stencil touch
//! ([`EnergyTerm::max_step`] runs additive CCD over the swept segment), so
//! the bodies stay apart by construction.
//!
//! **When the stencils are found.** At the start of every solver iteration
//! ([`EnergyTerm::begin_iteration`]) the broad phase finds the candidates at
//! the iterate and the narrow phase keeps the active ones (`s < s_hat`); the
//! gradient and the Hessian (per stencil, projected to PSD, added through
//! [`SparseHessian::add_stencil`] after the pattern grew to hold the pairs)
//! sum over those. Before each line search the candidates of the swept
//! segment `x -> x + dx` are found, so the energy of every trial point
//! on it is exact. The energy is therefore exact at any state the solver
//! visits.
//!
//! **Stiffness** (IPC's adaptive rule, as the IPC toolkit's
//! `initial_barrier_stiffness` and `update_barrier_stiffness`). The objective
//! is `E = inertia + w (U + kappa B)` with the integrator's weight `w`. At
//! the start of each step, with `g_E` the gradient of everything but the
//! contact and `g_B` that of `B = sum m b` (free vertices only),
//!
//! ```text
//! kappa_min = 1e11 m_avg / (4 s_0 b''(s_0)) / w,   s_0 = (1e-8 L)^2,   kappa_max = 100 kappa_min,
//! kappa     = clamp(-g_B . g_E / (w |g_B|^2), kappa_min, kappa_max),
//! ```
//!
//! (`m_avg` the mean vertex mass, `L` the scene's bounding-box diagonal;
//! `s_0 = d_hat^2 / 2` should `d_hat` be below `1e-8 L`, and `kappa = 1 / w`
//! clamped when no stencil is active, as in the IPC toolkit):
//! the barrier's push balances the other forces where contact is already
//! active, and is at least `kappa_min` elsewhere. Within a step, `kappa`
//! doubles (up to `kappa_max`) whenever the smallest distance is below
//! `1e-9 L` and still shrinking from one iteration to the next. A `kappa`
//! given in the scene is used as it is, never changed.

use super::{Blocker, EnergyTerm};
use crate::assembly::SparseHessian;
use crate::contact::ccd::CcdSettings;
use crate::contact::friction::{FrictionStencil, normal_force};
use crate::contact::{
    CandidateFinder, CollisionFreeStep, CollisionMesh, ContactStencil, StencilEnergy, StencilKind,
    barrier_second_derivative, collision_free_step,
};
use crate::math::Vector;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Below this many active stencils their derivatives are computed on the
/// calling thread (a rayon dispatch would cost more).
const PARALLEL_MIN_STENCILS: usize = 64;

/// The settings of `[effects.contact]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactSettings {
    /// The activation distance `d_hat`, in length units.
    pub activation_distance: f64,
    /// A fixed stiffness `kappa` (energy per length^4); `None` for IPC's adaptive rule.
    pub stiffness: Option<f64>,
    /// Whether parts of one body collide with each other (self-contact).
    pub self_contact: bool,
}

/// Work the contact term did, summed since it was built.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactCounters {
    /// Time in the broad phase (candidates at iterates and over segments).
    pub broad_phase: Duration,
    /// Time in continuous collision detection.
    pub ccd: Duration,
    /// Time computing the active stencils' derivatives (with their PSD
    /// projections) and adding them to the gradient and the Hessian.
    pub assembly: Duration,
    /// CCD queries whose iteration budget ran out (their safe step was used).
    pub ccd_budget_exhausted: usize,
}

/// `kappa sum_k m_k b(s_k)` over the stencils of a collision mesh.
pub struct ContactBarrier<const D: usize> {
    mesh: CollisionMesh,
    settings: ContactSettings,
    squared_activation: f64,
    stiffness: f64,
    /// `kappa_max` of the last step's weight.
    max_stiffness: f64,
    bounding_box_diagonal: f64,
    average_mass: f64,
    finder: CandidateFinder<D>,
    /// Candidates covering the current iterate or line-search segment.
    stencils: Vec<ContactStencil>,
    /// Indices into `stencils` of those active at the last iterate.
    active: Vec<usize>,
    /// Their derivatives (reused buffer).
    derivatives: Vec<Option<StencilEnergy>>,
    previous_min_distance_squared: f64,
    /// `grad B` at a step's start (reused buffer).
    barrier_gradient: Vec<Vector<D>>,
    ccd: CcdSettings,
    counters: ContactCounters,
    /// Nanoseconds of [`ContactCounters::assembly`] spent in the `&self`
    /// methods that add the stencils to a gradient and Hessian.
    scatter_nanos: AtomicU64,
}

impl<const D: usize> ContactBarrier<D> {
    /// The contact term of `mesh` at positions `x`, with the vertex
    /// `masses`, a stiffness to begin with (the fixed one, or `kappa_min`
    /// for weight 1 until the first step sets it), and the scene's
    /// bounding-box diagonal `L`.
    pub fn new(
        mesh: CollisionMesh,
        settings: ContactSettings,
        masses: &[f64],
        bounding_box_diagonal: f64,
        x: &[Vector<D>],
    ) -> Self {
        let average_mass = masses.iter().sum::<f64>() / masses.len().max(1) as f64;
        let mut term = Self {
            mesh,
            settings,
            squared_activation: settings.activation_distance.powi(2),
            stiffness: 0.0,
            max_stiffness: 0.0,
            bounding_box_diagonal,
            average_mass,
            finder: CandidateFinder::default(),
            stencils: Vec::new(),
            active: Vec::new(),
            derivatives: Vec::new(),
            previous_min_distance_squared: f64::INFINITY,
            barrier_gradient: Vec::new(),
            ccd: CcdSettings::default(),
            counters: ContactCounters::default(),
            scatter_nanos: AtomicU64::new(0),
        };
        let (min, max) = term.stiffness_bounds(1.0);
        term.stiffness = settings.stiffness.unwrap_or(min);
        term.max_stiffness = max;
        term.find_active(x);
        term
    }

    /// Whether some stencil was active (closer than `d_hat`) at the last
    /// state searched (an iterate or a step's start); without one the
    /// barrier's gradient is zero there.
    pub fn is_active(&self) -> bool {
        !self.active.is_empty()
    }

    /// The collision mesh.
    pub fn collision_mesh(&self) -> &CollisionMesh {
        &self.mesh
    }

    /// The stiffness `kappa` in use.
    pub fn stiffness(&self) -> f64 {
        self.stiffness
    }

    /// The activation distance `d_hat`.
    pub fn activation_distance(&self) -> f64 {
        self.settings.activation_distance
    }

    /// Whether the stiffness follows IPC's adaptive rule (no fixed `kappa`).
    pub fn is_adaptive(&self) -> bool {
        self.settings.stiffness.is_none()
    }

    /// The work done so far.
    pub fn counters(&self) -> ContactCounters {
        let scatter = Duration::from_nanos(self.scatter_nanos.load(Ordering::Relaxed));
        ContactCounters {
            assembly: self.counters.assembly + scatter,
            ..self.counters
        }
    }

    /// Adds the time since `start` to the assembly counter (from `&self`).
    fn count_scatter(&self, start: Instant) {
        let nanos = u64::try_from(start.elapsed().as_nanos()).unwrap_or(u64::MAX);
        self.scatter_nanos.fetch_add(nanos, Ordering::Relaxed);
    }

    /// `(kappa_min, kappa_max)` for the integrator weight `w`.
    pub fn stiffness_bounds(&self, weight: f64) -> (f64, f64) {
        let mut s0 = (1e-8 * self.bounding_box_diagonal).powi(2);
        if s0 >= self.squared_activation {
            // d_hat below 1e-8 L: the IPC toolkit's fallback.
            s0 = 0.5 * self.squared_activation;
        }
        let curvature = 4.0 * s0 * barrier_second_derivative(s0, self.squared_activation);
        let min = 1e11 * self.average_mass / curvature / weight;
        (min, 100.0 * min)
    }

    /// Finds the candidates at `x` and the stencils active there; returns
    /// the smallest squared distance among the candidates.
    fn find_active(&mut self, x: &[Vector<D>]) -> f64 {
        let start = Instant::now();
        self.finder.find(
            &self.mesh,
            x,
            None,
            self.settings.activation_distance,
            self.settings.self_contact,
            &mut self.stencils,
        );
        self.counters.broad_phase += start.elapsed();
        self.active.clear();
        let mut min = f64::INFINITY;
        for (k, stencil) in self.stencils.iter().enumerate() {
            let s = stencil.distance_squared(x);
            min = min.min(s);
            if s < self.squared_activation {
                self.active.push(k);
            }
        }
        min
    }

    /// The smallest distance between two primitives at `x` among those
    /// closer than `d_hat` (`None` when no pair is that close). `x` must be
    /// covered by the last candidate search (the solver's last iterate or
    /// line-search segment).
    pub fn min_distance(&self, x: &[Vector<D>]) -> Option<f64> {
        self.proximity(x).0
    }

    /// [`Self::min_distance`], and the number of stencils closer than
    /// `d_hat` at `x` (the active ones).
    pub fn proximity(&self, x: &[Vector<D>]) -> (Option<f64>, usize) {
        let (mut min, mut active) = (f64::INFINITY, 0);
        for stencil in &self.stencils {
            let s = stencil.distance_squared(x);
            min = min.min(s);
            active += usize::from(s < self.squared_activation);
        }
        (
            (min < self.squared_activation).then(|| min.max(0.0).sqrt()),
            active,
        )
    }

    /// Sets `kappa` by IPC's balance rule at the start of a step (see the
    /// module documentation): `rest_gradient` is the gradient of the
    /// objective without the contact at `x` (`None` when no stencil is
    /// active there: see [`Self::is_active`]), `weight` the integrator's
    /// `w`. A fixed stiffness is left alone. Uses the stencils found at `x`
    /// by [`EnergyTerm::begin_step`], which must come first.
    pub fn balance_stiffness(
        &mut self,
        x: &[Vector<D>],
        rest_gradient: Option<&[Vector<D>]>,
        weight: f64,
        free_index: &[Option<usize>],
    ) {
        if !self.is_adaptive() {
            return;
        }
        let (mut dot, mut norm_squared) = (0.0, 0.0);
        if let Some(rest_gradient) = rest_gradient.filter(|_| self.is_active()) {
            let mut barrier_gradient = std::mem::take(&mut self.barrier_gradient);
            barrier_gradient.clear();
            barrier_gradient.resize(x.len(), Vector::<D>::zeros());
            self.add_barrier_gradient(x, 1.0, &mut barrier_gradient);
            for ((gb, ge), free) in barrier_gradient.iter().zip(rest_gradient).zip(free_index) {
                if free.is_some() {
                    dot += gb.dot(ge);
                    norm_squared += gb.norm_squared();
                }
            }
            self.barrier_gradient = barrier_gradient;
        }
        let (min, max) = self.stiffness_bounds(weight);
        self.max_stiffness = max;
        // Without an active stencil, the IPC toolkit's 1 (clamped), in our
        // weighting.
        let balanced = if norm_squared > 0.0 {
            -dot / (weight * norm_squared)
        } else {
            1.0 / weight
        };
        self.stiffness = if balanced.is_finite() {
            balanced.clamp(min, max)
        } else {
            min
        };
    }

    /// The friction stencils of the stencils active at the lagged state
    /// `lagged` (found there), each with `mu` times its normal force
    /// `kappa |dB / dd|` there, their slip measured from `x_start`,
    /// appended to `out`. The candidates then cover `lagged`, as after an
    /// iteration's search.
    pub fn friction_stencils(
        &mut self,
        lagged: &[Vector<D>],
        x_start: &[Vector<D>],
        mu: f64,
        out: &mut Vec<FrictionStencil<D>>,
    ) {
        self.find_active(lagged);
        self.derivatives.clear();
        for &k in &self.active {
            let stencil = &self.stencils[k];
            let force = normal_force(stencil, lagged, self.squared_activation, self.stiffness);
            let mu = self.stencil_friction(stencil, mu);
            if force > 0.0
                && mu > 0.0
                && let Some(friction) =
                    FrictionStencil::of_contact(stencil, lagged, x_start, mu * force)
            {
                out.push(friction);
            }
        }
    }

    /// The friction coefficient of `stencil`: an obstacle's own where one
    /// side is an obstacle that has one, else the contact's `mu`.
    fn stencil_friction(&self, stencil: &ContactStencil, mu: f64) -> f64 {
        let (a, b) = stencil.sides();
        match (self.mesh.body_of(a[0]), self.mesh.body_of(b[0])) {
            (Some(a), Some(b)) => self.mesh.friction_between(a, b, mu),
            _ => mu,
        }
    }

    /// Whether some stencil can have friction: the contact's coefficient or
    /// an obstacle's is above 0.
    pub fn has_friction(&self, mu: f64) -> bool {
        mu > 0.0 || self.mesh.has_obstacle_friction()
    }

    /// Adds `scale * grad B` (without `kappa`) over every candidate.
    fn add_barrier_gradient(&self, x: &[Vector<D>], scale: f64, gradient: &mut [Vector<D>]) {
        for stencil in &self.stencils {
            if let Some(local) = stencil.energy_derivatives(x, self.squared_activation) {
                scatter(stencil, &local, scale, gradient);
            }
        }
    }

    /// The contact force on every vertex, `-kappa grad B` (zero where no
    /// stencil is active), at a state covered by the last candidate search.
    pub fn forces(&self, x: &[Vector<D>]) -> Vec<Vector<D>> {
        let mut forces = vec![Vector::<D>::zeros(); x.len()];
        self.add_barrier_gradient(x, -self.stiffness, &mut forces);
        forces
    }

    fn compute_active_derivatives(&mut self, x: &[Vector<D>]) {
        let start = Instant::now();
        let (stencils, active, activation) =
            (&self.stencils, &self.active, self.squared_activation);
        let derive = |&k: &usize| stencils[k].energy_derivatives(x, activation);
        self.derivatives.clear();
        if active.len() < PARALLEL_MIN_STENCILS {
            self.derivatives.extend(active.iter().map(derive));
        } else {
            active
                .par_iter()
                .map(derive)
                .collect_into_vec(&mut self.derivatives);
        }
        self.counters.assembly += start.elapsed();
    }
}

/// Adds `scale * local.gradient` to the stencil's vertices.
fn scatter<const D: usize>(
    stencil: &ContactStencil,
    local: &StencilEnergy,
    scale: f64,
    gradient: &mut [Vector<D>],
) {
    for (a, &v) in stencil.corners().iter().enumerate() {
        for (k, g) in gradient[v].iter_mut().enumerate() {
            *g += scale * local.gradient[a * D + k];
        }
    }
}

impl<const D: usize> ContactBarrier<D> {
    /// The collision-free fraction of `x -> x + dx`: the stencils of the
    /// swept segment (broad phase), then CCD on each, timed and counted.
    /// The active set is that of the iterate, which the swept candidates no
    /// longer index, so it is cleared.
    fn swept_step(&mut self, x: &[Vector<D>], dx: &[Vector<D>]) -> CollisionFreeStep {
        let start = Instant::now();
        self.finder.find(
            &self.mesh,
            x,
            Some(dx),
            self.settings.activation_distance,
            self.settings.self_contact,
            &mut self.stencils,
        );
        self.counters.broad_phase += start.elapsed();
        let start = Instant::now();
        let step = collision_free_step(&self.stencils, x, dx, &self.ccd);
        self.counters.ccd += start.elapsed();
        self.counters.ccd_budget_exhausted += step.budget_exhausted;
        self.active.clear();
        self.derivatives.clear();
        step
    }
}

impl<const D: usize> EnergyTerm<D> for ContactBarrier<D> {
    fn name(&self) -> &'static str {
        "contact"
    }

    fn value(&self, x: &[Vector<D>]) -> f64 {
        // A fold from +0: an empty `sum` of floats is -0.
        self.stiffness
            * self
                .stencils
                .iter()
                .map(|s| s.energy(x, self.squared_activation))
                .fold(0.0, |sum, e| sum + e)
    }

    fn add_gradient(&self, x: &[Vector<D>], scale: f64, gradient: &mut [Vector<D>]) {
        self.add_barrier_gradient(x, scale * self.stiffness, gradient);
    }

    fn add_hessian(&self, x: &[Vector<D>], scale: f64, hessian: &mut SparseHessian<D>) {
        let start = Instant::now();
        for &k in &self.active {
            let stencil = &self.stencils[k];
            if let Some(local) = stencil.energy_derivatives(x, self.squared_activation) {
                hessian.add_stencil(
                    stencil.corners(),
                    &(local.hessian * (scale * self.stiffness)),
                );
            }
        }
        self.count_scatter(start);
    }

    fn add_gradient_and_hessian(
        &self,
        _x: &[Vector<D>],
        scale: f64,
        gradient: &mut [Vector<D>],
        hessian: &mut SparseHessian<D>,
    ) {
        // The derivatives were computed for the active stencils by
        // `begin_iteration` at this same iterate.
        let start = Instant::now();
        let weight = scale * self.stiffness;
        for (&k, local) in self.active.iter().zip(&self.derivatives) {
            if let Some(local) = local {
                let stencil = &self.stencils[k];
                scatter(stencil, local, weight, gradient);
                hessian.add_stencil(stencil.corners(), &(local.hessian * weight));
            }
        }
        self.count_scatter(start);
    }

    fn max_step(&mut self, x: &[Vector<D>], dx: &[Vector<D>]) -> f64 {
        self.swept_step(x, dx).step
    }

    fn blocker(&mut self, x: &[Vector<D>], dx: &[Vector<D>]) -> Option<Blocker> {
        let step = self.swept_step(x, dx);
        let stencil = step.limiting.filter(|_| !(step.step > 0.0))?;
        Some(Blocker::Pair {
            corners: stencil.vertices,
            count: stencil.vertex_count(),
            edge_edge: stencil.kind == StencilKind::EdgeEdge,
        })
    }

    fn begin_iteration(&mut self, x: &[Vector<D>]) -> bool {
        let min = self.find_active(x);
        self.compute_active_derivatives(x);
        let mut changed = false;
        if self.is_adaptive() {
            let threshold = (1e-9 * self.bounding_box_diagonal).powi(2);
            if self.previous_min_distance_squared < threshold
                && min < threshold
                && min < self.previous_min_distance_squared
            {
                let raised = (2.0 * self.stiffness).min(self.max_stiffness.max(self.stiffness));
                changed = raised != self.stiffness;
                self.stiffness = raised;
                // The derivatives carry no kappa: they stay valid.
            }
        }
        self.previous_min_distance_squared = min;
        changed
    }

    fn coupled_pairs(&self, pairs: &mut Vec<(usize, usize)>) {
        for &k in &self.active {
            super::push_corner_pairs(self.stencils[k].corners(), pairs);
        }
    }

    /// The candidates at the step's start, for [`Self::balance_stiffness`]
    /// and the stiffness rule's first comparison (an adaptive stiffness
    /// only: with a fixed one the first iteration finds them).
    fn begin_step(&mut self, x: &[Vector<D>], _v: &[Vector<D>]) {
        if self.is_adaptive() {
            self.previous_min_distance_squared = self.find_active(x);
        }
    }
}

#[cfg(test)]
mod tests;
