//! A body's `mesh` table: a generated box or a mesh file (read once, here, with
//! its fingerprint recorded), its placement (`scale`, `rotate`, `translate`),
//! and the checks on its cells and mass. Every mesh file of a scene, a
//! body's or an obstacle's, is read by [`SceneValidator::read_mesh_file`].

use super::{SceneValidator, VResult};
use crate::math::Vector;
use crate::mesh_io::{
    ImportOptions, MeshFileFingerprint, MeshImportError, load_mesh, mesh_file_fingerprint,
};
use crate::scene::raw_scene::{Generator, RawMesh, RawRotate};
use crate::scene::scene_config::{BoxMesh, FileMesh, MAX_CELLS, MeshConfig, RecordedFile};
use crate::scene::scene_error::{num, nums};
use std::path::{Path, PathBuf};

impl SceneValidator<'_, '_> {
    /// A body's mesh (`generator = "box"` or `"file"`), its initial velocity
    /// and the resolved table.
    pub(super) fn mesh<const D: usize>(
        &self,
        raw: &RawMesh,
    ) -> VResult<(MeshConfig<D>, Vector<D>, RawMesh)> {
        let generator = raw.generator.unwrap_or_default();
        let (used, other, hint) = match generator {
            Generator::Box => (
                "box",
                [
                    ("path", raw.path.is_some()),
                    ("scale", raw.scale.is_some()),
                    ("rotate", raw.rotate.is_some()),
                    ("translate", raw.translate.is_some()),
                    ("orient", raw.orient.is_some()),
                    ("merge_tolerance", raw.merge_tolerance.is_some()),
                    ("file_size", raw.file_size.is_some()),
                    ("file_checksum", raw.file_checksum.is_some()),
                ]
                .to_vec(),
                "file",
            ),
            Generator::File => (
                "file",
                [
                    ("size", raw.size.is_some()),
                    ("cells", raw.cells.is_some()),
                    ("offset", raw.offset.is_some()),
                ]
                .to_vec(),
                "box",
            ),
        };
        if let Some((key, _)) = other.iter().find(|(_, present)| *present) {
            return Err(self.err(
                &format!("mesh.{key}"),
                format!(
                    "is only used with generator = \"{hint}\" (this mesh is generator = \"{used}\")"
                ),
            ));
        }
        match generator {
            Generator::Box => self
                .box_mesh::<D>(raw)
                .map(|(b, v, r)| (MeshConfig::Box(b), v, r)),
            Generator::File => self
                .file_mesh::<D>(raw)
                .map(|(f, v, r)| (MeshConfig::File(Box::new(f)), v, r)),
        }
    }

    /// Where a relative mesh path points: beside the scene file, or under
    /// `scenes/` of this source tree for a built-in scene.
    pub(super) fn mesh_folder(&self) -> PathBuf {
        match &self.doc.source().path {
            Some(file) => file.parent().map(Path::to_owned).unwrap_or_default(),
            None => Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes"),
        }
    }

    /// A body's mesh file: read once here (the simulation trusts it), placed,
    /// its size and checksum recorded.
    pub(super) fn file_mesh<const D: usize>(
        &self,
        raw: &RawMesh,
    ) -> VResult<(FileMesh<D>, Vector<D>, RawMesh)> {
        let velocity = match &raw.velocity {
            Some(v) => self.vector::<D>("mesh.velocity", v)?,
            None => Vector::<D>::zeros(),
        };
        let (file, mut resolved) = self.read_mesh_file::<D, _>(raw, true, load_mesh::<D>)?;
        let (mesh, report) = file.content;
        let coordinates: Vec<f64> = mesh
            .rest_positions()
            .iter()
            .flat_map(|x| x.iter().copied().collect::<Vec<_>>())
            .collect();
        self.single_precision("mesh.translate", &coordinates, false)?;
        resolved.velocity = Some(velocity.iter().copied().collect());
        Ok((
            FileMesh {
                path: file.path,
                options: file.options,
                mesh: std::sync::Arc::new(mesh),
                report,
                fingerprint: file.fingerprint,
                recorded: file.recorded,
            },
            velocity,
            resolved,
        ))
    }

