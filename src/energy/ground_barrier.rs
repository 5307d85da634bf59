//! The report's ground barrier (Li et al. 2020, IPC) against the plane `y = h`.
//!
//! For a vertex at gap `d = y - h` the barrier is
//!
//! ```text
//! b(d) = -(d - a)^2 ln(d / a)   for 0 < d < a,      0 for d >= a,     +inf for d <= 0,
//! b'(d)  = -2 (d - a) ln(d / a) - (d - a)^2 / d,
//! b''(d) = -2 ln(d / a) - 4 (d - a) / d + (d - a)^2 / d^2   (> 0 on (0, a): convex),
//! ```
//!
//! and the term is `kappa sum_i b(y_i - h)`. It is C2 at `d = a`, so Newton sees
//! no kick when a vertex enters the barrier; it is infinite at contact, and the
//! line search keeps every vertex strictly above the plane by a continuous
//! collision check ([`GroundBarrier::max_step`]), so the report's clamping to a
//! small epsilon, and the non-conservative force it caused, never arise.
//!
//! **Default stiffness.** Backward Euler does not create energy, so at any time
//! the barrier energy is at most the body's initial mechanical energy relative
//! to the ground, `E_0 = 1/2 sum m |v_0|^2 + sum m |g| (y_i - h)`. Choosing
//! `kappa = 2 E_0 / b(a / 100)` means that even one vertex alone, holding all of
//! that energy, stays farther than 1% of `a` from the plane, with a factor 2 to
//! spare. `E_0` is floored at `M (|g| a + a^2 / 1 s^2)` so a body at rest near
//! the ground still gets a usable stiffness.

use super::{Blocker, EnergyTerm};
use crate::assembly::SparseHessian;
use crate::contact::friction::FrictionStencil;
use crate::contact::{barrier, barrier_derivative, barrier_second_derivative};
use crate::math::{Matrix, UP_AXIS, Vector};

/// The fraction of the current gap a single line-search step may close at most.
pub const CONTACT_STEP_FRACTION: f64 = 0.9;

/// Bounds on a stiffness given in the scene relative to the automatic one:
/// beyond them the body stops at the barrier's edge with every step at the
/// iteration cap, or comes within round-off of the ground.
pub const STIFFNESS_RATIO: [f64; 2] = [1e-6, 1e6];

/// `kappa sum_i b(x_i[UP] - height)` over the bodies' vertices (the first
/// ones of a position array; obstacles' vertices after them are not held
/// by the ground).
#[derive(Debug, Clone)]
pub struct GroundBarrier {
    height: f64,
    width: f64,
    stiffness: f64,
    /// The default rule's stiffness for the bodies it was built for.
    automatic_stiffness: f64,
    /// The bodies' vertices: `0..body_vertices` of a position array.
    body_vertices: usize,
}

impl GroundBarrier {
    /// A barrier against the plane at `height` acting within `width` (`a`) with `stiffness` (`kappa`).
    pub fn new(height: f64, width: f64, stiffness: f64) -> Self {
        Self {
            height,
            width,
            stiffness,
            automatic_stiffness: stiffness,
            body_vertices: usize::MAX,
        }
    }

    /// The barrier for bodies with `masses` at `positions` moving with
    /// `velocities` under `gravity`: with the stiffness `fixed` when the
    /// scene gives one, else by the default rule. It holds these vertices
    /// only (any after them in a position array are obstacles').
    pub fn for_bodies<const D: usize>(
        height: f64,
        width: f64,
        fixed: Option<f64>,
        masses: &[f64],
        positions: &[Vector<D>],
        velocities: &[Vector<D>],
        gravity: Option<Vector<D>>,
    ) -> Self {
        let automatic_stiffness =
            Self::default_stiffness(height, width, masses, positions, velocities, gravity);
        Self {
            height,
            width,
            stiffness: fixed.unwrap_or(automatic_stiffness),
            automatic_stiffness,
            body_vertices: positions.len(),
        }
    }

    /// The stiffness `kappa` in use.
    pub fn stiffness(&self) -> f64 {
        self.stiffness
    }

    /// The stiffness the default rule gives the bodies this barrier was
    /// built for (the one in use unless the scene fixes it).
    pub fn automatic_stiffness(&self) -> f64 {
        self.automatic_stiffness
    }

    /// The plane's height.
    pub fn height(&self) -> f64 {
        self.height
    }

    /// The barrier's width `a`: it acts on vertices closer than this.
    pub fn width(&self) -> f64 {
        self.width
    }

    /// The lowest vertex's height above the plane (`+inf` for no vertex).
    pub fn min_height<const D: usize>(&self, x: &[Vector<D>]) -> f64 {
        self.held(x)
            .iter()
            .map(|xi| self.gap(xi))
            .fold(f64::INFINITY, f64::min)
    }

