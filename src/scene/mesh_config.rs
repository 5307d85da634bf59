//! A body's mesh settings, validated: a generated box or a mesh file read
//! once by the validator (kept with its recorded size and checksum).

use crate::math::Vector;
use crate::mesh::{Mesh, MeshError};
use crate::mesh_io::{ImportOptions, ImportReport, MeshFileFingerprint};
use crate::sim::PinRegion;
use std::path::PathBuf;
use std::sync::Arc;

/// The box generator's parameters (`[mesh]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoxMesh<const D: usize> {
    /// Extents per axis, in length units (required in a scene file; `Default`: 1 per axis).
    pub size: Vector<D>,
    /// Cells per axis; a cell is 2 triangles in 2D, 6 tetrahedra in 3D
    /// (required in a scene file; `Default`: 1 per axis).
    pub cells: [usize; D],
    /// Position of the lowest corner, in length units (default: the origin).
    pub offset: Vector<D>,
}

impl<const D: usize> Default for BoxMesh<D> {
    fn default() -> Self {
        Self {
            size: Vector::<D>::repeat(1.0),
            cells: [1; D],
            offset: Vector::<D>::zeros(),
        }
    }
}

impl<const D: usize> BoxMesh<D> {
    /// Builds the mesh.
    pub fn build(&self) -> Result<Mesh<D>, MeshError> {
        Mesh::axis_aligned_box(self.offset, self.offset + self.size, self.cells)
    }

    /// Number of vertices the mesh will have.
    pub fn vertex_count(&self) -> usize {
        self.cells.iter().map(|c| c + 1).product()
    }

    /// Number of simplices the mesh will have.
    pub fn element_count(&self) -> usize {
        self.cells.iter().product::<usize>() * (1..=D).product::<usize>()
    }

    /// The vertex coordinates along `axis`, computed exactly as the mesh generator does.
    pub(crate) fn axis_coordinates(&self, axis: usize) -> impl Iterator<Item = f64> + '_ {
        let (min, max) = (self.offset[axis], self.offset[axis] + self.size[axis]);
        let cells = self.cells[axis];
        (0..=cells).map(move |i| min + (max - min) * i as f64 / cells as f64)
    }
}

/// A mesh read from a file (`generator = "file"`): read, placed and cleaned
/// when the scene is validated, so that counts and errors are known before
/// any work starts.
#[derive(Debug, Clone)]
pub struct FileMesh<const D: usize> {
    /// The file, resolved against the scene file's folder (a built-in
    /// scene's against `scenes/`).
    pub path: PathBuf,
    /// Placement and cleaning (`mesh.scale`, `mesh.rotate`, `mesh.translate`,
    /// `mesh.orient`, `mesh.merge_tolerance`).
    pub options: ImportOptions<D>,
    /// The cleaned mesh.
    pub mesh: Arc<Mesh<D>>,
    /// What the import ignored, re-oriented, dropped and merged.
    pub report: ImportReport,
    /// The file's size and checksum as it was read.
    pub fingerprint: MeshFileFingerprint,
    /// The size and checksum the scene recorded (`mesh.file_size`,
    /// `mesh.file_checksum`, as a run's `scene.toml` holds them), if any.
    pub recorded: RecordedFile,
}

/// A mesh file's size and checksum as a scene recorded them.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RecordedFile {
    /// `mesh.file_size`.
    pub size: Option<u64>,
    /// `mesh.file_checksum`.
    pub checksum: Option<String>,
}

