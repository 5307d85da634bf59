//! One body of a scene: its rest mesh, material, density, initial velocity and pinned region.

use super::PinRegion;
use crate::material::Material;
use crate::math::Vector;
use crate::mesh::Mesh;

/// A body of a simulation. Bodies share gravity, the ground and the
/// contact between and within them (`[effects.contact]`).
#[derive(Debug, Clone)]
pub struct Body<const D: usize> {
    /// The rest mesh, in scene coordinates, with its own vertex numbering.
    pub mesh: Mesh<D>,
    /// Its material.
    pub material: Material,
    /// Mass per unit rest volume (area in 2D), in mass/length^3.
    pub density: f64,
    /// Initial velocity of every free vertex, in length/s.
    pub velocity: Vector<D>,
    /// Its vertices inside this box at rest are pinned (default: none).
    pub pinned: Option<PinRegion<D>>,
}