    /// The friction stencils of the vertices within the barrier's width at
    /// the lagged state `lagged` (each with `mu` times the barrier's push
    /// `kappa |b'(d)|` there, the normal up), their slip measured from
    /// `x_start`, appended to `out`.
    pub fn friction_stencils<const D: usize>(
        &self,
        lagged: &[Vector<D>],
        x_start: &[Vector<D>],
        mu: f64,
        out: &mut Vec<FrictionStencil<D>>,
    ) {
        let mut up = Vector::<D>::zeros();
        up[UP_AXIS] = 1.0;
        for (vertex, xi) in self.held(lagged).iter().enumerate() {
            let d = self.gap(xi);
            if d > 0.0 && d < self.width {
                let push = -self.stiffness * barrier_derivative(d, self.width);
                out.push(FrictionStencil::vertex_on_plane(
                    vertex,
                    x_start,
                    up,
                    mu * push,
                ));
            }
        }
    }

    /// The first vertex on or below the plane, with its height.
    pub fn first_vertex_below<const D: usize>(&self, x: &[Vector<D>]) -> Option<(usize, f64)> {
        self.held(x)
            .iter()
            .position(|xi| !(self.gap(xi) > 0.0))
            .map(|v| (v, x[v][UP_AXIS]))
    }

    /// Why a vertex whose position is prescribed cannot be at `target`
    /// (on or below the plane: no solve can lift it off), or `None`.
    pub fn prescribed_position_problem<const D: usize>(
        &self,
        vertex: usize,
        target: &Vector<D>,
    ) -> Option<String> {
        (vertex < self.body_vertices && !(self.gap(target) > 0.0)).then(|| {
            format!(
                "puts vertex {vertex} at height {}, on or below the ground at {}",
                target[UP_AXIS], self.height
            )
        })
    }

    /// The default `kappa` for a body with `masses` at `positions` moving with
    /// `velocities` under `gravity` (see the module documentation).
    pub fn default_stiffness<const D: usize>(
        height: f64,
        width: f64,
        masses: &[f64],
        positions: &[Vector<D>],
        velocities: &[Vector<D>],
        gravity: Option<Vector<D>>,
    ) -> f64 {
        let g = gravity.map_or(0.0, |g| g.norm());
        let total_mass: f64 = masses.iter().sum();
        let energy: f64 = masses
            .iter()
            .zip(positions)
            .zip(velocities)
            .map(|((m, x), v)| 0.5 * m * v.norm_squared() + m * g * (x[UP_AXIS] - height).max(0.0))
            .sum();
        let floor = total_mass * (g * width + width * width);
        2.0 * energy.max(floor) / barrier(width / 100.0, width)
    }

    fn gap<const D: usize>(&self, x: &Vector<D>) -> f64 {
        x[UP_AXIS] - self.height
    }

    /// The part of a per-vertex array the ground holds: the bodies' vertices.
    fn held<'a, T>(&self, x: &'a [T]) -> &'a [T] {
        &x[..self.body_vertices.min(x.len())]
    }
}

impl<const D: usize> EnergyTerm<D> for GroundBarrier {
    fn name(&self) -> &'static str {
        "barrier"
    }

    fn value(&self, x: &[Vector<D>]) -> f64 {
        self.stiffness
            * self
                .held(x)
                .iter()
                .map(|xi| barrier(self.gap(xi), self.width))
                .sum::<f64>()
    }

    fn add_gradient(&self, x: &[Vector<D>], scale: f64, gradient: &mut [Vector<D>]) {
        for (g, xi) in gradient.iter_mut().zip(self.held(x)) {
            let d = self.gap(xi);
            if d < self.width {
                g[UP_AXIS] += scale * self.stiffness * barrier_derivative(d, self.width);
            }
        }
    }

    fn add_hessian(&self, x: &[Vector<D>], scale: f64, hessian: &mut SparseHessian<D>) {
        for (vertex, xi) in self.held(x).iter().enumerate() {
            let d = self.gap(xi);
            if d < self.width {
                let mut block = Matrix::<D>::zeros();
                block[(UP_AXIS, UP_AXIS)] =
                    scale * self.stiffness * barrier_second_derivative(d, self.width);
                hessian.add_vertex_block(vertex, &block);
            }
        }
    }

    /// Continuous collision check against the plane: a vertex moving down by
    /// `dx` reaches it at `t = d / -dx_up`; the step may close at most
    /// `CONTACT_STEP_FRACTION` (0.9) of any gap.
    fn max_step(&mut self, x: &[Vector<D>], dx: &[Vector<D>]) -> f64 {
        self.held(x)
            .iter()
            .zip(dx)
            .filter(|(_, step)| step[UP_AXIS] < 0.0)
            .map(|(xi, step)| CONTACT_STEP_FRACTION * self.gap(xi) / -step[UP_AXIS])
            .fold(1.0, f64::min)
    }

    fn blocker(&mut self, x: &[Vector<D>], dx: &[Vector<D>]) -> Option<Blocker> {
        self.held(x)
            .iter()
            .zip(dx)
            .position(|(xi, step)| step[UP_AXIS] < 0.0 && !(self.gap(xi) > 0.0))
            .map(Blocker::Vertex)
    }
}
