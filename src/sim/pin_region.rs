//! A pinned region and its prescribed rigid path: `x(t) = c + R(w tau)(X - c) + v tau`, `tau = min(t, until)`.
//!
//! Every vertex inside the box `min..max` at rest (`X`) is held exactly: it is
//! not an unknown of the solve, and at the start of each step its position is
//! set to the region's path at the step's end time `t`:
//!
//! ```text
//! x(t) = c + R(w tau) (X - c) + v tau,        tau = min(t, until)
//! v(t) = w k x (R(w tau) (X - c)) + v         while t < until, else 0
//! ```
//!
//! where `v` is the translation velocity, `w` the angular velocity (rad/s),
//! `k` the unit rotation axis (3D; in 2D the rotation is in the plane,
//! counter-clockwise for `w > 0`, and `k x r = (-r_y, r_x)`), and `c` the
//! centre of rotation at rest. The path is evaluated from the rest position
//! and the time alone, never accumulated step by step, so a pinned vertex is
//! on its path to round-off however long the run, and after `until` it
//! stands still where the path left it. `R(0)` is the identity exactly
//! (`cos 0 = 1`, `sin 0 = 0`), so a region that does not move holds its
//! vertices at their rest positions bit for bit.
//!
//! Rotations are the one place in the simulation that names the dimension:
//! a rotation in 2D has an angle, in 3D an axis and an angle (Rodrigues'
//! formula `R r = r cos a + (k x r) sin a + k (k . r)(1 - cos a)`).

use crate::math::{Vector, Vector3};

/// How a pinned region moves: a rigid motion (translation plus rotation about
/// a centre), stopping at `until`. [`PinMotion::default`] holds still.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PinMotion<const D: usize> {
    /// Translation velocity `v`, in length/s (default: zero).
    pub velocity: Vector<D>,
    /// Angular velocity `w`, in rad/s (default: 0).
    pub angular_velocity: f64,
    /// Unit rotation axis `k` (3D only; ignored in 2D, where rotation is in
    /// the plane) (default: z).
    pub axis: Vector3,
    /// Centre of rotation `c` at rest, in length units (default: origin;
    /// the scene layer defaults it to the centre of the box).
    pub center: Vector<D>,
    /// Time after which the region stands still, in s (default: `None`,
    /// never).
    pub until: Option<f64>,
    /// Time at which the region lets go: from the first step that starts at
    /// or after it, its vertices are free unknowns, starting from where the
    /// path left them with the path's velocity (`None`: held for the whole run).
    pub release: Option<f64>,
}

impl<const D: usize> Default for PinMotion<D> {
    fn default() -> Self {
        Self {
            velocity: Vector::<D>::zeros(),
            angular_velocity: 0.0,
            axis: Vector3::z(),
            center: Vector::<D>::zeros(),
            until: None,
            release: None,
        }
    }
}

impl<const D: usize> PinMotion<D> {
    /// Whether the motion moves anything at all (some velocity or rotation).
    pub fn is_moving(&self) -> bool {
        self.angular_velocity != 0.0 || self.velocity.iter().any(|v| *v != 0.0)
    }

    /// Whether the region is moving at time `t` (moving, and `t < until`).
    pub fn is_moving_at(&self, t: f64) -> bool {
        self.is_moving() && self.until.is_none_or(|u| t < u)
    }

    /// The elapsed time of the path at `t`: `min(t, until)`.
    fn path_time(&self, t: f64) -> f64 {
        self.until.map_or(t, |u| t.min(u))
    }

    /// `x(t)` of the vertex at rest position `rest`.
    pub fn position(&self, rest: &Vector<D>, t: f64) -> Vector<D> {
        let tau = self.path_time(t);
        let arm = rotate(
            &self.axis,
            self.angular_velocity * tau,
            &(rest - self.center),
        );
        self.center + arm + self.velocity * tau
    }

    /// `dx/dt` at `t` of the vertex at rest position `rest` (zero once stopped).
    pub fn velocity_of(&self, rest: &Vector<D>, t: f64) -> Vector<D> {
        if !self.is_moving_at(t) {
            return Vector::<D>::zeros();
        }
        let tau = self.path_time(t);
        let arm = rotate(
            &self.axis,
            self.angular_velocity * tau,
            &(rest - self.center),
        );
        cross_axis(&self.axis, &arm) * self.angular_velocity + self.velocity
    }
}

/// `R(angle) r`: in the plane (2D), or about the unit `axis` (3D).
pub fn rotate<const D: usize>(axis: &Vector3, angle: f64, r: &Vector<D>) -> Vector<D> {
    let (s, c) = angle.sin_cos();
    let mut out = *r;
    match D {
        2 => {
            out[0] = c * r[0] - s * r[1];
            out[1] = s * r[0] + c * r[1];
        }
        3 => {
            let r3 = Vector3::new(r[0], r[1], r[2]);
            let rotated = r3 * c + axis.cross(&r3) * s + axis * (axis.dot(&r3) * (1.0 - c));
            out.copy_from_slice(rotated.as_slice());
        }
        _ => unreachable!("elasto simulates 2D and 3D only"),
    }
    out
}

/// `k x r`: in the plane `(-r_y, r_x)` (2D), or with the unit `axis` (3D).
fn cross_axis<const D: usize>(axis: &Vector3, r: &Vector<D>) -> Vector<D> {
    let mut out = Vector::<D>::zeros();
    match D {
        2 => {
            out[0] = -r[1];
            out[1] = r[0];
        }
        3 => {
            let c = axis.cross(&Vector3::new(r[0], r[1], r[2]));
            out.copy_from_slice(c.as_slice());
        }
        _ => unreachable!("elasto simulates 2D and 3D only"),
    }
    out
}

/// An axis-aligned box: every vertex inside it at rest is pinned (held
/// exactly on the box's [`PinMotion`] path; Dirichlet).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PinRegion<const D: usize> {
    /// Lower corner.
    pub min: Vector<D>,
    /// Upper corner.
    pub max: Vector<D>,
    /// How the held vertices move (default: they hold still).
    pub motion: PinMotion<D>,
}

impl<const D: usize> PinRegion<D> {
    /// A region `min..max` that holds its vertices still at rest.
    pub fn new(min: Vector<D>, max: Vector<D>) -> Self {
        Self {
            min,
            max,
            motion: PinMotion::default(),
        }
    }

    /// The same region moving along `motion`.
    pub fn moving(self, motion: PinMotion<D>) -> Self {
        Self { motion, ..self }
    }

    /// Whether `x` lies in the box (inclusive).
    pub fn contains(&self, x: &Vector<D>) -> bool {
        (0..D).all(|k| x[k] >= self.min[k] && x[k] <= self.max[k])
    }

    /// The centre of the box, `(min + max) / 2`.
    pub fn box_center(&self) -> Vector<D> {
        (self.min + self.max) * 0.5
    }
}
