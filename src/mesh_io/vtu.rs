//! VTK XML unstructured grids (`.vtu`), read with the `vtkio` crate.
//!
//! `vtkio` parses the XML and decodes ASCII, base64 binary, appended and
//! zlib- or LZ4-compressed data arrays; this module only checks the result
//! (a truncated file, another VTK data set type, cells that point past the
//! points; before parsing, the sizes compressed arrays declare, see
//! `vtu_sizes.rs`) and keeps the cells of type 10 (`VTK_TETRA`) in 3D or 5
//! (`VTK_TRIANGLE`) in 2D. Points and cells are numbered from 0, as in
//! ParaView's spreadsheet view; several pieces are joined.

use super::imported_mesh::{MeshBuilder, Numbering, Shape};
use super::{ImportedMesh, Location, MeshImportError};
use std::path::Path;
use vtkio::model::{CellType, DataSet, Piece, VertexNumbers};

const FORMAT: &str = "VTK XML unstructured grid";

/// Reads a `.vtu` file held in `bytes`.
pub(crate) fn read(
    path: &Path,
    bytes: &[u8],
    dimension: usize,
) -> Result<ImportedMesh, MeshImportError> {
    let not_a_mesh = |reason: String| MeshImportError::NotAMesh {
        path: path.to_owned(),
        format: FORMAT,
        reason,
    };
    let syntax = |reason: String| MeshImportError::Syntax {
        path: path.to_owned(),
        location: Location::File,
        reason,
    };
    if !bytes.windows(8).any(|w| w == b"<VTKFile") {
        return Err(not_a_mesh("it has no `<VTKFile` element".to_owned()));
    }
    if let Some(kind) = data_set_type(bytes).filter(|kind| *kind != "UnstructuredGrid") {
        return Err(not_a_mesh(format!(
            "it holds VTK {kind} data, not an unstructured grid"
        )));
    }
    if !bytes.trim_ascii_end().ends_with(b"</VTKFile>") {
        return Err(MeshImportError::Truncated {
            path: path.to_owned(),
            location: Location::Byte(bytes.len()),
            expected: "`</VTKFile>`".to_owned(),
        });
    }
    // vtkio allocates what the compressed headers declare: checked first.
    super::vtu_sizes::check_declared_sizes(path, bytes)?;
    // vtkio slices its binary data by the sizes the file states, and panics
    // on some corrupt ones (seen with a damaged compression header), so a
    // panic there is turned into an error naming the file like any other.
    let parsed = std::panic::catch_unwind(|| vtkio::Vtk::parse_xml(bytes)).map_err(|panic| {
        let what = panic
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| panic.downcast_ref::<&str>().copied())
            .unwrap_or("unknown failure");
        syntax(format!(
            "corrupt VTK data (the vtkio reader failed: {what})"
        ))
    })?;
    let vtk = parsed.map_err(|e| syntax(format!("invalid VTK XML: {e}")))?;
    let pieces = match vtk.data {
        DataSet::UnstructuredGrid { pieces, .. } => pieces,
        other => {
            let kind = match other {
                DataSet::ImageData { .. } => "image data",
                DataSet::StructuredGrid { .. } => "a structured grid",
                DataSet::RectilinearGrid { .. } => "a rectilinear grid",
                DataSet::PolyData { .. } => "poly data",
                _ => "a field",
            };
            return Err(not_a_mesh(format!(
                "it holds {kind}, not an unstructured grid"
            )));
        }
    };
    let mut builder = MeshBuilder::new(
        path.to_owned(),
        FORMAT.to_owned(),
        dimension,
        Numbering::Consecutive { first: 0 },
    );
    let mut point_offset = 0usize;
    let mut cell_offset = 0usize;
    let mut vertices = Vec::new();
    for (p, piece) in pieces.into_iter().enumerate() {
        let piece = match piece {
            Piece::Inline(piece) => piece,
            _ => {
                return Err(syntax(format!(
                    "piece {p} is stored in another file; elasto reads serial .vtu files only"
                )));
            }
        };
        let coordinates: Vec<f64> = piece
            .points
            .cast_into()
            .ok_or_else(|| syntax(format!("piece {p}: the points are not numbers")))?;
        if !coordinates.len().is_multiple_of(3) {
            return Err(syntax(format!(
                "piece {p}: {} point coordinates is not a multiple of 3",
                coordinates.len()
            )));
        }
        let point_count = coordinates.len() / 3;
        builder.reserve_points(point_count);
        for (k, xyz) in coordinates.chunks_exact(3).enumerate() {
            builder
                .add_point((point_offset + k) as i64, [xyz[0], xyz[1], xyz[2]])
                .map_err(syntax)?;
        }
        let (connectivity, offsets) = match piece.cells.cell_verts {
            VertexNumbers::XML {
                connectivity,
                offsets,
            } => (connectivity, offsets),
            VertexNumbers::Legacy { .. } => {
                return Err(syntax(format!("piece {p}: cells in the legacy layout")));
            }
        };
        // Offsets mark the end of each cell; some writers add a leading 0.
        let offsets = match offsets.first() {
            Some(0) if offsets.len() == piece.cells.types.len() + 1 => &offsets[1..],
            _ => &offsets[..],
        };
        if offsets.len() != piece.cells.types.len() {
            return Err(syntax(format!(
                "piece {p}: {} cell offsets for {} cell types",
                offsets.len(),
                piece.cells.types.len()
            )));
        }
        let mut start = 0usize;
        for (c, (&end, &cell_type)) in offsets.iter().zip(&piece.cells.types).enumerate() {
            let label = (cell_offset + c) as i64;
            let end = usize::try_from(end)
                .ok()
                .filter(|&end| end >= start && end <= connectivity.len())
                .ok_or_else(|| {
                    syntax(format!(
                        "cell {label}: offset {end} lies outside the connectivity array of {} entries",
                        connectivity.len()
                    ))
                })?;
            vertices.clear();
            for &v in &connectivity[start..end] {
                let v = i64::try_from(v).unwrap_or(i64::MAX);
                vertices.push(v.saturating_add(point_offset as i64));
            }
            start = end;
            let (nodes, shape) = match cell_type {
                CellType::Triangle => (3, Shape::Triangle),
                CellType::Tetra => (4, Shape::Tetrahedron),
                other => (0, Shape::Other(cell_type_name(other))),
            };
            if nodes > 0 && vertices.len() != nodes {
                return Err(syntax(format!(
                    "cell {label} of type {cell_type:?} has {} points instead of {nodes}",
                    vertices.len()
                )));
            }
            builder.add_element(shape, label, &vertices);
        }
        point_offset += point_count;
        cell_offset += offsets.len();
    }
    builder.finish()
}

/// The `type` attribute of the `<VTKFile ...>` tag, if it can be found.
fn data_set_type(bytes: &[u8]) -> Option<&str> {
    let start = bytes.windows(8).position(|w| w == b"<VTKFile")?;
    let tag = &bytes[start..];
    let tag = &tag[..tag.iter().position(|&b| b == b'>')?];
    let tag = std::str::from_utf8(tag).ok()?;
    let value = tag.split_once(" type=\"")?.1;
    Some(&value[..value.find('"')?])
}

/// `QuadraticTetra` → `"quadratic tetra"`.
fn cell_type_name(cell_type: CellType) -> String {
    let debug = format!("{cell_type:?}");
    let mut name = String::new();
    for (i, ch) in debug.chars().enumerate() {
        if ch.is_ascii_uppercase() && i > 0 {
            name.push(' ');
        }
        name.push(ch.to_ascii_lowercase());
    }
    match name.as_str() {
        "vertex" => "point".to_owned(),
        "quad" => "quadrangle".to_owned(),
        "wedge" => "prism".to_owned(),
        _ => name,
    }
}
