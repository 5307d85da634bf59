//! Lagged IPC friction as a term of the incremental potential: the sum of the friction stencils frozen at a step's start.
//!
//! The term is
//!
//! ```text
//! D(x) = sum_k mu_k lambda_k f0(|u_k(x)|; eps),     eps = eps_v dt,
//! ```
//!
//! over the friction stencils `k` ([`crate::contact::friction`] writes out
//! `u_k`, `f0` and the derivatives): one per contact stencil active at the
//! lagged state (with `lambda_k = kappa |dB_k / dd|`, the contact
//! barrier's normal force there, and the contact `mu`) and one per vertex
//! within the ground's barrier width (with `lambda = kappa |b'(d)|` and the
//! ground's `mu`). The stencils are built at the step's start
//! ([`Friction::lag`]) and, for `solver.friction_iterations > 1`, built
//! again at each solution for another solve (the slip still measured from
//! the step's start), as polyfem does. The integrator's weight `w` scales
//! `D` like any potential: `D` is the work friction does over the step, and
//! `w grad D` the impulse it gives (for backward Euler, `-grad D` is the
//! friction force at the step's end).
//!
//! Friction dissipates: `D` is no stored energy, so it is not among the
//! potentials of the energy breakdown. The work it took out of the bodies
//! over a step, `sum_k mu_k lambda_k f1(y_k) y_k` at the step's end, is
//! summed into `friction_dissipated` ([`Friction::dissipated`]).
//!
//! The Hessian of every stencil is positive semi-definite by construction,
//! so it is added without projection; its vertex pairs are declared
//! ([`EnergyTerm::coupled_pairs`]) so that the sparse pattern holds them,
//! like the contact barrier's.

use super::EnergyTerm;
use crate::assembly::SparseHessian;
use crate::contact::MAX_STENCIL_COORDINATES;
use crate::contact::friction::FrictionStencil;
use crate::math::{Matrix, Vector};
use nalgebra::SMatrix;

/// The friction coefficients and the velocity threshold of a scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionSettings {
    /// `mu` between and within bodies (0: none).
    pub contact: f64,
    /// `mu` against the ground (0: none).
    pub ground: f64,
    /// `eps_v`: below this slip velocity friction is static (smoothed), in
    /// length/s.
    pub velocity_threshold: f64,
}

/// `sum_k mu_k lambda_k f0(|u_k|)` over the stencils frozen at a step's start.
#[derive(Debug, Clone)]
pub struct Friction<const D: usize> {
    settings: FrictionSettings,
    /// `eps = eps_v dt` of the step being solved.
    slip_threshold: f64,
    stencils: Vec<FrictionStencil<D>>,
}

impl<const D: usize> Friction<D> {
    /// The term with no stencils yet (the first [`Self::lag`] builds them).
    pub fn new(settings: FrictionSettings) -> Self {
        Self {
            settings,
            slip_threshold: settings.velocity_threshold,
            stencils: Vec::new(),
        }
    }

    /// The coefficients and the velocity threshold.
    pub fn settings(&self) -> FrictionSettings {
        self.settings
    }

    /// Replaces the stencils by `stencils` for a step of length `dt`.
    pub fn lag(&mut self, stencils: Vec<FrictionStencil<D>>, dt: f64) {
        self.stencils = stencils;
        self.slip_threshold = self.settings.velocity_threshold * dt;
    }

    /// The stencils in use.
    pub fn stencils(&self) -> &[FrictionStencil<D>] {
        &self.stencils
    }

    /// The work friction did on the bodies from the step's start to `x`,
    /// `sum_k mu_k lambda_k f1(y_k) y_k` (force against the slip times its
    /// length; non-negative).
    pub fn dissipated(&self, x: &[Vector<D>]) -> f64 {
        self.stencils
            .iter()
            .map(|s| s.dissipated(x, self.slip_threshold))
            .fold(0.0, |sum, w| sum + w)
    }

    /// The friction force on every vertex at `x`, `-grad D` (the potential
    /// is work over the step, so its gradient is a force).
    pub fn forces(&self, x: &[Vector<D>]) -> Vec<Vector<D>> {
        let mut forces = vec![Vector::<D>::zeros(); x.len()];
        self.add_gradient(x, -1.0, &mut forces);
        forces
    }
}

impl<const D: usize> EnergyTerm<D> for Friction<D> {
    fn name(&self) -> &'static str {
        "friction"
    }

    fn value(&self, x: &[Vector<D>]) -> f64 {
        self.stencils
            .iter()
            .map(|s| s.potential(x, self.slip_threshold))
            .fold(0.0, |sum, e| sum + e)
    }

    fn add_gradient(&self, x: &[Vector<D>], scale: f64, gradient: &mut [Vector<D>]) {
        for stencil in &self.stencils {
            let local = stencil.derivatives(x, self.slip_threshold);
            add_stencil_gradient(stencil, &local.gradient, scale, gradient);
        }
    }

    fn add_hessian(&self, x: &[Vector<D>], scale: f64, hessian: &mut SparseHessian<D>) {
        for stencil in &self.stencils {
            let local = stencil.derivatives(x, self.slip_threshold).hessian * scale;
            add_stencil_blocks(stencil, &local, hessian);
        }
    }

    fn add_gradient_and_hessian(
        &self,
        x: &[Vector<D>],
        scale: f64,
        gradient: &mut [Vector<D>],
        hessian: &mut SparseHessian<D>,
    ) {
        for stencil in &self.stencils {
            let local = stencil.derivatives(x, self.slip_threshold);
            add_stencil_gradient(stencil, &local.gradient, scale, gradient);
            add_stencil_blocks(stencil, &(local.hessian * scale), hessian);
        }
    }

    fn coupled_pairs(&self, pairs: &mut Vec<(usize, usize)>) {
        for stencil in &self.stencils {
            super::push_corner_pairs(stencil.corners(), pairs);
        }
    }
}

/// Adds `scale w_a g` to each corner `a` of a stencil.
fn add_stencil_gradient<const D: usize>(
    stencil: &FrictionStencil<D>,
    g: &Vector<D>,
    scale: f64,
    gradient: &mut [Vector<D>],
) {
    for (&w, &v) in stencil.weights.iter().zip(stencil.corners()) {
        gradient[v] += g * (scale * w);
    }
}

/// Adds the blocks `w_a w_b H` of a stencil (a vertex on the ground: its
/// one diagonal block).
fn add_stencil_blocks<const D: usize>(
    stencil: &FrictionStencil<D>,
    block: &Matrix<D>,
    hessian: &mut SparseHessian<D>,
) {
    if stencil.count == 1 {
        hessian.add_vertex_block(stencil.vertices[0], &(block * stencil.weights[0].powi(2)));
        return;
    }
    let mut local = SMatrix::<f64, MAX_STENCIL_COORDINATES, MAX_STENCIL_COORDINATES>::zeros();
    let w = &stencil.weights;
    for a in 0..stencil.count {
        for b in 0..stencil.count {
            local
                .fixed_view_mut::<D, D>(a * D, b * D)
                .copy_from(&(block * (w[a] * w[b])));
        }
    }
    hessian.add_stencil(stencil.corners(), &local);
}

#[cfg(test)]
mod tests;
