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
//! | [`Bdf2`] (first step: backward Euler) | `4/3 x_n - 1/3 x_{n-1} + 8/9 dt v_n - 2/9 dt v_{n-1}` | `4/9 dt^2` | `(3 x_{n+1} - 4 x_n + x_{n-1}) / (2 dt)` |
//! | [`Newmark`] (`beta = 1/4`, `gamma = 1/2`) | `x_n + dt v_n + dt^2/4 a_n` | `dt^2/4` | `v_n + dt/2 (a_n + a_{n+1})`, `a_{n+1} = 4 (x_{n+1} - x~) / dt^2` |
//!
//! Backward Euler is first order and dissipative; BDF2 is second order and
//! damps high frequencies as strongly but resolved motion far less (energy
//! lost per period `O(dt^3)` against `O(dt)`); Newmark is second order and
//! does not damp (it conserves the energy of a linear problem); where one of
//! its steps would gain energy (a stiff impact), the stepper takes that step
//! again as a backward-Euler step ([`TimeIntegrator::guards_energy`]). A scheme that
//! carries the acceleration (Newmark) gets `a_0 = -M^{-1} grad U(x_0)` once
//! at setup through [`TimeIntegrator::set_initial_acceleration`].
//!
//! # Adding a scheme
//!
//! One new file implementing [`TimeIntegrator`] (its module doc writes out
//! `x~`, `w` and the velocity update), one arm in [`IntegratorKind`] (whose
//! serde name is the scene value of `time.integrator`) with its entry in
//! [`IntegratorKind::ALL`], [`IntegratorKind::name`] and
//! [`IntegratorKind::build`].

mod backward_euler;
mod bdf2;
mod newmark;

pub use backward_euler::BackwardEuler;
pub use bdf2::Bdf2;
pub use newmark::Newmark;

use crate::math::Vector;
use serde::{Deserialize, Serialize};

/// A time-integration scheme written as an incremental potential.
pub trait TimeIntegrator<const D: usize>: Send + Sync {
    /// Called once, before the first step, with the initial acceleration
    /// `a_0 = -M^{-1} grad U(x_0)` (zero on pinned vertices). A scheme that
    /// carries the acceleration (Newmark) keeps it; the others ignore it.
    fn set_initial_acceleration(&mut self, _acceleration: &[Vector<D>]) {}
    /// Starts a step of length `dt` from positions `x` and velocities `v`:
    /// computes and keeps the prediction `x~` (see [`Self::predicted`]).
    fn begin_step(&mut self, x: &[Vector<D>], v: &[Vector<D>], dt: f64);
    /// The prediction `x~` of the step begun last.
    fn predicted(&self) -> &[Vector<D>];
    /// The weight `w` on the potential energy in the incremental potential
    /// of the step begun last.
    fn potential_weight(&self, dt: f64) -> f64;
    /// Ends the step begun last: `x_new` is the minimiser; overwrites
    /// `velocities` with `v_{n+1}` and updates the scheme's history.
    fn end_step(&mut self, x_new: &[Vector<D>], velocities: &mut [Vector<D>], dt: f64);
    /// A copy of the scheme with its history, so a step can be taken back
    /// and retried (as shorter steps).
    fn boxed_clone(&self) -> Box<dyn TimeIntegrator<D>>;
    /// Whether the scheme does not dissipate and can gain energy where a
    /// step is stiff (Newmark at an impact): the stepper then checks each
    /// step's total energy and takes a step that gained energy again, damped
    /// ([`Self::damp_next_step`]). Dissipative schemes say no (default).
    fn guards_energy(&self) -> bool {
        false
    }
    /// Makes the next step (begun by [`Self::begin_step`]) a dissipative one,
    /// for a scheme that [`guards_energy`](Self::guards_energy).
    fn damp_next_step(&mut self) {}
}

/// The schemes a scene can choose (`time.integrator`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum IntegratorKind {
    /// `backward-euler`: first order, dissipative (default).
    #[default]
    BackwardEuler,
    /// `bdf2`: second order, damps resolved motion far less than backward Euler; first step by backward Euler.
    Bdf2,
    /// `newmark`: implicit Newmark (trapezoidal rule), second order, no numerical damping.
    Newmark,
}

impl IntegratorKind {
    /// Every scheme, in the order docs/scene-reference.md lists them.
    pub const ALL: [IntegratorKind; 3] = [
        IntegratorKind::BackwardEuler,
        IntegratorKind::Bdf2,
        IntegratorKind::Newmark,
    ];

    /// The scene-file name.
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::BackwardEuler => "backward-euler",
            IntegratorKind::Bdf2 => "bdf2",
            IntegratorKind::Newmark => "newmark",
        }
    }

    /// A fresh integrator of this kind for `vertex_count` vertices.
    pub fn build<const D: usize>(self, vertex_count: usize) -> Box<dyn TimeIntegrator<D>> {
        match self {
            IntegratorKind::BackwardEuler => Box::new(BackwardEuler::new(vertex_count)),
            IntegratorKind::Bdf2 => Box::new(Bdf2::new(vertex_count)),
            IntegratorKind::Newmark => Box::new(Newmark::new(vertex_count)),
        }
    }
}
