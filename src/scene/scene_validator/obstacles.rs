//! `[[obstacles]]`: each obstacle's mesh, friction and rigid path.
//!
//! An obstacle's `mesh` table is a body's (`generator = "box"` or
//! `"file"`, the same messages for a file that cannot be read), but a box
//! takes `scale`, `rotate` and `translate` too (applied to the generated
//! box, a ramp is a rotated box) and its `cells` default to 1 per axis;
//! a file may be a surface (`.obj`, `.ply`) besides a volume mesh (whose
//! boundary is used); it has no `velocity` (an obstacle moves along its
//! path).

use super::{SceneValidator, VResult};
use crate::math::Vector;
use crate::mesh::{Mesh, SurfaceMesh};
use crate::mesh_io::{ImportOptions, load_surface};
use crate::scene::raw_scene::{Generator, RawMesh, RawObstacle, RawPinned};
use crate::scene::scene_config::MeshConfig;
use crate::sim::{Effects, Obstacle};
use std::sync::Arc;

impl SceneValidator<'_, '_> {
    /// The obstacles (`[[obstacles]]`): each a mesh (`mesh`, as a body's,
    /// `cells` defaulting to 1 per axis for a box; its boundary collides),
    /// an optional `friction` and a rigid path (the motion keys of
    /// `[[effects.pinned]]` but `release`, centred by default on the mesh's
    /// bounding box). They need `[effects.contact]`.
    #[allow(clippy::type_complexity)]
    pub(super) fn obstacles<const D: usize>(
        &self,
        raw: Option<&[RawObstacle]>,
        effects: &Effects<D>,
    ) -> VResult<(Vec<Obstacle<D>>, Option<Vec<RawObstacle>>)> {
        let Some(list) = raw else {
            return Ok((Vec::new(), None));
        };
        if list.is_empty() {
            return Ok((Vec::new(), None));
        }
        if effects.contact.is_none() {
            return Err(self.err(
                "obstacles",
                "take part in contact: add [effects.contact] (its `distance` is the gap \
                 bodies keep from an obstacle)",
            ));
        }
        let mut obstacles = Vec::with_capacity(list.len());
        let mut resolved = Vec::with_capacity(list.len());
        for (i, entry) in list.iter().enumerate() {
            let v = self.under(format!("obstacles[{i}]."));
            if entry.mesh.velocity.is_some() {
                return Err(v.err(
                    "mesh.velocity",
                    "is a body's initial velocity: an obstacle moves along its path, \
                     given by `velocity` (and `angular_velocity`) beside `mesh`",
                ));
            }
            let (surface, fill, raw_mesh) = v.obstacle_surface::<D>(&entry.mesh)?;
            let friction = match entry.friction {
                Some(mu) => Some(v.friction_coefficient("friction", Some(mu))?),
                None => None,
            };
            let motion_keys = RawPinned {
                min: Vec::new(),
                max: Vec::new(),
                velocity: entry.velocity.clone(),
                angular_velocity: entry.angular_velocity,
                axis: entry.axis.clone(),
                center: entry.center.clone(),
                until: entry.until,
                release: None,
            };
            let motion = v.motion::<D>("", &motion_keys, box_center(surface.points()))?;
            resolved.push(RawObstacle {
                mesh: raw_mesh,
                friction,
                center: motion
                    .is_moving()
                    .then(|| motion.center.iter().copied().collect()),
                ..entry.clone()
            });
            obstacles.push(Obstacle {
                surface,
                fill,
                motion,
                friction,
            });
        }
        Ok((obstacles, Some(resolved)))
    }