impl<const D: usize> FileMesh<D> {
    /// Why the file differs from what the scene recorded, if it does.
    pub fn change(&self) -> Option<String> {
        let size_changed = self
            .recorded
            .size
            .is_some_and(|s| s != self.fingerprint.size);
        let sum_changed = self
            .recorded
            .checksum
            .as_ref()
            .is_some_and(|c| !c.eq_ignore_ascii_case(&self.fingerprint.checksum));
        if !size_changed && !sum_changed {
            return None;
        }
        let then = [
            self.recorded.size.map(|s| format!("{s} bytes")),
            self.recorded.checksum.clone(),
        ]
        .into_iter()
        .flatten()
        .collect::<Vec<_>>()
        .join(", ");
        Some(format!(
            "{} has changed since this scene was written ({then} then, {} bytes, {} now): the run \
             will not reproduce the one that recorded it",
            self.path.display(),
            self.fingerprint.size,
            self.fingerprint.checksum
        ))
    }
}

impl<const D: usize> PartialEq for FileMesh<D> {
    /// Same file, options and report (the mesh follows from them).
    fn eq(&self, other: &Self) -> bool {
        self.path == other.path && self.options == other.options && self.report == other.report
    }
}

/// A body's rest mesh: generated or read from a file (`[mesh]`).
#[derive(Debug, Clone, PartialEq)]
pub enum MeshConfig<const D: usize> {
    /// `generator = "box"` (the default).
    Box(BoxMesh<D>),
    /// `generator = "file"` (boxed: it is much larger than a box's parameters).
    File(Box<FileMesh<D>>),
}

impl<const D: usize> Default for MeshConfig<D> {
    fn default() -> Self {
        MeshConfig::Box(BoxMesh::default())
    }
}

impl<const D: usize> MeshConfig<D> {
    /// Builds (or hands out a copy of the imported) mesh.
    pub fn build(&self) -> Result<Mesh<D>, MeshError> {
        match self {
            MeshConfig::Box(b) => b.build(),
            MeshConfig::File(f) => Ok(Mesh::clone(&f.mesh)),
        }
    }

    /// Number of vertices the mesh has.
    pub fn vertex_count(&self) -> usize {
        match self {
            MeshConfig::Box(b) => b.vertex_count(),
            MeshConfig::File(f) => f.mesh.vertex_count(),
        }
    }

    /// Number of simplices the mesh has.
    pub fn element_count(&self) -> usize {
        match self {
            MeshConfig::Box(b) => b.element_count(),
            MeshConfig::File(f) => f.mesh.element_count(),
        }
    }

    /// Whether some vertex lies in `region` (inclusive) at rest, and whether
    /// every vertex does. A box's grid is a tensor product, so some vertex
    /// is caught exactly when every axis has a grid coordinate inside.
    pub fn vertices_in(&self, region: &PinRegion<D>) -> (bool, bool) {
        let (min, max) = (region.min, region.max);
        match self {
            MeshConfig::Box(mesh) => (
                (0..D).all(|a| mesh.axis_coordinates(a).any(|x| min[a] <= x && x <= max[a])),
                (0..D).all(|a| mesh.axis_coordinates(a).all(|x| min[a] <= x && x <= max[a])),
            ),
            MeshConfig::File(f) => {
                let inside = |x: &Vector<D>| (0..D).all(|a| min[a] <= x[a] && x[a] <= max[a]);
                let positions = f.mesh.rest_positions();
                (positions.iter().any(inside), positions.iter().all(inside))
            }
        }
    }

    /// The lowest rest coordinate of the mesh along `axis`.
    pub fn lowest(&self, axis: usize) -> f64 {
        match self {
            MeshConfig::Box(b) => b.offset[axis],
            MeshConfig::File(f) => f
                .mesh
                .rest_positions()
                .iter()
                .map(|x| x[axis])
                .fold(f64::INFINITY, f64::min),
        }
    }

    /// The box generator's parameters, for a box.
    pub fn as_box(&self) -> Option<&BoxMesh<D>> {
        match self {
            MeshConfig::Box(b) => Some(b),
            MeshConfig::File(_) => None,
        }
    }

    /// The import report, for a mesh file.
    pub fn import_report(&self) -> Option<&ImportReport> {
        match self {
            MeshConfig::Box(_) => None,
            MeshConfig::File(f) => Some(&f.report),
        }
    }
}
