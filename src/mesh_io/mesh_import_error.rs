//! Errors of reading and cleaning a mesh file: each names the file, and the
//! line (text), byte (binary data), element or vertex where it went wrong.

use crate::input_file::InputFileError;
use crate::mesh::{MeshError, SurfaceError};
use std::fmt;
use std::path::PathBuf;

/// Where in a file an error was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Location {
    /// A line of a text file (1-based).
    Line(usize),
    /// A byte offset into binary data (0-based).
    Byte(usize),
    /// The file as a whole.
    File,
}

impl fmt::Display for Location {
    /// `:12` after the file name for a line, ` (byte 4096)` for a byte offset.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Line(line) => write!(f, ":{line}"),
            Location::Byte(byte) => write!(f, " (byte {byte})"),
            Location::File => Ok(()),
        }
    }
}

/// A mesh file that cannot be read, or a mesh that cannot be cleaned.
///
/// Element and vertex numbers are the file's own (gmsh tags, MEDIT and TetGen
/// numbers, VTU indices), so that they can be looked up in the file.
#[derive(Debug, thiserror::Error)]
pub enum MeshImportError {
    /// The file (or its TetGen partner) cannot be read: the OS refused, it
    /// is not a regular file, or it is too large.
    #[error("cannot read mesh file {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: InputFileError,
    },
    /// The extension names no format elasto reads.
    #[error(
        "{}: unknown mesh file extension {extension:?}; elasto reads .msh (gmsh), .mesh (MEDIT), .node + .ele (TetGen, Triangle) and .vtu (VTK)",
        path.display()
    )]
    UnknownExtension {
        /// The file.
        path: PathBuf,
        /// Its extension ("" when it has none).
        extension: String,
    },
    /// The extension names no surface format elasto reads (an obstacle's file).
    #[error(
        "{}: unknown surface file extension {extension:?}; an obstacle is read from .obj (Wavefront), .ply, or the boundary of a mesh file (.msh, .mesh, .node + .ele, .vtu)",
        path.display()
    )]
    UnknownSurfaceExtension {
        /// The file.
        path: PathBuf,
        /// Its extension ("" when it has none).
        extension: String,
    },
    /// The file does not start like a file of the format its extension names.
    #[error("{}: not a {format} mesh: {reason}", path.display())]
    NotAMesh {
        /// The file.
        path: PathBuf,
        /// The format the extension promised.
        format: &'static str,
        /// What was found instead.
        reason: String,
    },
    /// The file ends before its own counts say it should.
    #[error("{}{location}: the file is truncated: it ends where {expected} should be", path.display())]
    Truncated {
        /// The file.
        path: PathBuf,
        /// Where the data ends.
        location: Location,
        /// What was still expected.
        expected: String,
    },
    /// A count in the file's header that the rest of the file cannot hold:
    /// refused before anything is allocated for it.
    #[error(
        "{}{location}: the file declares {count} {what}, more than the {bytes_left} bytes after this point can hold (the file is truncated or the count is wrong)",
        path.display()
    )]
    CountBeyondFile {
        /// The file.
        path: PathBuf,
        /// Where the count is.
        location: Location,
        /// The count as declared.
        count: u64,
        /// What is counted ("nodes", "attributes per point", ...).
        what: String,
        /// The bytes the file has left.
        bytes_left: usize,
    },
    /// A value or keyword that does not fit the format.
    #[error("{}{location}: {reason}", path.display())]
    Syntax {
        /// The file.
        path: PathBuf,
        /// Where.
        location: Location,
        /// What is wrong.
        reason: String,
    },
    /// A version of the format that elasto does not read.
    #[error("{}: {format} version {version} is not supported: {hint}", path.display())]
    UnsupportedVersion {
        /// The file.
        path: PathBuf,
        /// The format.
        format: &'static str,
        /// The version found.
        version: String,
        /// What to do instead.
        hint: &'static str,
    },
    /// An element names a vertex the file does not define.
    #[error(
        "{}: element {element} refers to vertex {vertex}, which the file does not define",
        path.display()
    )]
    BadIndex {
        /// The file.
        path: PathBuf,
        /// The element, in the file's numbering.
        element: i64,
        /// The missing vertex, in the file's numbering.
        vertex: i64,
    },
    /// No element of the kind the scene needs.
    #[error("{}: the file holds no {wanted}{found}", path.display())]
    NoElements {
        /// The file.
        path: PathBuf,
        /// "tetrahedra" or "triangles".
        wanted: &'static str,
        /// What the file holds instead (", only ..." or "").
        found: String,
    },
    /// Tetrahedra in a file read for a 2D scene.
    #[error(
        "{}: the file holds {count} tetrahedra: it is a 3D mesh, but the scene is 2D",
        path.display()
    )]
    NotTwoDimensional {
        /// The file.
        path: PathBuf,
        /// Number of tetrahedra.
        count: usize,
    },
    /// A vertex of a 2D mesh off the plane z = 0.
    #[error(
        "{}: vertex {vertex} has z = {z}, but a 2D mesh must lie in the plane z = 0",
        path.display()
    )]
    NotPlanar {
        /// The file.
        path: PathBuf,
        /// The vertex, in the file's numbering.
        vertex: i64,
        /// Its z coordinate.
        z: f64,
    },
    /// A vertex coordinate that is infinite or not a number.
    #[error("{}: vertex {vertex} has a non-finite coordinate ({value})", path.display())]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// The vertex, in the file's numbering.
        vertex: i64,
        /// The coordinate.
        value: f64,
    },
    /// A vertex beyond the range the renderer's 32-bit floats hold, in the
    /// file or after the transforms.
    #[error(
        "{}: vertex {vertex} lies at {value:e}{after}, beyond ±3.4e38: images are drawn in \
         32-bit floats, which hold magnitudes up to 3.4e38",
        path.display()
    )]
    OutOfRange {
        /// The file.
        path: PathBuf,
        /// The vertex, in the file's numbering.
        vertex: i64,
        /// The coordinate.
        value: f64,
        /// `""`, or what moved it there (`" after scale, rotate and translate"`).
        after: &'static str,
    },
    /// An element with (numerically) zero volume.
    #[error(
        "{}: element {element} with vertices {vertices:?} is degenerate (signed volume {volume:.3e})",
        path.display()
    )]
    Degenerate {
        /// The file.
        path: PathBuf,
        /// The element, in the file's numbering.
        element: i64,
        /// Its vertices, in the file's numbering.
        vertices: Vec<i64>,
        /// Its signed volume (area in 2D), after the transforms.
        volume: f64,
    },
    /// An inverted element while re-orienting is off.
    #[error(
        "{}: element {element} with vertices {vertices:?} is inverted (signed volume {volume:.3e}); re-orienting is off (`orient = false`)",
        path.display()
    )]
    Inverted {
        /// The file.
        path: PathBuf,
        /// The element, in the file's numbering.
        element: i64,
        /// Its vertices, in the file's numbering.
        vertices: Vec<i64>,
        /// Its signed volume (area in 2D), after the transforms.
        volume: f64,
    },
    /// An import option out of range.
    #[error("mesh import option `{key}`: {reason}")]
    InvalidOption {
        /// The option.
        key: &'static str,
        /// Why it is invalid.
        reason: String,
    },
    /// A surface's facets were refused by [`crate::mesh::SurfaceMesh::new`]
    /// (facets numbered from 0 in the file's order, polygons split into
    /// triangles).
    #[error("{}: {source}", path.display())]
    Surface {
        /// The file.
        path: PathBuf,
        /// The surface error.
        source: SurfaceError,
    },
    /// The cleaned mesh was still refused by [`crate::mesh::Mesh::new`].
    #[error("{}: {source}", path.display())]
    Mesh {
        /// The file.
        path: PathBuf,
        /// The mesh error.
        source: MeshError,
    },
}