    /// The one place a mesh file is read, a body's volume mesh or an
    /// obstacle's surface alike: `mesh.path` resolved against the scene's
    /// folder, the placement (`scale`, `rotate`, `translate`, and with
    /// `cleaned` the volume mesh's `orient` and `merge_tolerance`), the
    /// file read by `read`, its size and checksum taken and the recorded ones
    /// checked for form. Returns the resolved `mesh` table (path made
    /// absolute, the fingerprint recorded; no `velocity`).
    pub(super) fn read_mesh_file<const D: usize, T>(
        &self,
        raw: &RawMesh,
        cleaned: bool,
        read: impl FnOnce(&Path, &ImportOptions<D>) -> Result<T, MeshImportError>,
    ) -> VResult<(MeshFile<D, T>, RawMesh)> {
        let given = raw
            .path
            .as_deref()
            .ok_or_else(|| self.err("mesh.path", "is required with generator = \"file\""))?;
        if given.trim().is_empty() {
            return Err(self.err("mesh.path", "must not be empty"));
        }
        let path = self.mesh_folder().join(given);
        let path = std::path::absolute(&path).unwrap_or(path);
        let (scale, rotate, translate) = self.placement::<D>(raw)?;
        let merge_tolerance = raw.merge_tolerance.unwrap_or(0.0);
        if !(merge_tolerance.is_finite() && merge_tolerance >= 0.0) {
            return Err(self.err(
                "mesh.merge_tolerance",
                format!("must be a finite number >= 0, got {}", num(merge_tolerance)),
            ));
        }
        let orient = raw.orient.unwrap_or(true);
        let options = ImportOptions {
            orient,
            merge_tolerance,
            scale,
            rotate,
            translate,
        };
        let recorded = RecordedFile {
            size: match raw.file_size {
                Some(size) => Some(u64::try_from(size).map_err(|_| {
                    self.err(
                        "mesh.file_size",
                        format!("must be a whole number of bytes >= 0, got {size}"),
                    )
                })?),
                None => None,
            },
            checksum: match &raw.file_checksum {
                Some(sum) if MeshFileFingerprint::is_checksum(sum) => Some(sum.clone()),
                Some(sum) => {
                    return Err(self.err(
                        "mesh.file_checksum",
                        format!(
                            "must be `xxh3:` and 16 hexadecimal digits, as a run's scene.toml \
                             records it, got {sum:?}"
                        ),
                    ));
                }
                None => None,
            },
        };
        let content = read(&path, &options)
            .map_err(|e| self.err("mesh.path", format!("cannot be imported: {e}")))?;
        let fingerprint = mesh_file_fingerprint(&path)
            .map_err(|e| self.err("mesh.path", format!("cannot be read: {e}")))?;
        let resolved = RawMesh {
            generator: Some(Generator::File),
            size: None,
            cells: None,
            offset: None,
            velocity: None,
            path: Some(path.display().to_string()),
            scale: Some(scale),
            rotate: Some(if D == 2 {
                RawRotate::Angle(rotate[2])
            } else {
                RawRotate::Angles(rotate.to_vec())
            }),
            translate: Some(translate.iter().copied().collect()),
            orient: cleaned.then_some(orient),
            merge_tolerance: cleaned.then_some(merge_tolerance),
            file_size: i64::try_from(fingerprint.size).ok(),
            file_checksum: Some(fingerprint.checksum.clone()),
        };
        Ok((
            MeshFile {
                path,
                options,
                content,
                fingerprint,
                recorded,
            },
            resolved,
        ))
    }

    /// `mesh.scale`, `mesh.rotate` (one angle in 2D, three in 3D, degrees)
    /// and `mesh.translate` (defaults 1, none, none).
    pub(super) fn placement<const D: usize>(
        &self,
        raw: &RawMesh,
    ) -> VResult<(f64, [f64; 3], Vector<D>)> {
        let scale = self.positive("mesh.scale", raw.scale.unwrap_or(1.0))?;
        let rotate = match (&raw.rotate, D) {
            (None, _) => [0.0; 3],
            (Some(RawRotate::Angle(a)), 2) if a.is_finite() => [0.0, 0.0, *a],
            (Some(RawRotate::Angles(v)), 3) if v.len() == 3 && v.iter().all(|a| a.is_finite()) => {
                [v[0], v[1], v[2]]
            }
            (Some(_), 2) => {
                return Err(self.err(
                    "mesh.rotate",
                    "is one finite angle in degrees in 2D (about the axis out of the plane)",
                ));
            }
            (Some(_), _) => {
                return Err(self.err(
                    "mesh.rotate",
                    "is three finite angles in degrees in 3D (about x, then y, then z)",
                ));
            }
        };
        let translate = match &raw.translate {
            Some(v) => self.vector::<D>("mesh.translate", v)?,
            None => Vector::<D>::zeros(),
        };
        Ok((scale, rotate, translate))
    }

