//! An obstacle of a scene: a surface that takes part in contact but is not an unknown, held still or moved along a prescribed rigid path.
//!
//! An obstacle's vertices join the simulation's position array after the
//! bodies' vertices. They carry no mass, no elasticity and no gravity, and
//! the ground ignores them. Each is pinned to its obstacle's rigid path
//! (the same [`PinMotion`] as a pinned region,
//! `x(t) = c + R(w tau)(X - c) + v tau`), so a moving obstacle is placed
//! exactly like a moving pinned
//! region: before the solve where the line search's CCD allows the whole
//! move, otherwise part of the way and pulled the rest within the solve by
//! the augmented Lagrangian (`energy::PrescribedMotion`). Its boundary is
//! part of the collision mesh; pairs of two obstacle primitives are never
//! contact candidates (obstacles do not collide with each other).
//!
//! The geometry is a surface ([`SurfaceMesh`]): a box's boundary, the
//! boundary of a volume mesh read from a file, or a surface file (OBJ, PLY;
//! a polyline in 2D), closed or open.

use super::PinMotion;
use crate::mesh::SurfaceMesh;
use std::sync::Arc;

/// A scene's obstacle.
#[derive(Debug, Clone)]
pub struct Obstacle<const D: usize> {
    /// The obstacle's surface at rest, in scene coordinates.
    pub surface: Arc<SurfaceMesh<D>>,
    /// In 2D, triangles over the surface's points that fill it in frames
    /// (a box's or a 2D mesh's; empty for a polyline and in 3D). Drawing
    /// only: contact sees the surface.
    pub fill: Vec<[usize; 3]>,
    /// Its rigid path (default: holds still).
    pub motion: PinMotion<D>,
    /// The friction coefficient of contact with this obstacle (`None`: the
    /// contact's, `[effects.contact] friction`).
    pub friction: Option<f64>,
}

impl<const D: usize> PartialEq for Obstacle<D> {
    /// The same geometry, path and friction.
    fn eq(&self, other: &Self) -> bool {
        self.surface == other.surface
            && self.fill == other.fill
            && self.motion == other.motion
            && self.friction == other.friction
    }
}
