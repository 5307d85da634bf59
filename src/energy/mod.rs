//! Energy terms of the incremental potential, each with value, gradient and Hessian.
//!
//! A time step minimises `E(x) = 1/2 |x - x_pred|_M^2 + dt^2 sum_k U_k(x)`
//! ([`Inertia`] plus the potential terms a scene asks for: [`Elasticity`],
//! [`Gravity`], [`GroundBarrier`]). Only the terms a scene asks for are built, so
//! an absent effect costs nothing: no flag is checked inside a hot loop.
//!
//! Every term adds into shared accumulators with a `scale` (the `dt^2` above):
//! the gradient as one vector per vertex, the Hessian through a
//! [`SparseHessian`] (projected to be positive semi-definite, so that the
//! Newton direction is a descent direction). A term may also cap the line
//! search ([`EnergyTerm::max_step`]): the ground barrier never lets a vertex
//! reach the plane, a Neo-Hookean body never lets an element invert.

mod elasticity;
mod gravity;
mod ground_barrier;
mod inertia;

pub use elasticity::Elasticity;
pub use gravity::Gravity;
pub use ground_barrier::GroundBarrier;
pub use inertia::Inertia;

use crate::math::Vector;
use crate::solver::SparseHessian;

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
    /// The largest `t` in `(0, 1]` such that the whole segment `x + s dx`,
    /// `0 <= s <= t`, stays feasible for this term, with a safety margin.
    fn max_step(&self, _x: &[Vector<D>], _dx: &[Vector<D>]) -> f64 {
        1.0
    }
}
