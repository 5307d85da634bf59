//! The effects a scene asks for; an absent effect does not exist in the simulation.

use super::{Obstacle, PinRegion};
use crate::math::Vector;

/// A flat ground `x[UP_AXIS] = height` with the report's log barrier.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ground {
    /// Height of the plane along the up axis (y), in length units (default: 0).
    pub height: f64,
    /// Barrier activation distance `a`: the barrier acts for gaps in (0, a), in length units (default: 0.1).
    pub activation_distance: f64,
    /// Barrier stiffness `kappa`, in energy per length^2; `None` picks it by the
    /// default rule documented in [`crate::energy::GroundBarrier::default_stiffness`].
    pub stiffness: Option<f64>,
    /// The coefficient of friction `mu` against the ground (default 0: none;
    /// [`crate::energy::Friction`]).
    pub friction: f64,
}

/// Contact between and within bodies (`[effects.contact]`), the IPC way.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// The activation distance `d_hat`, in length units; `None` for the
    /// default, `1e-3` times the diagonal of the bodies' bounding box at the start.
    pub distance: Option<f64>,
    /// A fixed barrier stiffness `kappa` (energy per length^4); `None` for
    /// IPC's adaptive rule ([`crate::energy::ContactBarrier`]).
    pub stiffness: Option<f64>,
    /// Whether parts of one body collide with each other (default: true).
    pub self_contact: bool,
    /// The coefficient of friction `mu` between and within bodies (default
    /// 0: none; [`crate::energy::Friction`]).
    pub friction: f64,
}

impl Default for Contact {
    fn default() -> Self {
        Self {
            distance: None,
            stiffness: None,
            self_contact: true,
            friction: 0.0,
        }
    }
}

/// The set of effects acting on the body besides inertia and elasticity.
#[derive(Debug, Clone, PartialEq)]
pub struct Effects<const D: usize> {
    /// Gravitational acceleration, in length/s^2; `None` means no gravity term.
    pub gravity: Option<Vector<D>>,
    /// Ground contact; `None` means no barrier term and no contact checks.
    pub ground: Option<Ground>,
    /// Contact between and within bodies; `None` means bodies pass through
    /// each other and themselves, and pay nothing for it.
    pub contact: Option<Contact>,
    /// Pinned regions (`[[effects.pinned]]`), each with its path; empty
    /// means every vertex is free. A vertex in several regions follows the
    /// first.
    pub pinned: Vec<PinRegion<D>>,
    /// Obstacles (`[[obstacles]]`): surfaces bodies collide with, held
    /// still or moved along a rigid path; they need `contact` (default: none).
    pub obstacles: Vec<Obstacle<D>>,
}

impl<const D: usize> Default for Effects<D> {
    fn default() -> Self {
        Self {
            gravity: None,
            ground: None,
            contact: None,
            pinned: Vec::new(),
            obstacles: Vec::new(),
        }
    }
}
