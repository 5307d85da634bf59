//! Energy terms of the incremental potential, each with value, gradient and Hessian.
//!
//! A time step minimises `E(x) = 1/2 |x - x~|_M^2 + w sum_k U_k(x)`
//! ([`Inertia`] plus the potential terms a scene asks for: [`Elasticity`],
//! [`Gravity`], [`GroundBarrier`], [`ContactBarrier`], and the dissipative
//! [`Friction`], which is in the objective but stores no energy), where the time integrator chooses the
//! prediction `x~` and the weight `w` (`dt^2` for backward Euler). Only the
//! terms a scene asks for are built, so an absent effect costs nothing: no
//! flag is checked inside a hot loop.
//!
//! Every term adds into shared accumulators with a `scale` (the weight `w`):
//! the gradient as one vector per vertex, the Hessian through a
//! [`SparseHessian`] (projected to be positive semi-definite, so that the
//! Newton direction is a descent direction). A term may also cap the line
//! search ([`EnergyTerm::max_step`]): the ground barrier never lets a vertex
//! reach the plane, a Neo-Hookean body never lets an element invert, the
//! contact barrier never lets two surface primitives touch. A term may update
//! itself once per time step ([`EnergyTerm::begin_step`]) and once per solver
//! iteration ([`EnergyTerm::begin_iteration`]: the contact barrier's active
//! set and stiffness).
//!
//! # Adding a term
//!
//! One new file implementing [`EnergyTerm`], and one line in the simulation's
//! setup (`sim/simulation_setup.rs`) that builds it when the scene asks for
//! the effect. Its name and value then appear in the per-frame energy
//! breakdown (`stats.csv`, `elasto check`) without further code. A term that
//! couples vertices sharing no element (contact pairs) declares those pairs
//! ([`EnergyTerm::coupled_pairs`]) and adds its blocks with
//! [`SparseHessian::add_stencil`]; the pattern grows to hold them (see
//! [`crate::assembly`]).

mod body_elasticity;
mod contact_barrier;
mod elasticity;
mod element_derivatives;
mod element_field;
mod friction;
mod gravity;
mod ground_barrier;
mod inertia;
mod prescribed_motion;

pub use body_elasticity::BodyElasticity;
pub use contact_barrier::{ContactBarrier, ContactCounters, ContactSettings};
pub use elasticity::Elasticity;
pub(crate) use elasticity::PARALLEL_MIN_ELEMENTS;
pub use element_field::ElementField;
pub use friction::{Friction, FrictionSettings};
pub use gravity::Gravity;
pub use ground_barrier::{GroundBarrier, STIFFNESS_RATIO as GROUND_STIFFNESS_RATIO};
pub use inertia::Inertia;
pub use prescribed_motion::PrescribedMotion;

use crate::assembly::SparseHessian;
use crate::math::Vector;

/// Where a line search has no room: what makes a term's step cap 0
/// ([`EnergyTerm::blocker`]). Vertex ids are the simulation's (all bodies'
/// meshes joined, in scene order). An element never blocks: the relative
/// volume filter of the materials that forbid inversion always leaves a
/// positive step from an uninverted element (`Elasticity::max_step`); only
/// the ground and contact, at a gap of exactly zero, can leave none.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Blocker {
    /// A vertex on (or below) the ground that the step moves down.
    Vertex(usize),
    /// Two surface primitives at zero distance along the step: the corners
    /// (3 in 2D: vertex against edge; 4 in 3D: vertex against triangle, or
    /// edge against edge).
    Pair {
        /// The corners' vertex ids (the first `count`).
        corners: [usize; 4],
        /// How many corners there are: 3 or 4.
        count: usize,
        /// Whether the pair is two edges (3D).
        edge_edge: bool,
    },
}

impl std::fmt::Display for Blocker {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Blocker::Vertex(v) => {
                write!(f, "vertex {v} is on the ground and the step moves it down")
            }
            Blocker::Pair {
                corners,
                count,
                edge_edge,
            } => {
                let c = &corners[..count];
                match (count, edge_edge) {
                    (3, _) => write!(f, "vertex {} touches edge {}-{}", c[0], c[1], c[2]),
                    (_, false) => write!(
                        f,
                        "vertex {} touches triangle {}-{}-{}",
                        c[0], c[1], c[2], c[3]
                    ),
                    (_, true) => write!(f, "edge {}-{} touches edge {}-{}", c[0], c[1], c[2], c[3]),
                }
            }
        }
    }
}

