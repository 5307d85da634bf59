//! Surface files in, for obstacles: Wavefront OBJ and PLY, or the boundary of a volume mesh file.
//!
//! | format | extension | 3D facets | 2D facets | read by |
//! | --- | --- | --- | --- | --- |
//! | Wavefront OBJ | `.obj` | `f` faces (polygons split into a fan of triangles) | `l` polylines (one segment per pair of points) | this module |
//! | PLY, ASCII or binary | `.ply` | `face` (`vertex_indices`) | `edge` (`vertex1`, `vertex2`) | the `ply-rs-bw` crate |
//! | a volume mesh (`.msh`, `.mesh`, `.node`/`.ele`, `.vtu`) | | the boundary triangles | the boundary edges | [`super::load_mesh`] |
//!
//! OBJ is read here and not with the `tobj` crate: `tobj` files an `l`
//! polyline of three points as a triangle (it sorts elements by their
//! number of points, not by their keyword), and its errors carry no line.
//! Points go through the scene's `scale`, `rotate` and `translate`; in 2D
//! they must lie in the plane z = 0. Elements of the other dimension (lines
//! in a 3D file, faces in a 2D one), normals, texture coordinates, groups
//! and materials are skipped. Every error names the file and, for OBJ, the
//! line; a PLY header's counts are checked against the bytes the file holds
//! before anything is read for them.

use super::{ImportOptions, Location, MeshImportError, load_mesh, read_file};
use crate::math::Vector;
use crate::mesh::SurfaceMesh;
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{DefaultElement, Encoding, Property};
use std::path::Path;

/// A file's points (`[x, y, z]`) and facets (0-based, `D` points each).
type PointsAndFacets = (Vec<[f64; 3]>, Vec<Vec<usize>>);

/// A surface read from a file, with what it was read as.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceImport<const D: usize> {
    /// The surface, placed.
    pub surface: SurfaceMesh<D>,
    /// The format, e.g. `"Wavefront OBJ"` or `"boundary of gmsh MSH 4.1 ASCII"`.
    pub format: String,
}

/// Reads the surface in the file at `path` and places it by `options`
/// (`scale`, `rotate`, `translate`; a volume mesh is cleaned by all of them
/// first). The format follows the extension (see the module documentation).
pub fn load_surface<const D: usize>(
    path: &Path,
    options: &ImportOptions<D>,
) -> Result<SurfaceImport<D>, MeshImportError> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let (points, facets, format) = match extension.as_str() {
        "obj" => {
            let (points, facets) = read_obj(path, &read_file(path)?, D)?;
            (points, facets, "Wavefront OBJ".to_owned())
        }
        "ply" => {
            let ((points, facets), variant) = read_ply(path, &read_file(path)?, D)?;
            (points, facets, format!("PLY {variant}"))
        }
        "msh" | "mesh" | "node" | "ele" | "vtu" => {
            let (mesh, report) = load_mesh(path, options)?;
            return Ok(SurfaceImport {
                surface: SurfaceMesh::boundary_of(&mesh),
                format: format!("boundary of {}", report.format),
            });
        }
        _ => {
            return Err(MeshImportError::UnknownSurfaceExtension {
                path: path.to_owned(),
                extension,
            });
        }
    };
    let mut placed = Vec::with_capacity(points.len());
    for (i, p) in points.iter().enumerate() {
        let vertex = i as i64 + 1;
        if let Some(&value) = p.iter().find(|v| !v.is_finite()) {
            return Err(MeshImportError::NonFinite {
                path: path.to_owned(),
                vertex,
                value,
            });
        }
        if D == 2 && p[2] != 0.0 {
            return Err(MeshImportError::NotPlanar {
                path: path.to_owned(),
                vertex,
                z: p[2],
            });
        }
        let x: Vector<D> = options.place_point(*p);
        if let Some(&value) = x.iter().find(|v| !(v.abs() <= f64::from(f32::MAX))) {
            return Err(MeshImportError::OutOfRange {
                path: path.to_owned(),
                vertex,
                value,
                after: " after scale, rotate and translate",
            });
        }
        placed.push(x);
    }
    let facets = facets
        .into_iter()
        .map(|f| std::array::from_fn(|k| f[k]))
        .collect();
    let surface = SurfaceMesh::new(placed, facets).map_err(|source| MeshImportError::Surface {
        path: path.to_owned(),
        source,
    })?;
    Ok(SurfaceImport { surface, format })
}

