//! MEDIT `.mesh` files (ASCII), as written by TetWild, fTetWild, gmsh, MMG.
//!
//! Hand-written: no maintained Rust crate reads MEDIT. The format is a list
//! of keywords, each followed by its data: `MeshVersionFormatted v`,
//! `Dimension d`, `Vertices n` then `n` lines of `d` coordinates and a
//! reference, `Tetrahedra n` / `Triangles n` / `Edges n` / ... then `n` lines
//! of 1-based vertex numbers and a reference, and `End`. `#` starts a
//! comment. Keywords elasto does not use (`Corners`, `Ridges`, `Normals`,
//! ...) are skipped up to the next keyword; elements other than the
//! requested simplices are counted.

use super::cursor::{Cursor, text_bytes};
use super::imported_mesh::{MeshBuilder, Numbering, Shape};
use super::{ImportedMesh, MeshImportError};
use std::path::Path;

const FORMAT: &str = "MEDIT";

/// Reads a `.mesh` file held in `bytes`.
pub(crate) fn read(
    path: &Path,
    bytes: &[u8],
    dimension: usize,
) -> Result<ImportedMesh, MeshImportError> {
    let mut cursor = Cursor::new(bytes, path, Some(b'#'));
    match cursor.token() {
        Some(t) if t.eq_ignore_ascii_case("MeshVersionFormatted") => {}
        Some(_) => {
            return Err(MeshImportError::NotAMesh {
                path: path.to_owned(),
                format: FORMAT,
                reason: "it does not start with `MeshVersionFormatted`".to_owned(),
            });
        }
        None => {
            return Err(MeshImportError::NotAMesh {
                path: path.to_owned(),
                format: FORMAT,
                reason: "the file is empty".to_owned(),
            });
        }
    }
    let version: u32 = cursor.number(|| "the version after `MeshVersionFormatted`".into())?;
    let mut builder = MeshBuilder::new(
        path.to_owned(),
        format!("{FORMAT} {version} ASCII"),
        dimension,
        Numbering::Consecutive { first: 1 },
    );
    let mut file_dimension: Option<usize> = None;
    let mut next_vertex = 1i64;
    while let Some(keyword) = cursor.token() {
        if !keyword.starts_with(|c: char| c.is_ascii_alphabetic()) {
            return Err(cursor.syntax(format!(
                "expected a keyword such as `Vertices` or `Tetrahedra`, found `{keyword}`"
            )));
        }
        let lower = keyword.to_ascii_lowercase();
        if lower == "end" {
            break;
        }
        if lower == "dimension" {
            let d: usize = cursor.number(|| "the dimension".into())?;
            if d != 2 && d != 3 {
                return Err(cursor.syntax(format!("dimension must be 2 or 3, found {d}")));
            }
            file_dimension = Some(d);
            continue;
        }
        let element = match lower.as_str() {
            "vertices" => None,
            "edges" => Some((2, Shape::Other("line".into()))),
            "triangles" => Some((3, Shape::Triangle)),
            "quadrilaterals" => Some((4, Shape::Other("quadrangle".into()))),
            "tetrahedra" => Some((4, Shape::Tetrahedron)),
            "prisms" => Some((6, Shape::Other("prism".into()))),
            "pyramids" => Some((5, Shape::Other("pyramid".into()))),
            "hexahedra" => Some((8, Shape::Other("hexahedron".into()))),
            "edgesp2" => Some((3, Shape::Other("3-node line".into()))),
            "trianglesp2" => Some((6, Shape::Other("6-node triangle".into()))),
            "tetrahedrap2" => Some((10, Shape::Other("10-node tetrahedron".into()))),
            _ => {
                // Not used by elasto: skip its data, up to the next keyword.
                while cursor
                    .peek()
                    .is_some_and(|t| !t.starts_with(|c: char| c.is_ascii_alphabetic()))
                {
                    cursor.token();
                }
                continue;
            }
        };
        let count: usize = cursor.number(|| format!("the number of {keyword}"))?;
        match element {
            None => {
                let d =
                    file_dimension.ok_or_else(|| cursor.syntax("`Vertices` before `Dimension`"))?;
                // Each vertex: its coordinates and a reference.
                cursor
                    .declared_count(count as u64, text_bytes(d as u64 + 1), || "vertices".into())?;
                builder.reserve_points(count);
                for k in 0..count {
                    let what = || format!("vertex {} of {count}", k + 1);
                    let mut p = [0.0; 3];
                    for c in p.iter_mut().take(d) {
                        *c = cursor.number(what)?;
                    }
                    cursor.number::<f64>(what)?; // reference
                    builder
                        .add_point(next_vertex, p)
                        .map_err(|reason| cursor.syntax(reason))?;
                    next_vertex += 1;
                }
            }
            Some((nodes, shape)) => {
                // Each element: its vertex numbers and a reference.
                cursor.declared_count(count as u64, text_bytes(nodes as u64 + 1), || {
                    keyword.to_ascii_lowercase()
                })?;
                let mut vertices = vec![0i64; nodes];
                for k in 0..count {
                    let what = || format!("{} {} of {count}", keyword, k + 1);
                    for v in vertices.iter_mut() {
                        *v = cursor.number(what)?;
                    }
                    cursor.number::<f64>(what)?; // reference
                    builder.add_element(shape.clone(), k as i64 + 1, &vertices);
                }
            }
        }
    }
    builder.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_2d_file_with_comments_and_unused_keywords() {
        let text = "MeshVersionFormatted 1\n# a comment\nDimension 2\nVertices\n4\n\
                    0 0 1\n1 0 1\n1 1 1\n0 1 1\nCorners 2 1 3\nEdges 1\n1 2 5\n\
                    Triangles 2\n1 2 3 0\n1 3 4 0\nEnd\n";
        let mesh = read(Path::new("sq.mesh"), text.as_bytes(), 2).unwrap();
        assert_eq!(mesh.format, "MEDIT 1 ASCII");
        assert_eq!(mesh.points[2], [1.0, 1.0, 0.0]);
        assert_eq!(mesh.simplices, vec![0, 1, 2, 0, 2, 3]);
        assert_eq!(mesh.ignored.get("line"), Some(&1));
    }

    #[test]
    fn a_vertex_number_past_the_end_is_a_bad_index() {
        let text = "MeshVersionFormatted 2\nDimension 3\nVertices 4\n0 0 0 0\n1 0 0 0\n\
                    0 1 0 0\n0 0 1 0\nTetrahedra 2\n1 2 3 4 0\n1 2 3 5 0\nEnd\n";
        let err = read(Path::new("t.mesh"), text.as_bytes(), 3).unwrap_err();
        assert_eq!(
            err.to_string(),
            "t.mesh: element 2 refers to vertex 5, which the file does not define"
        );
    }
}
