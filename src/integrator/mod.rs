//! Time integrators posed as incremental potentials: each owns its prediction `x~`, the weight on the potential, its history and the velocity update.
//!
//! Every implicit scheme here advances positions by minimising
//!
//! ```text
//! x_{n+1} = argmin_x  1/2 |x - x~|_M^2 + w U(x),
//! ```
//!
//! whose stationarity condition `M (x - x~) = -w grad U(x)` is the scheme's
//! update. The scheme chooses the prediction `x~` (from `x_n`, `v_n` and
//! whatever history it keeps) and the weight `w` on the potential, and after
//! the solve turns `x_{n+1}` into `v_{n+1}`. The solver sees only the
//! objective; the simulation sees only [`TimeIntegrator`].
//!
//! | scheme | `x~` | `w` | velocity update |
//! |---|---|---|---|
//! | [`BackwardEuler`] | `x_n + dt v_n` | `dt^2` | `(x_{n+1} - x_n) / dt` |
//!
//! # Adding a scheme
//!
//! One new file implementing [`TimeIntegrator`] (its module doc writes out
//! `x~`, `w` and the velocity update), one arm in [`IntegratorKind`] (whose
//! serde name is the scene value of `time.integrator`), and one arm in
//! [`IntegratorKind::build`].

mod backward_euler;

pub use backward_euler::BackwardEuler;

use crate::math::Vector;
use serde::{Deserialize, Serialize};

/// A time-integration scheme written as an incremental potential.
pub trait TimeIntegrator<const D: usize>: Send + Sync {
    /// Starts a step of length `dt` from positions `x` and velocities `v`:
    /// computes and keeps the prediction `x~` (see [`Self::predicted`]).
    fn begin_step(&mut self, x: &[Vector<D>], v: &[Vector<D>], dt: f64);
    /// The prediction `x~` of the step begun last.
    fn predicted(&self) -> &[Vector<D>];
    /// The weight `w` on the potential energy in the incremental potential.
    fn potential_weight(&self, dt: f64) -> f64;
    /// Ends the step begun last: `x_new` is the minimiser; overwrites
    /// `velocities` with `v_{n+1}` and updates the scheme's history.
    fn end_step(&mut self, x_new: &[Vector<D>], velocities: &mut [Vector<D>], dt: f64);
}

/// The schemes a scene can choose (`time.integrator`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum IntegratorKind {
    /// `backward-euler`: first order, dissipative (default).
    #[default]
    BackwardEuler,
}

impl IntegratorKind {
    /// Every scheme, in the order the README lists them.
    pub const ALL: [IntegratorKind; 1] = [IntegratorKind::BackwardEuler];

    /// The scene-file name.
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::BackwardEuler => "backward-euler",
        }
    }

    /// A fresh integrator of this kind for `vertex_count` vertices.
    pub fn build<const D: usize>(self, vertex_count: usize) -> Box<dyn TimeIntegrator<D>> {
        match self {
            IntegratorKind::BackwardEuler => Box::new(BackwardEuler::new(vertex_count)),
        }
    }
}