/// Points and facets (0-based) of an OBJ file: `dimension` 3 keeps
/// triangles (faces split into fans), 2 keeps segments (`l` polylines).
fn read_obj(
    path: &Path,
    bytes: &[u8],
    dimension: usize,
) -> Result<PointsAndFacets, MeshImportError> {
    let text = std::str::from_utf8(bytes).map_err(|e| MeshImportError::NotAMesh {
        path: path.to_owned(),
        format: "Wavefront OBJ",
        reason: format!("the file is not text (UTF-8): {e}"),
    })?;
    let syntax = |line: usize, reason: String| MeshImportError::Syntax {
        path: path.to_owned(),
        location: Location::Line(line),
        reason,
    };
    let mut points: Vec<[f64; 3]> = Vec::new();
    let mut facets: Vec<Vec<usize>> = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let number = number + 1;
        let line = line.split('#').next().unwrap_or("");
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        match keyword {
            "v" => {
                let values: Vec<f64> = words
                    .take(3)
                    .map(|w| {
                        w.parse::<f64>()
                            .map_err(|_| syntax(number, format!("`{w}` is not a number")))
                    })
                    .collect::<Result<_, _>>()?;
                if values.len() < 2 {
                    return Err(syntax(number, "a vertex `v` needs x, y and z".to_owned()));
                }
                points.push([values[0], values[1], values.get(2).copied().unwrap_or(0.0)]);
            }
            "f" | "l" => {
                let corners: Vec<usize> = words
                    .map(|w| obj_index(w, points.len()).map_err(|reason| syntax(number, reason)))
                    .collect::<Result<_, _>>()?;
                let needed = if keyword == "f" { 3 } else { 2 };
                if corners.len() < needed {
                    return Err(syntax(
                        number,
                        format!(
                            "`{keyword}` needs at least {needed} points, got {}",
                            corners.len()
                        ),
                    ));
                }
                match (keyword, dimension) {
                    ("f", 3) => facets.extend(
                        (1..corners.len() - 1)
                            .map(|k| vec![corners[0], corners[k], corners[k + 1]]),
                    ),
                    ("l", 2) => facets.extend(corners.windows(2).map(<[usize]>::to_vec)),
                    _ => {}
                }
            }
            _ => {}
        }
    }
    if facets.is_empty() {
        return Err(MeshImportError::NoElements {
            path: path.to_owned(),
            wanted: if dimension == 3 {
                "faces (`f`)"
            } else {
                "polylines (`l`)"
            },
            found: String::new(),
        });
    }
    Ok((points, facets))
}

/// The 0-based point of an OBJ index word (`i`, `i/t`, `i//n`, `i/t/n`;
/// negative: counted back from the last point read), given `count` points.
fn obj_index(word: &str, count: usize) -> Result<usize, String> {
    let first = word.split('/').next().unwrap_or("");
    let index: i64 = first
        .parse()
        .map_err(|_| format!("`{word}` is not a point index"))?;
    let resolved = if index < 0 {
        count as i64 + index
    } else {
        index - 1
    };
    if index == 0 || resolved < 0 || resolved >= count as i64 {
        return Err(format!(
            "point index {index} does not name one of the {count} points read so far"
        ));
    }
    Ok(resolved as usize)
}

