//! BDF2: `x~ = 4/3 x_n - 1/3 x_{n-1} + 8/9 dt v_n - 2/9 dt v_{n-1}`, weight `4/9 dt^2`, `v_{n+1} = (3 x_{n+1} - 4 x_n + x_{n-1}) / (2 dt)`; the first step is backward Euler.
//!
//! The second-order backward differentiation formula, applied to positions
//! and to velocities (with `M a_{n+1} = -grad U(x_{n+1})`):
//!
//! ```text
//! x_{n+1} - 4/3 x_n + 1/3 x_{n-1} = 2/3 dt v_{n+1}
//! v_{n+1} - 4/3 v_n + 1/3 v_{n-1} = 2/3 dt a_{n+1}
//! ```
//!
//! Putting the second into the first:
//!
//! ```text
//! x_{n+1} = 4/3 x_n - 1/3 x_{n-1} + 2/3 dt (4/3 v_n - 1/3 v_{n-1}) + 4/9 dt^2 a_{n+1}
//!         = x~ + 4/9 dt^2 a_{n+1},
//! x~      = 4/3 x_n - 1/3 x_{n-1} + 8/9 dt v_n - 2/9 dt v_{n-1},
//! ```
//!
//! that is `M (x_{n+1} - x~) = -4/9 dt^2 grad U(x_{n+1})`: the stationarity
//! condition of `1/2 |x - x~|_M^2 + 4/9 dt^2 U(x)`. The first relation then
//! gives the velocity, `v_{n+1} = (3 x_{n+1} - 4 x_n + x_{n-1}) / (2 dt)`,
//! and with it the second relation holds exactly (multiply out
//! `3/(2 dt) (x_{n+1} - 4/3 x_n + 1/3 x_{n-1})`).
//!
//! BDF2 needs two past states; the first step (and any step whose `dt`
//! differs from the previous one's) is a backward-Euler step
//! (`x~ = x_n + dt v_n`, weight `dt^2`, `v_{n+1} = (x_{n+1} - x_n) / dt`),
//! whose local error `O(dt^2)` keeps the scheme second order. Second order
//! and L-stable: it damps the highest frequencies like backward Euler but
//! the resolved ones far less (its energy loss per period is `O(dt^3)`
//! against backward Euler's `O(dt)`). For a constant acceleration it is
//! exact once started: the backward-Euler start leaves a constant offset
//! of `3/4 dt^2 a` in the positions (`tests/integration/integrators.rs`), and the
//! velocities are exact.

use super::TimeIntegrator;
use crate::math::Vector;

/// BDF2, keeping `x_n`, `v_n` and the previous step's `x_{n-1}`, `v_{n-1}`.
#[derive(Debug, Clone)]
pub struct Bdf2<const D: usize> {
    predicted: Vec<Vector<D>>,
    /// `x_n` and `v_n` of the step begun last.
    start: Vec<Vector<D>>,
    start_velocity: Vec<Vector<D>>,
    /// `x_{n-1}` and `v_{n-1}`, once a step has been taken.
    previous: Vec<Vector<D>>,
    previous_velocity: Vec<Vector<D>>,
    /// The length of the last step taken (`None` before the first).
    previous_dt: Option<f64>,
    /// Whether the step begun last is a BDF2 step (else backward Euler).
    two_step: bool,
}

impl<const D: usize> Bdf2<D> {
    /// BDF2 for `vertex_count` vertices.
    pub fn new(vertex_count: usize) -> Self {
        let zeros = vec![Vector::<D>::zeros(); vertex_count];
        Self {
            predicted: zeros.clone(),
            start: zeros.clone(),
            start_velocity: zeros.clone(),
            previous: zeros.clone(),
            previous_velocity: zeros,
            previous_dt: None,
            two_step: false,
        }
    }
}

impl<const D: usize> TimeIntegrator<D> for Bdf2<D> {
    fn begin_step(&mut self, x: &[Vector<D>], v: &[Vector<D>], dt: f64) {
        self.start.copy_from_slice(x);
        self.start_velocity.copy_from_slice(v);
        self.two_step = self.previous_dt == Some(dt);
        if self.two_step {
            for ((((p, x), v), x1), v1) in self
                .predicted
                .iter_mut()
                .zip(x)
                .zip(v)
                .zip(&self.previous)
                .zip(&self.previous_velocity)
            {
                *p = (x * 4.0 - x1) / 3.0 + (v * 4.0 - v1) * (2.0 * dt / 9.0);
            }
        } else {
            for ((p, x), v) in self.predicted.iter_mut().zip(x).zip(v) {
                *p = x + v * dt;
            }
        }
    }

    fn predicted(&self) -> &[Vector<D>] {
        &self.predicted
    }

    fn potential_weight(&self, dt: f64) -> f64 {
        if self.two_step {
            4.0 / 9.0 * dt * dt
        } else {
            dt * dt
        }
    }

    fn boxed_clone(&self) -> Box<dyn TimeIntegrator<D>> {
        Box::new(self.clone())
    }

    fn end_step(&mut self, x_new: &[Vector<D>], velocities: &mut [Vector<D>], dt: f64) {
        if self.two_step {
            for (((v, x), x0), x1) in velocities
                .iter_mut()
                .zip(x_new)
                .zip(&self.start)
                .zip(&self.previous)
            {
                *v = (x * 3.0 - x0 * 4.0 + x1) / (2.0 * dt);
            }
        } else {
            for ((v, x), x0) in velocities.iter_mut().zip(x_new).zip(&self.start) {
                *v = (x - x0) / dt;
            }
        }
        // x_n, v_n become x_{n-1}, v_{n-1} of the next step.
        std::mem::swap(&mut self.previous, &mut self.start);
        std::mem::swap(&mut self.previous_velocity, &mut self.start_velocity);
        self.previous_dt = Some(dt);
    }
}
