//! Implicit Newmark (`beta = 1/4`, `gamma = 1/2`, the trapezoidal rule): `x~ = x_n + dt v_n + dt^2/4 a_n`, weight `dt^2/4`, `a_{n+1} = 4 (x_{n+1} - x~) / dt^2`, `v_{n+1} = v_n + dt/2 (a_n + a_{n+1})`.
//!
//! Newmark's scheme with `M a_{n+1} = -grad U(x_{n+1})`:
//!
//! ```text
//! x_{n+1} = x_n + dt v_n + dt^2 ((1/2 - beta) a_n + beta a_{n+1})
//! v_{n+1} = v_n + dt ((1 - gamma) a_n + gamma a_{n+1})
//! ```
//!
//! With `beta = 1/4` the first reads `x_{n+1} = x~ + dt^2/4 a_{n+1}`,
//! `x~ = x_n + dt v_n + dt^2/4 a_n`, that is
//! `M (x_{n+1} - x~) = -dt^2/4 grad U(x_{n+1})`: the stationarity condition
//! of `1/2 |x - x~|_M^2 + dt^2/4 U(x)`. The minimiser gives the new
//! acceleration `a_{n+1} = 4 (x_{n+1} - x~) / dt^2` and, with `gamma = 1/2`,
//! the velocity `v_{n+1} = v_n + dt/2 (a_n + a_{n+1})`.
//!
//! The scheme carries the acceleration: the first step needs
//! `a_0 = -M^{-1} grad U(x_0)` (zero on pinned vertices), which the
//! simulation hands over once at setup
//! ([`TimeIntegrator::set_initial_acceleration`]). Second order, no
//! numerical damping: for a linear problem it conserves
//! `1/2 v^T M v + U(x)` exactly (for a nonlinear one, up to `O(dt^2)`),
//! and it is exact for a constant acceleration (free fall).

use super::TimeIntegrator;
use crate::math::Vector;

/// Newmark's trapezoidal rule, keeping `x~`, `v_n` and `a_n`.
#[derive(Debug, Clone)]
pub struct Newmark<const D: usize> {
    predicted: Vec<Vector<D>>,
    /// `v_n` of the step begun last.
    start_velocity: Vec<Vector<D>>,
    /// `a_n`: the initial acceleration, then the last step's `a_{n+1}`.
    acceleration: Vec<Vector<D>>,
}

impl<const D: usize> Newmark<D> {
    /// Newmark for `vertex_count` vertices, with zero initial acceleration
    /// until [`TimeIntegrator::set_initial_acceleration`] says otherwise.
    pub fn new(vertex_count: usize) -> Self {
        let zeros = vec![Vector::<D>::zeros(); vertex_count];
        Self {
            predicted: zeros.clone(),
            start_velocity: zeros.clone(),
            acceleration: zeros,
        }
    }
}

impl<const D: usize> TimeIntegrator<D> for Newmark<D> {
    fn set_initial_acceleration(&mut self, acceleration: &[Vector<D>]) {
        self.acceleration.copy_from_slice(acceleration);
    }

    fn begin_step(&mut self, x: &[Vector<D>], v: &[Vector<D>], dt: f64) {
        self.start_velocity.copy_from_slice(v);
        for (((p, x), v), a) in self
            .predicted
            .iter_mut()
            .zip(x)
            .zip(v)
            .zip(&self.acceleration)
        {
            *p = x + v * dt + a * (0.25 * dt * dt);
        }
    }

    fn predicted(&self) -> &[Vector<D>] {
        &self.predicted
    }

    fn potential_weight(&self, dt: f64) -> f64 {
        0.25 * dt * dt
    }

    fn boxed_clone(&self) -> Box<dyn TimeIntegrator<D>> {
        Box::new(self.clone())
    }

    fn end_step(&mut self, x_new: &[Vector<D>], velocities: &mut [Vector<D>], dt: f64) {
        for ((((v, a), x), p), v0) in velocities
            .iter_mut()
            .zip(&mut self.acceleration)
            .zip(x_new)
            .zip(&self.predicted)
            .zip(&self.start_velocity)
        {
            let a_new = (x - p) * (4.0 / (dt * dt));
            *v = v0 + (*a + a_new) * (0.5 * dt);
            *a = a_new;
        }
    }
}
