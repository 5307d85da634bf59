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
//! Obstacles' surfaces ([`load_surface`], `surface_file.rs`): Wavefront
//! `.obj` and `.ply`, or the boundary of any of the mesh files above.
//!
//! Every error names the file and, where it applies, the line (text), byte
//! (binary data), element or vertex, in the file's own numbering.

mod clean;
mod cursor;
mod imported_mesh;
mod medit;
mod mesh_import_error;
mod msh;
mod surface_file;
mod tetgen;
mod vtu;
mod vtu_sizes;

pub use clean::{ImportOptions, ImportReport, clean};
pub use imported_mesh::ImportedMesh;
pub use mesh_import_error::{Location, MeshImportError};
pub use surface_file::{SurfaceImport, load_surface};

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

/// What a mesh file was when it was read: its size and checksum, recorded
/// in a run's `scene.toml` so a later run of it can tell that the file has
/// changed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MeshFileFingerprint {
    /// Bytes in the file (for TetGen, the `.node` and `.ele` together).
    pub size: u64,
    /// `xxh3:` and the file's (or the TetGen pair's) 64-bit XXH3 hash in 16
    /// hexadecimal digits.
    pub checksum: String,
}

impl MeshFileFingerprint {
    /// The prefix of [`MeshFileFingerprint::checksum`].
    pub const CHECKSUM_PREFIX: &'static str = "xxh3:";

    /// Whether `text` is a checksum as [`MeshFileFingerprint::checksum`]
    /// writes it.
    pub fn is_checksum(text: &str) -> bool {
        text.strip_prefix(Self::CHECKSUM_PREFIX)
            .is_some_and(|hex| hex.len() == 16 && hex.bytes().all(|b| b.is_ascii_hexdigit()))
    }
}

/// The size and checksum of the mesh file at `path` (the `.node` and
/// `.ele` pair for TetGen, in that order), read in pieces, at most
/// [`MAX_MESH_FILE_BYTES`] per file. XXH3 (the `twox-hash` crate) hashes
/// at several GB/s, so a large mesh costs about as much as reading it; it
/// tells a changed file, it is no defence against a forged one.
pub fn mesh_file_fingerprint(path: &Path) -> Result<MeshFileFingerprint, MeshImportError> {
    use std::hash::Hasher;
    use std::io::Read;
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let files = match extension.as_str() {
        "node" | "ele" => vec![path.with_extension("node"), path.with_extension("ele")],
        _ => vec![path.to_owned()],
    };
    let mut hasher = twox_hash::XxHash3_64::default();
    let mut size = 0u64;
    let mut buffer = vec![0u8; 1 << 20];
    for file in &files {
        let io = |source: std::io::Error| MeshImportError::Io {
            path: file.clone(),
            source: source.into(),
        };
        let opened =
            crate::input_file::open_regular_file(file, MAX_MESH_FILE_BYTES).map_err(|source| {
                MeshImportError::Io {
                    path: file.clone(),
                    source,
                }
            })?;
        let mut limited = opened.take(MAX_MESH_FILE_BYTES);
        loop {
            let read = limited.read(&mut buffer).map_err(io)?;
            if read == 0 {
                break;
            }
            hasher.write(&buffer[..read]);
            size += read as u64;
        }
    }
    Ok(MeshFileFingerprint {
        size,
        checksum: format!(
            "{}{:016x}",
            MeshFileFingerprint::CHECKSUM_PREFIX,
            hasher.finish()
        ),
    })
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
