//! The raw content of a mesh file: its vertices and the simplices of the
//! requested dimension, in the file's order, with the file's own numbers.

use super::MeshImportError;
use std::collections::{BTreeMap, HashMap};
use std::path::PathBuf;

/// A mesh as read from a file, before cleaning.
///
/// Vertices are 3D (z = 0 for a 2D file); simplices are triangles for
/// `dimension = 2` and tetrahedra for `dimension = 3`, `dimension + 1`
/// 0-based indices into `points` each. Every vertex of the file is kept, used
/// or not; elements of other types are only counted.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportedMesh {
    /// The file read (the path given, for TetGen either `.node` or `.ele`).
    pub path: PathBuf,
    /// The format and variant, e.g. `"gmsh MSH 4.1 binary"`.
    pub format: String,
    /// 2 (triangles) or 3 (tetrahedra).
    pub dimension: usize,
    /// Every vertex of the file, in file order.
    pub points: Vec<[f64; 3]>,
    /// The file's number of each vertex (gmsh node tag, MEDIT or TetGen
    /// number, VTU index), for messages.
    pub point_labels: Vec<i64>,
    /// The kept simplices, `dimension + 1` indices into `points` each.
    pub simplices: Vec<usize>,
    /// The file's number of each kept simplex, for messages.
    pub simplex_labels: Vec<i64>,
    /// Elements of other types, by type name (singular: `"triangle"`,
    /// `"line"`, `"10-node tetrahedron"`), with their counts.
    pub ignored: BTreeMap<String, usize>,
}

impl ImportedMesh {
    /// Number of vertices per kept simplex.
    pub fn nodes_per_simplex(&self) -> usize {
        self.dimension + 1
    }

    /// Number of kept simplices.
    pub fn simplex_count(&self) -> usize {
        self.simplex_labels.len()
    }

    /// The vertex indices of kept simplex `e`.
    pub fn simplex(&self, e: usize) -> &[usize] {
        let n = self.nodes_per_simplex();
        &self.simplices[e * n..(e + 1) * n]
    }
}

/// The kind of an element of a file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Shape {
    /// A linear triangle.
    Triangle,
    /// A linear tetrahedron.
    Tetrahedron,
    /// Anything else, by singular name (`"line"`, `"10-node tetrahedron"`).
    Other(String),
}

/// How a file numbers its vertices.
#[derive(Debug)]
pub(crate) enum Numbering {
    /// Vertex `k` of the file (0-based) has number `first + k`.
    Consecutive {
        /// The first vertex's number (0 or 1).
        first: i64,
    },
    /// Each vertex has a tag of its own (gmsh node tags).
    Tags(HashMap<i64, usize>),
}

/// Collects a file's vertices and elements, keeping the simplices of one
/// dimension and counting the rest; vertex numbers are resolved at the end,
/// so a format may list elements before vertices.
pub(crate) struct MeshBuilder {
    mesh: ImportedMesh,
    numbering: Numbering,
    /// The vertex numbers of each kept simplex, as written.
    simplex_vertex_labels: Vec<i64>,
    tetrahedra_in_2d: usize,
}

impl MeshBuilder {
    /// An empty builder for `path`, keeping simplices of `dimension` (2 or 3).
    pub fn new(path: PathBuf, format: String, dimension: usize, numbering: Numbering) -> Self {
        Self {
            mesh: ImportedMesh {
                path,
                format,
                dimension,
                points: Vec::new(),
                point_labels: Vec::new(),
                simplices: Vec::new(),
                simplex_labels: Vec::new(),
                ignored: BTreeMap::new(),
            },
            numbering,
            simplex_vertex_labels: Vec::new(),
            tetrahedra_in_2d: 0,
        }
    }

    /// Reserves room for `n` more vertices.
    pub fn reserve_points(&mut self, n: usize) {
        self.mesh.points.reserve(n.min(1 << 24));
        self.mesh.point_labels.reserve(n.min(1 << 24));
    }

    /// Adds a vertex with the file's number `label`. With tag numbering a
    /// repeated tag is an error (the caller adds the place).
    pub fn add_point(&mut self, label: i64, point: [f64; 3]) -> Result<(), String> {
        let index = self.mesh.points.len();
        match &mut self.numbering {
            Numbering::Consecutive { first } => {
                if label != *first + index as i64 {
                    return Err(format!(
                        "vertex number {label} out of sequence: expected {}",
                        *first + index as i64
                    ));
                }
            }
            Numbering::Tags(tags) => {
                if tags.insert(label, index).is_some() {
                    return Err(format!("vertex tag {label} is defined twice"));
                }
            }
        }
        self.mesh.points.push(point);
        self.mesh.point_labels.push(label);
        Ok(())
    }

    /// Adds an element numbered `label` in the file, with the vertex numbers
    /// `vertices` as written. Simplices of the builder's dimension are kept
    /// (their first `dimension + 1` vertices), everything else is counted.
    pub fn add_element(&mut self, shape: Shape, label: i64, vertices: &[i64]) {
        let kept = match (&shape, self.mesh.dimension) {
            (Shape::Triangle, 2) | (Shape::Tetrahedron, 3) => true,
            (Shape::Tetrahedron, 2) => {
                self.tetrahedra_in_2d += 1;
                false
            }
            _ => false,
        };
        if kept {
            let n = self.mesh.dimension + 1;
            self.simplex_vertex_labels.extend_from_slice(&vertices[..n]);
            self.mesh.simplex_labels.push(label);
        } else {
            let name = match shape {
                Shape::Triangle => "triangle".to_owned(),
                Shape::Tetrahedron => "tetrahedron".to_owned(),
                Shape::Other(name) => name,
            };
            *self.mesh.ignored.entry(name).or_insert(0) += 1;
        }
    }