/// Appends every pair of a stencil's `corners` (for
/// [`EnergyTerm::coupled_pairs`] of the terms that couple stencils: the
/// contact barrier and friction).
pub(crate) fn push_corner_pairs(corners: &[usize], pairs: &mut Vec<(usize, usize)>) {
    for (i, &a) in corners.iter().enumerate() {
        for &b in &corners[i + 1..] {
            pairs.push((a, b));
        }
    }
}

/// One additive term of the incremental potential.
pub trait EnergyTerm<const D: usize>: Send + Sync {
    /// A short name for statistics ("elastic", "gravity", "barrier", ...).
    fn name(&self) -> &'static str;
    /// The energy at positions `x` (`+inf` at infeasible states).
    fn value(&self, x: &[Vector<D>]) -> f64;
    /// Adds `scale * dE/dx` into `gradient` (one entry per vertex).
    fn add_gradient(&self, x: &[Vector<D>], scale: f64, gradient: &mut [Vector<D>]);
    /// Adds `scale * d2E/dx2`, projected to be positive semi-definite, into `hessian`.
    fn add_hessian(&self, x: &[Vector<D>], scale: f64, hessian: &mut SparseHessian<D>);
    /// Both [`Self::add_gradient`] and [`Self::add_hessian`]; a term whose
    /// two share work (the elasticity: `F`, `P`, `dP/dF` per element) does
    /// them in one pass. The default calls the two.
    fn add_gradient_and_hessian(
        &self,
        x: &[Vector<D>],
        scale: f64,
        gradient: &mut [Vector<D>],
        hessian: &mut SparseHessian<D>,
    ) {
        self.add_gradient(x, scale, gradient);
        self.add_hessian(x, scale, hessian);
    }
    /// [`Self::add_gradient_and_hessian`] without the PSD projection where
    /// the term has one to leave out, for Newton with projection on demand
    /// (`solver.projection`): the elasticity adds its exact element
    /// Hessians. The default is the projected Hessian, which is the exact
    /// one for the terms that are PSD by construction (inertia, gravity,
    /// the ground barrier, friction's lagged Hessian, prescribed motion);
    /// the contact barrier keeps its per-stencil projection (IPC's
    /// practice) this way.
    fn add_gradient_and_unprojected_hessian(
        &self,
        x: &[Vector<D>],
        scale: f64,
        gradient: &mut [Vector<D>],
        hessian: &mut SparseHessian<D>,
    ) {
        self.add_gradient_and_hessian(x, scale, gradient, hessian);
    }
    /// The largest `t` in `(0, 1]` such that the whole segment `x + s dx`,
    /// `0 <= s <= t`, stays feasible for this term, with a safety margin.
    /// Called once per line search, before any trial point is evaluated; a
    /// contact term finds the stencils of the swept segment here, so that
    /// [`Self::value`] covers every trial point on it.
    fn max_step(&mut self, _x: &[Vector<D>], _dx: &[Vector<D>]) -> f64 {
        1.0
    }
    /// What leaves no step at all when [`Self::max_step`] is 0 (the vertex,
    /// element or pair whose feasibility allows no move along `dx`), for the
    /// report of a step that could not move. `None` when the term allows a
    /// step. Called only after a zero cap, so it may repeat the search.
    fn blocker(&mut self, _x: &[Vector<D>], _dx: &[Vector<D>]) -> Option<Blocker> {
        None
    }
    /// Called at the start of every solver iteration, at the iterate `x`,
    /// before its gradient and Hessian: a contact term finds the stencils
    /// active at `x` and may raise its stiffness here. Returns whether the
    /// term's energy changed as a function of `x` (the solver then evaluates
    /// `E(x)` again). Most terms do nothing.
    fn begin_iteration(&mut self, _x: &[Vector<D>]) -> bool {
        false
    }
    /// Appends the vertex pairs (simulation vertex ids) whose Hessian blocks
    /// this term fills beyond the pairs that share an element, as found by
    /// the last [`Self::begin_iteration`]: the sparse pattern grows to hold
    /// them before assembly. Only contact terms have any.
    fn coupled_pairs(&self, _pairs: &mut Vec<(usize, usize)>) {}
    /// Called once at the start of every time step, before the solve, with
    /// the positions and velocities the step starts from. A term whose
    /// energy depends on the step's start (lagged friction needs the contact
    /// forces there) updates itself here; most terms do nothing.
    fn begin_step(&mut self, _x: &[Vector<D>], _v: &[Vector<D>]) {}
}
