//! Backward Euler: `x~ = x_n + dt v_n`, weight `dt^2`, `v_{n+1} = (x_{n+1} - x_n) / dt`.
//!
//! The report's scheme. Minimising `1/2 |x - x~|_M^2 + dt^2 U(x)` gives
//! `M (x_{n+1} - x_n - dt v_n) / dt^2 = -grad U(x_{n+1})`, which with the
//! velocity update above is exactly `M (v_{n+1} - v_n) / dt = f(x_{n+1})`.
//! First order in `dt`; it dissipates energy, the more the larger `dt`
//! (numerical damping), and never creates any.

use super::TimeIntegrator;
use crate::math::Vector;

/// Backward Euler, keeping `x_n` for the velocity update.
#[derive(Debug, Clone)]
pub struct BackwardEuler<const D: usize> {
    predicted: Vec<Vector<D>>,
    start: Vec<Vector<D>>,
}

impl<const D: usize> BackwardEuler<D> {
    /// Backward Euler for `vertex_count` vertices.
    pub fn new(vertex_count: usize) -> Self {
        Self {
            predicted: vec![Vector::<D>::zeros(); vertex_count],
            start: vec![Vector::<D>::zeros(); vertex_count],
        }
    }
}

impl<const D: usize> TimeIntegrator<D> for BackwardEuler<D> {
    fn begin_step(&mut self, x: &[Vector<D>], v: &[Vector<D>], dt: f64) {
        self.start.copy_from_slice(x);
        for ((p, x), v) in self.predicted.iter_mut().zip(x).zip(v) {
            *p = x + v * dt;
        }
    }

    fn predicted(&self) -> &[Vector<D>] {
        &self.predicted
    }

    fn potential_weight(&self, dt: f64) -> f64 {
        dt * dt
    }

    fn boxed_clone(&self) -> Box<dyn TimeIntegrator<D>> {
        Box::new(self.clone())
    }

    fn end_step(&mut self, x_new: &[Vector<D>], velocities: &mut [Vector<D>], dt: f64) {
        for ((v, x), x0) in velocities.iter_mut().zip(x_new).zip(&self.start) {
            *v = (x - x0) / dt;
        }
    }
}