    /// An obstacle's surface at rest, its fill (2D: the triangles of a box
    /// or a 2D mesh) and its resolved table.
    fn obstacle_surface<const D: usize>(&self, raw: &RawMesh) -> VResult<ObstacleShape<D>> {
        if raw.velocity.is_some() {
            return Err(self.err(
                "mesh.velocity",
                "is a body's initial velocity: an obstacle moves along its path, given by \
                 `velocity` (and `angular_velocity`) beside `mesh`",
            ));
        }
        if raw.generator.unwrap_or_default() == Generator::File {
            return self.obstacle_file::<D>(raw);
        }
        let (scale, rotate, translate) = self.placement::<D>(raw)?;
        let unplaced = RawMesh {
            cells: raw.cells.clone().or_else(|| Some(vec![1; D])),
            scale: None,
            rotate: None,
            translate: None,
            ..raw.clone()
        };
        let (mesh, _, resolved) = self.mesh::<D>(&unplaced)?;
        let MeshConfig::Box(generated) = mesh else {
            unreachable!("generator = \"box\" gives a box")
        };
        let generated = generated
            .build()
            .map_err(|e| self.err("mesh", format!("cannot be meshed: {e}")))?;
        let placement = ImportOptions {
            scale,
            rotate,
            translate,
            ..ImportOptions::default()
        };
        let surface = SurfaceMesh::boundary_of(&generated).mapped(|x| placement.place(x));
        let fill = fill_of(&generated);
        let resolved = RawMesh {
            velocity: None,
            scale: Some(scale),
            rotate: raw.rotate.clone(),
            translate: Some(translate.iter().copied().collect()),
            ..resolved
        };
        Ok((Arc::new(surface), fill, resolved))
    }

    /// An obstacle read from a file: a surface (`.obj`, `.ply`) placed by
    /// the mesh transforms, or a volume mesh's boundary (read as a body's).
    fn obstacle_file<const D: usize>(&self, raw: &RawMesh) -> VResult<ObstacleShape<D>> {
        let is_surface_file = raw.path.as_deref().is_some_and(|p| {
            let lower = p.to_ascii_lowercase();
            lower.ends_with(".obj") || lower.ends_with(".ply")
        });
        if !is_surface_file {
            let (mesh, _, mut resolved) = self.mesh::<D>(raw)?;
            resolved.velocity = None;
            let MeshConfig::File(file) = mesh else {
                unreachable!("generator = \"file\" gives a file mesh")
            };
            let surface = SurfaceMesh::boundary_of(&file.mesh);
            return Ok((Arc::new(surface), fill_of(&file.mesh), resolved));
        }
        for key in ["size", "cells", "offset", "orient", "merge_tolerance"] {
            let given = match key {
                "size" => raw.size.is_some(),
                "cells" => raw.cells.is_some(),
                "offset" => raw.offset.is_some(),
                "orient" => raw.orient.is_some(),
                _ => raw.merge_tolerance.is_some(),
            };
            if given {
                return Err(self.err(
                    &format!("mesh.{key}"),
                    "is not used for a surface file (.obj, .ply): it applies to \
                     generated boxes or volume meshes",
                ));
            }
        }
        let (file, resolved) = self.read_mesh_file::<D, _>(raw, false, load_surface::<D>)?;
        Ok((Arc::new(file.content.surface), Vec::new(), resolved))
    }
}

/// An obstacle's surface, its fill and its resolved `mesh` table.
type ObstacleShape<const D: usize> = (Arc<SurfaceMesh<D>>, Vec<[usize; 3]>, RawMesh);

/// The triangles that fill a 2D mesh in frames (none in 3D).
fn fill_of<const D: usize>(mesh: &Mesh<D>) -> Vec<[usize; 3]> {
    if D != 2 {
        return Vec::new();
    }
    mesh.simplices().map(|s| [s[0], s[1], s[2]]).collect()
}

/// The centre of the box around `points`.
fn box_center<const D: usize>(points: &[Vector<D>]) -> Vector<D> {
    let (low, high) = points.iter().fold(
        (
            Vector::<D>::repeat(f64::INFINITY),
            Vector::<D>::repeat(f64::NEG_INFINITY),
        ),
        |(low, high), x| (low.inf(x), high.sup(x)),
    );
    (low + high) / 2.0
}