    /// Resolves vertex numbers and checks what a mesh needs: simplices of the
    /// right dimension, known vertices, finite coordinates, and z = 0 in 2D.
    pub fn finish(self) -> Result<ImportedMesh, MeshImportError> {
        let Self {
            mut mesh,
            numbering,
            simplex_vertex_labels,
            tetrahedra_in_2d,
        } = self;
        let path = mesh.path.clone();
        if tetrahedra_in_2d > 0 {
            return Err(MeshImportError::NotTwoDimensional {
                path,
                count: tetrahedra_in_2d,
            });
        }
        if mesh.simplex_labels.is_empty() {
            let wanted = if mesh.dimension == 2 {
                "triangles"
            } else {
                "tetrahedra"
            };
            let found = if mesh.ignored.is_empty() {
                String::new()
            } else {
                format!(", only {}", describe_counts(&mesh.ignored))
            };
            return Err(MeshImportError::NoElements {
                path,
                wanted,
                found,
            });
        }
        let n = mesh.dimension + 1;
        let count = mesh.points.len();
        mesh.simplices = Vec::with_capacity(simplex_vertex_labels.len());
        for (k, &vertex) in simplex_vertex_labels.iter().enumerate() {
            let index = match &numbering {
                Numbering::Consecutive { first } => vertex
                    .checked_sub(*first)
                    .and_then(|i| usize::try_from(i).ok())
                    .filter(|&i| i < count),
                Numbering::Tags(tags) => tags.get(&vertex).copied(),
            };
            match index {
                Some(index) => mesh.simplices.push(index),
                None => {
                    return Err(MeshImportError::BadIndex {
                        path,
                        element: mesh.simplex_labels[k / n],
                        vertex,
                    });
                }
            }
        }
        let mut used = vec![false; count];
        for &v in &mesh.simplices {
            used[v] = true;
        }
        let extent = mesh
            .points
            .iter()
            .zip(&used)
            .filter(|(_, u)| **u)
            .flat_map(|(p, _)| p.iter().map(|c| c.abs()))
            .filter(|c| c.is_finite())
            .fold(0.0f64, f64::max);
        for (k, point) in mesh.points.iter().enumerate() {
            if !used[k] {
                continue;
            }
            let vertex = mesh.point_labels[k];
            if let Some(&value) = point.iter().find(|c| !c.is_finite()) {
                return Err(MeshImportError::NonFinite {
                    path,
                    vertex,
                    value,
                });
            }
            if mesh.dimension == 2 && point[2].abs() > 1e-12 * extent.max(f64::MIN_POSITIVE) {
                return Err(MeshImportError::NotPlanar {
                    path,
                    vertex,
                    z: point[2],
                });
            }
        }
        Ok(mesh)
    }
}

/// `"84 triangles, 24 lines, 1 point"`.
pub(crate) fn describe_counts(counts: &BTreeMap<String, usize>) -> String {
    // Largest counts first reads best; ties keep the names' order.
    let mut pairs: Vec<(&String, usize)> = counts.iter().map(|(name, &n)| (name, n)).collect();
    pairs.sort_by_key(|&(_, n)| std::cmp::Reverse(n));
    pairs
        .iter()
        .map(|&(name, n)| format!("{n} {}", plural(name, n)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The plural of an element type's name when `n != 1`.
pub(crate) fn plural(name: &str, n: usize) -> String {
    if n == 1 {
        name.to_owned()
    } else if let Some(stem) = name.strip_suffix("hedron") {
        format!("{stem}hedra")
    } else if let Some(stem) = name.strip_suffix("vertex") {
        format!("{stem}vertices")
    } else {
        format!("{name}s")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn builder(dimension: usize) -> MeshBuilder {
        MeshBuilder::new(
            PathBuf::from("a.msh"),
            "test".into(),
            dimension,
            Numbering::Tags(HashMap::new()),
        )
    }

    #[test]
    fn other_element_types_are_counted_by_name() {
        let mut b = builder(3);
        for (k, p) in [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
            .into_iter()
            .enumerate()
        {
            b.add_point(10 + k as i64, p).unwrap();
        }
        b.add_element(Shape::Tetrahedron, 1, &[10, 11, 12, 13]);
        b.add_element(Shape::Triangle, 2, &[10, 11, 12]);
        b.add_element(Shape::Triangle, 3, &[10, 11, 13]);
        b.add_element(Shape::Other("line".into()), 4, &[10, 11]);
        let mesh = b.finish().unwrap();
        assert_eq!(mesh.simplices, vec![0, 1, 2, 3]);
        assert_eq!(mesh.simplex_labels, vec![1]);
        assert_eq!(describe_counts(&mesh.ignored), "2 triangles, 1 line");
    }

    #[test]
    fn a_repeated_tag_and_an_unknown_vertex_are_refused() {
        let mut b = builder(2);
        b.add_point(1, [0.0; 3]).unwrap();
        assert_eq!(
            b.add_point(1, [1.0, 0.0, 0.0]).unwrap_err(),
            "vertex tag 1 is defined twice"
        );
        b.add_element(Shape::Triangle, 7, &[1, 1, 5]);
        assert_eq!(
            b.finish().unwrap_err().to_string(),
            "a.msh: element 7 refers to vertex 5, which the file does not define"
        );
    }

    #[test]
    fn plurals_of_element_names() {
        assert_eq!(plural("10-node tetrahedron", 2), "10-node tetrahedra");
        assert_eq!(plural("point", 3), "points");
        assert_eq!(plural("line", 1), "line");
    }
}