    /// A generated box: `size`, `cells`, `offset`, checked against the cell limit.
    pub(super) fn box_mesh<const D: usize>(
        &self,
        raw: &RawMesh,
    ) -> VResult<(BoxMesh<D>, Vector<D>, RawMesh)> {
        let required = |key: &str| {
            self.err(
                key,
                "is required with generator = \"box\" (give `size` and `cells`, or use \
                 generator = \"file\" with `path`)",
            )
        };
        let raw_size = raw.size.as_ref().ok_or_else(|| required("mesh.size"))?;
        let raw_cells = raw.cells.as_ref().ok_or_else(|| required("mesh.cells"))?;
        let size = self.vector::<D>("mesh.size", raw_size)?;
        if let Some(bad) = size.iter().find(|s| **s <= 0.0) {
            return Err(self.err(
                "mesh.size",
                format!("every extent must be > 0, got {}", num(*bad)),
            ));
        }
        if raw_cells.len() != D {
            return Err(self.err(
                "mesh.cells",
                format!(
                    "needs {D} components (dimension = {D}), got {}",
                    raw_cells.len()
                ),
            ));
        }
        let mut cells = [0usize; D];
        for (c, &n) in cells.iter_mut().zip(raw_cells) {
            *c = self.count("mesh.cells", n, MAX_CELLS)?;
        }
        let total = cells.iter().try_fold(1usize, |acc, &c| acc.checked_mul(c));
        if total.is_none_or(|n| n > MAX_CELLS) {
            return Err(self.err(
                "mesh.cells",
                format!(
                    "{:?} makes {} cells, more than the {MAX_CELLS} allowed",
                    raw_cells,
                    cells.iter().map(|&c| c as f64).product::<f64>()
                ),
            ));
        }
        let offset = match &raw.offset {
            Some(v) => self.vector::<D>("mesh.offset", v)?,
            None => Vector::<D>::zeros(),
        };
        self.box_cells::<D>(&BoxMesh {
            size,
            cells,
            offset,
        })?;
        let velocity = match &raw.velocity {
            Some(v) => self.vector::<D>("mesh.velocity", v)?,
            None => Vector::<D>::zeros(),
        };
        let resolved = RawMesh {
            generator: Some(Generator::Box),
            size: Some(size.iter().copied().collect()),
            cells: Some(raw_cells.clone()),
            offset: Some(offset.iter().copied().collect()),
            velocity: Some(velocity.iter().copied().collect()),
            ..raw.clone()
        };
        Ok((
            BoxMesh {
                size,
                cells,
                offset,
            },
            velocity,
            resolved,
        ))
    }

    /// The box generator must be able to place every cell: the corners fit
    /// the renderer's 32-bit floats, each cell spans a resolvable step of its
    /// coordinates, and its volume is a normal double.
    pub(super) fn box_cells<const D: usize>(&self, mesh: &BoxMesh<D>) -> VResult<()> {
        let upper = mesh.offset + mesh.size;
        for axis in 0..D {
            if !upper[axis].is_finite() {
                return Err(self.err(
                    "mesh.size",
                    format!(
                        "offset + size along axis {axis} overflows: {} + {}",
                        num(mesh.offset[axis]),
                        num(mesh.size[axis])
                    ),
                ));
            }
        }
        self.single_precision("mesh.offset", mesh.offset.as_slice(), false)?;
        self.single_precision("mesh.size", upper.as_slice(), false)?;
        let cell: Vec<f64> = (0..D)
            .map(|a| mesh.size[a] / mesh.cells[a] as f64)
            .collect();
        for axis in 0..D {
            let magnitude = mesh.offset[axis].abs().max(upper[axis].abs());
            if !(cell[axis] >= 1e-9 * magnitude) {
                return Err(self.err(
                    "mesh.size",
                    format!(
                        "cells of {} along axis {axis} are too small to place at {} \
                         (mesh.offset): a cell must span at least 1e-9 of its coordinates \
                         in double precision",
                        num(cell[axis]),
                        num(mesh.offset[axis])
                    ),
                ));
            }
        }
        let volume: f64 = cell.iter().product();
        let diagonal: f64 = cell.iter().map(|h| h * h).sum();
        if !(volume >= f64::MIN_POSITIVE && volume.is_finite() && diagonal.is_finite()) {
            let which = if volume.is_finite() && volume < 1.0 {
                "small: their volume underflows"
            } else {
                "large: their volume overflows"
            };
            return Err(self.err(
                "mesh.size",
                format!(
                    "cells of {} are too {which} double precision; choose other length units",
                    nums(&cell)
                ),
            ));
        }
        Ok(())
    }

    /// Masses are density times element volumes: they must be normal doubles.
    pub(super) fn mass<const D: usize>(&self, mesh: &MeshConfig<D>, density: f64) -> VResult<()> {
        let (element, volume) = match mesh {
            MeshConfig::Box(mesh) => (
                (0..D)
                    .map(|a| mesh.size[a] / mesh.cells[a] as f64)
                    .product::<f64>()
                    / (1..=D + 1).product::<usize>() as f64,
                mesh.size.iter().product::<f64>(),
            ),
            MeshConfig::File(f) => (
                f.mesh
                    .rest_elements()
                    .iter()
                    .map(|e| e.volume)
                    .fold(f64::INFINITY, f64::min),
                f.mesh.rest_volume(),
            ),
        };
        let total = density * volume;
        if !(density * element >= f64::MIN_POSITIVE && total.is_finite()) {
            return Err(self.err(
                "material.density",
                format!(
                    "{} times the mesh's volume gives vertex masses outside double precision \
                     (total mass {})",
                    num(density),
                    num(total)
                ),
            ));
        }
        Ok(())
    }
}

/// A mesh file as [`SceneValidator::read_mesh_file`] read it: where it is,
/// how it was placed, what `read` made of it, and its size and checksum
/// (as read, and as the scene recorded them).
pub(super) struct MeshFile<const D: usize, T> {
    /// The file, absolute.
    pub path: PathBuf,
    /// Its placement and cleaning.
    pub options: ImportOptions<D>,
    /// What was read: a cleaned mesh and its report, or a surface.
    pub content: T,
    /// The size and checksum read.
    pub fingerprint: MeshFileFingerprint,
    /// The size and checksum the scene recorded.
    pub recorded: RecordedFile,
}
