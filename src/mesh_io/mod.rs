//! Mesh files in: gmsh `.msh` (2.2 and 4.1, ASCII and binary), MEDIT `.mesh`,
//! TetGen/Triangle `.node` + `.ele` and VTK `.vtu`, read into an
//! [`ImportedMesh`] and cleaned into a [`Mesh`].
//!
//! Reading ([`read_mesh`]) picks the format by the file's extension (case
//! does not matter) and keeps the simplices of the requested dimension:
//! tetrahedra in 3D, triangles in 2D. Elements of other types (the surface
//! triangles, lines and points gmsh writes along with the tetrahedra,
//! higher-order or non-simplex cells) are counted by type and otherwise
//! ignored; a 2D read refuses tetrahedra and vertices off the plane z = 0.
//! Cleaning ([`clean`]) transforms the vertices, merges duplicates on request,
//! re-orients inverted elements, refuses degenerate ones, drops unreferenced
//! vertices and counts connected pieces (see [`clean`] for the order). [`load_mesh`] does both.
//!
//! | format | extension | read by |
//! | --- | --- | --- |
//! | gmsh MSH 2.2 and 4.1, ASCII and binary | `.msh` | this module (`msh.rs`) |
//! | MEDIT (TetWild, fTetWild, MMG, gmsh) | `.mesh` | this module (`medit.rs`) |
//! | TetGen / Triangle | `.node` + `.ele` | this module (`tetgen.rs`) |
//! | VTK XML unstructured grid | `.vtu` | the `vtkio` crate |
//!
//! Every error names the file and, where it applies, the line (text), byte
//! (binary data), element or vertex, in the file's own numbering.

mod clean;
mod cursor;
mod imported_mesh;
mod medit;
mod mesh_import_error;
mod msh;
mod tetgen;
mod vtu;

pub use clean::{ImportOptions, ImportReport, clean};
pub use imported_mesh::ImportedMesh;
pub use mesh_import_error::{Location, MeshImportError};

use crate::input_file::{MAX_MESH_FILE_BYTES, read_regular_file};
use crate::mesh::Mesh;
use std::path::Path;

/// Reads the mesh file at `path`, keeping triangles (`dimension = 2`) or
/// tetrahedra (`dimension = 3`); the format follows the extension: `.msh`,
/// `.mesh`, `.node` or `.ele` (the other file of the pair is found beside
/// it), `.vtu`.
pub fn read_mesh(path: &Path, dimension: usize) -> Result<ImportedMesh, MeshImportError> {
    if dimension != 2 && dimension != 3 {
        return Err(MeshImportError::InvalidOption {
            key: "dimension",
            reason: format!("must be 2 or 3, got {dimension}"),
        });
    }
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    match extension.as_str() {
        "msh" => msh::read(path, &read_file(path)?, dimension),
        "mesh" => medit::read(path, &read_file(path)?, dimension),
        "node" | "ele" => tetgen::read(path, dimension),
        "vtu" => vtu::read(path, &read_file(path)?, dimension),
        _ => Err(MeshImportError::UnknownExtension {
            path: path.to_owned(),
            extension,
        }),
    }
}

/// Reads and cleans the mesh file at `path`: [`read_mesh`] then [`clean`].
pub fn load_mesh<const D: usize>(
    path: &Path,
    options: &ImportOptions<D>,
) -> Result<(Mesh<D>, ImportReport), MeshImportError> {
    clean(read_mesh(path, D)?, options)
}

/// The whole file, or an error naming it and the cause: a file that is not
/// regular (a pipe would block, a device never end) or holds more than
/// [`MAX_MESH_FILE_BYTES`] is refused before it is read.
fn read_file(path: &Path) -> Result<Vec<u8>, MeshImportError> {
    read_regular_file(path, MAX_MESH_FILE_BYTES).map_err(|source| MeshImportError::Io {
        path: path.to_owned(),
        source,
    })
}