/// Points and facets of a PLY file (vertex `x`, `y`, `z`; 3D: `face`
/// lists split into fans; 2D: `edge` `vertex1`, `vertex2`), and its
/// variant ("ASCII", "binary little endian", ...).
fn read_ply(
    path: &Path,
    bytes: &[u8],
    dimension: usize,
) -> Result<(PointsAndFacets, String), MeshImportError> {
    let not_ply = |reason: String| MeshImportError::NotAMesh {
        path: path.to_owned(),
        format: "PLY",
        reason,
    };
    let parser = Parser::<DefaultElement>::new();
    let header = parser
        .read_ply_header(&mut &bytes[..])
        .map_err(|e| not_ply(e.to_string()))?;
    // Every element takes at least one byte per property: a count beyond
    // the file is refused before the parser reserves room for it.
    for (name, element) in &header.elements {
        let least = element
            .count
            .saturating_mul(element.properties.len().max(1));
        if least > bytes.len() {
            return Err(MeshImportError::CountBeyondFile {
                path: path.to_owned(),
                location: Location::File,
                count: element.count as u64,
                what: format!("`{name}` elements"),
                bytes_left: bytes.len(),
            });
        }
    }
    let variant = match header.encoding {
        Encoding::Ascii => "ASCII",
        Encoding::BinaryBigEndian => "binary big endian",
        Encoding::BinaryLittleEndian => "binary little endian",
    };
    let ply = parser
        .read_ply(&mut &bytes[..])
        .map_err(|e| not_ply(e.to_string()))?;
    let number = |p: Option<&Property>| -> Option<f64> {
        Some(match p? {
            Property::Char(v) => f64::from(*v),
            Property::UChar(v) => f64::from(*v),
            Property::Short(v) => f64::from(*v),
            Property::UShort(v) => f64::from(*v),
            Property::Int(v) => f64::from(*v),
            Property::UInt(v) => f64::from(*v),
            Property::Float(v) => f64::from(*v),
            Property::Double(v) => *v,
            _ => return None,
        })
    };
    let list = |p: Option<&Property>| -> Option<Vec<i64>> {
        Some(match p? {
            Property::ListChar(v) => v.iter().map(|&i| i64::from(i)).collect(),
            Property::ListUChar(v) => v.iter().map(|&i| i64::from(i)).collect(),
            Property::ListShort(v) => v.iter().map(|&i| i64::from(i)).collect(),
            Property::ListUShort(v) => v.iter().map(|&i| i64::from(i)).collect(),
            Property::ListInt(v) => v.iter().map(|&i| i64::from(i)).collect(),
            Property::ListUInt(v) => v.iter().map(|&i| i64::from(i)).collect(),
            _ => return None,
        })
    };
    let empty = Vec::new();
    let vertices = ply.payload.get("vertex").unwrap_or(&empty);
    let mut points = Vec::with_capacity(vertices.len());
    for (i, v) in vertices.iter().enumerate() {
        let coordinate = |name: &str| {
            number(v.get(name)).ok_or_else(|| not_ply(format!("vertex {i} has no number `{name}`")))
        };
        let z = if dimension == 2 && !v.contains_key("z") {
            0.0
        } else {
            coordinate("z")?
        };
        points.push([coordinate("x")?, coordinate("y")?, z]);
    }
    let count = points.len() as i64;
    let mut facets = Vec::new();
    let index = |element: usize, i: i64| -> Result<usize, MeshImportError> {
        if (0..count).contains(&i) {
            Ok(i as usize)
        } else {
            Err(MeshImportError::BadIndex {
                path: path.to_owned(),
                element: element as i64,
                vertex: i,
            })
        }
    };
    if dimension == 3 {
        for (f, face) in ply.payload.get("face").unwrap_or(&empty).iter().enumerate() {
            let corners = list(face.get("vertex_indices").or(face.get("vertex_index")))
                .ok_or_else(|| not_ply(format!("face {f} has no list `vertex_indices`")))?;
            if corners.len() < 3 {
                return Err(not_ply(format!("face {f} has {} corners", corners.len())));
            }
            let corners: Vec<usize> = corners
                .iter()
                .map(|&i| index(f, i))
                .collect::<Result<_, _>>()?;
            facets.extend(
                (1..corners.len() - 1).map(|k| vec![corners[0], corners[k], corners[k + 1]]),
            );
        }
    } else {
        for (e, edge) in ply.payload.get("edge").unwrap_or(&empty).iter().enumerate() {
            let end = |name: &str| {
                number(edge.get(name))
                    .ok_or_else(|| not_ply(format!("edge {e} has no index `{name}`")))
            };
            facets.push(vec![
                index(e, end("vertex1")? as i64)?,
                index(e, end("vertex2")? as i64)?,
            ]);
        }
    }
    if facets.is_empty() {
        return Err(MeshImportError::NoElements {
            path: path.to_owned(),
            wanted: if dimension == 3 {
                "faces (`face`)"
            } else {
                "edges (`edge`)"
            },
            found: String::new(),
        });
    }
    Ok(((points, facets), variant.to_owned()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn obj(text: &str, dimension: usize) -> Result<PointsAndFacets, String> {
        read_obj(Path::new("t.obj"), text.as_bytes(), dimension).map_err(|e| e.to_string())
    }

    #[test]
    fn obj_faces_polylines_and_indices() {
        let text = "# a quad and a polyline\nv 0 0 0\nv 1 0 0\nv 1 1 0 # corner\nv 0 1 0\n\
                    vn 0 0 1\nf 1//1 2//1 3//1 4//1\nl -4 -3 -2\n";
        let (points, facets) = obj(text, 3).unwrap();
        assert_eq!(points.len(), 4);
        assert_eq!(facets, vec![vec![0, 1, 2], vec![0, 2, 3]]);
        let (_, segments) = obj(text, 2).unwrap();
        assert_eq!(segments, vec![vec![0, 1], vec![1, 2]]);
    }

    #[test]
    fn obj_errors_name_the_line() {
        for (text, expected) in [
            ("v 0 0 0\nv 1 x 0\n", "t.obj:2: `x` is not a number"),
            ("v 0 0 0\nf 1 2 3\n", "t.obj:2: point index 2 does not name"),
            (
                "v 0 0 0\nv 1 0 0\nf 1 2\n",
                "t.obj:3: `f` needs at least 3 points",
            ),
            ("v 0 0 0\nv 1 0 0\nl 1 2\n", "holds no faces (`f`)"),
        ] {
            let message = obj(text, 3).unwrap_err();
            assert!(message.contains(expected), "{message}");
        }
    }

    #[test]
    fn ply_faces_and_edges() {
        let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n\
                    property float y\nproperty float z\nelement face 1\n\
                    property list uchar int vertex_indices\nelement edge 1\n\
                    property int vertex1\nproperty int vertex2\nend_header\n\
                    0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n0 1\n";
        let ((points, facets), variant) = read_ply(Path::new("t.ply"), text.as_bytes(), 3).unwrap();
        assert_eq!(points[1], [1.0, 0.0, 0.0]);
        assert_eq!(facets, vec![vec![0, 1, 2]]);
        assert_eq!(variant, "ASCII");
        let ((_, segments), _) = read_ply(Path::new("t.ply"), text.as_bytes(), 2).unwrap();
        assert_eq!(segments, vec![vec![0, 1]]);
        // A count the file cannot hold is refused before it is read.
        let huge = text.replace("element vertex 3", "element vertex 4000000000");
        let message = read_ply(Path::new("t.ply"), huge.as_bytes(), 3)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("declares 4000000000 `vertex` elements"),
            "{message}"
        );
    }
}
