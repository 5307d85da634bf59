//! From an imported file to a simulation mesh: transforms, duplicate
//! vertices, orientation, degenerate elements, unreferenced vertices and the
//! number of connected pieces.

use super::imported_mesh::{describe_counts, plural};
use super::{ImportedMesh, MeshImportError};
use crate::math::{Matrix, Vector, determinant};
use crate::mesh::{Mesh, edge_matrix};
use std::collections::{BTreeMap, HashMap};
use std::fmt;
use std::path::PathBuf;

/// How an imported mesh is placed and cleaned.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportOptions<const D: usize> {
    /// Re-orient inverted elements (negative signed volume) instead of
    /// refusing them (default: `true`).
    pub orient: bool,
    /// Merge used vertices closer than this, in length units after the
    /// transforms; 0 merges nothing (default: 0).
    pub merge_tolerance: f64,
    /// Uniform scale factor, applied first, > 0 (default: 1).
    pub scale: f64,
    /// Rotation angles in degrees about x, then y, then z, applied after the
    /// scale (default: `[0, 0, 0]`). A 2D mesh turns only about z: the first
    /// two must then be 0.
    pub rotate: [f64; 3],
    /// Translation applied last, in length units (default: zero).
    pub translate: Vector<D>,
}

impl<const D: usize> Default for ImportOptions<D> {
    fn default() -> Self {
        Self {
            orient: true,
            merge_tolerance: 0.0,
            scale: 1.0,
            rotate: [0.0; 3],
            translate: Vector::<D>::zeros(),
        }
    }
}

/// What cleaning found and did, for `check`'s summary.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportReport {
    /// The file read.
    pub path: PathBuf,
    /// Its format and variant, e.g. `"gmsh MSH 4.1 binary"`.
    pub format: String,
    /// 2 (triangles) or 3 (tetrahedra).
    pub dimension: usize,
    /// Vertices of the cleaned mesh.
    pub vertices: usize,
    /// Simplices of the cleaned mesh.
    pub elements: usize,
    /// Elements of other types in the file, by type name, with counts.
    pub ignored: BTreeMap<String, usize>,
    /// Inverted elements that were re-oriented.
    pub reoriented: usize,
    /// Vertices of the file that no kept simplex uses, dropped.
    pub dropped_vertices: usize,
    /// Used vertices merged into an earlier one within `merge_tolerance`.
    pub merged_vertices: usize,
    /// Simplices with the same corner positions as an earlier one, dropped.
    pub duplicate_elements: usize,
    /// Connected pieces (bodies) of the mesh.
    pub pieces: usize,
}

impl ImportReport {
    /// Number of ignored elements of all types.
    pub fn ignored_count(&self) -> usize {
        self.ignored.values().sum()
    }
}

impl fmt::Display for ImportReport {
    /// One line: `cube.msh (gmsh MSH 4.1 ASCII): 45 vertices, 100 tetrahedra,
    /// 1 piece; ignored 84 triangles, 24 lines, 8 points; ...`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let simplex = if self.dimension == 2 {
            "triangle"
        } else {
            "tetrahedron"
        };
        write!(
            f,
            "{} ({}): {} {}, {} {}, {} {}",
            self.path.display(),
            self.format,
            self.vertices,
            plural("vertex", self.vertices),
            self.elements,
            plural(simplex, self.elements),
            self.pieces,
            plural("piece", self.pieces)
        )?;
        if !self.ignored.is_empty() {
            write!(f, "; ignored {}", describe_counts(&self.ignored))?;
        }
        if self.reoriented > 0 {
            write!(f, "; re-oriented {} inverted", self.reoriented)?;
        }
        if self.dropped_vertices > 0 {
            write!(
                f,
                "; dropped {} unreferenced {}",
                self.dropped_vertices,
                plural("vertex", self.dropped_vertices)
            )?;
        }
        if self.merged_vertices > 0 {
            write!(
                f,
                "; merged {} duplicate {}",
                self.merged_vertices,
                plural("vertex", self.merged_vertices)
            )?;
        }
        if self.duplicate_elements > 0 {
            let simplex = if self.dimension == 2 {
                "triangle"
            } else {
                "tetrahedron"
            };
            write!(
                f,
                "; dropped {} duplicate {} (the same corners as an earlier one)",
                self.duplicate_elements,
                plural(simplex, self.duplicate_elements)
            )?;
        }
        Ok(())
    }
}

/// Cleans an imported mesh into a [`Mesh`] and reports what it did.
///
/// The steps, in this order:
/// 1. every vertex is transformed: `x' = R_z R_y R_x (s x) + t`, i.e. scaled by
///    `scale`, rotated by `rotate[0]` degrees about x, then `rotate[1]` about y,
///    then `rotate[2]` about z (right-handed, counter-clockwise seen from the
///    positive axis), then translated by `translate`; a used vertex beyond
///    the renderer's `±3.4e38` (in the file or after the transforms) is an
///    error naming it;
/// 2. with `merge_tolerance > 0`, each used vertex closer than the tolerance
///    (after the transforms, in scene length units) to an earlier kept vertex
///    is merged into the earliest such one (a spatial hash with cells of the
///    tolerance's size: linear time; merging does not chain);
/// 3. each simplex's signed volume `det D_m / d!` is checked: one whose
///    magnitude is at most `1e-12` times the product of its edge lengths
///    over `d!` (the threshold of [`Mesh::new`]) is degenerate, an error naming
///    it; a negative one is re-oriented by swapping its second and third
///    vertices, unless `orient = false`, where it is an error;
/// 4. a simplex whose corners are at the same positions as an earlier
///    one's (in any order: the same element listed twice, or a piece of
///    the file repeated with vertices of its own) is dropped and counted,
///    so that no mass or stiffness is counted twice;
/// 5. vertices that no simplex uses are dropped;
/// 6. connected pieces (simplices sharing a vertex belong to one piece) are
///    counted: several pieces are fine, they are several bodies.
pub fn clean<const D: usize>(
    imported: ImportedMesh,
    options: &ImportOptions<D>,
) -> Result<(Mesh<D>, ImportReport), MeshImportError> {
    validate(options)?;
    if imported.dimension != D {
        return Err(MeshImportError::InvalidOption {
            key: "dimension",
            reason: format!(
                "the file was read as a {}D mesh but is cleaned as a {D}D one",
                imported.dimension
            ),
        });
    }
    let path = imported.path.clone();
    let rotation = rotation(options.rotate);
    let points: Vec<Vector<D>> = imported
        .points
        .iter()
        .map(|p| options.place_rotated(&rotation, *p))
        .collect();
    let n = points.len();
    let mut used = vec![false; n];
    for &v in &imported.simplices {
        used[v] = true;
    }
    // Coordinates beyond f32's range: every edge length and volume computed
    // from them overflows, so this is said before any element is judged.
    let limit = f64::from(f32::MAX);
    if let Some((v, value)) = (0..n).filter(|&v| used[v]).find_map(|v| {
        points[v]
            .iter()
            .find(|x| !(x.abs() <= limit))
            .map(|&x| (v, x))
    }) {
        let in_file = imported.points[v].iter().any(|x| !(x.abs() <= limit));
        return Err(MeshImportError::OutOfRange {
            path,
            vertex: imported.point_labels[v],
            value,
            after: if in_file {
                ""
            } else {
                " after scale, rotate and translate"
            },
        });
    }
    let (representative, merged_vertices) = if options.merge_tolerance > 0.0 {
        merge_close(&points, &used, options.merge_tolerance)
    } else {
        ((0..n).collect(), 0)
    };

    let nodes = D + 1;
    let mut simplices: Vec<Vec<usize>> = Vec::with_capacity(imported.simplex_count());
    let mut reoriented = 0;
    let mut seen_corners = std::collections::HashSet::with_capacity(imported.simplex_count());
    let mut duplicate_elements = 0;
    for e in 0..imported.simplex_count() {
        let original = imported.simplex(e);
        let mut simplex: Vec<usize> = original.iter().map(|&v| representative[v]).collect();
        let dm = edge_matrix(&points, &simplex);
        let volume = determinant(&dm) / factorial(D);
        let size = (0..D).map(|c| dm.column(c).norm()).product::<f64>() / factorial(D);
        let labels = || original.iter().map(|&v| imported.point_labels[v]).collect();
        if !(volume.abs() > 1e-12 * size) {
            return Err(MeshImportError::Degenerate {
                path,
                element: imported.simplex_labels[e],
                vertices: labels(),
                volume,
            });
        }
        if volume < 0.0 {
            if !options.orient {
                return Err(MeshImportError::Inverted {
                    path,
                    element: imported.simplex_labels[e],
                    vertices: labels(),
                    volume,
                });
            }
            simplex.swap(1, 2);
            reoriented += 1;
        }
        if !seen_corners.insert(corner_key(&points, &simplex)) {
            duplicate_elements += 1;
            continue;
        }
        debug_assert_eq!(simplex.len(), nodes);
        simplices.push(simplex);
    }

    // Keep the vertices the simplices use, in file order.
    let mut new_index = vec![usize::MAX; n];
    let mut positions = Vec::new();
    for simplex in &simplices {
        for &v in simplex {
            new_index[v] = 0;
        }
    }
    for v in 0..n {
        if new_index[v] == 0 {
            new_index[v] = positions.len();
            positions.push(points[v]);
        }
    }
    for simplex in &mut simplices {
        for v in simplex.iter_mut() {
            *v = new_index[*v];
        }
    }
    // Every file vertex is kept, merged into another, or dropped (unused,
    // or used only by duplicate simplices).
    let dropped_vertices = n.saturating_sub(positions.len() + merged_vertices);
    let pieces = count_pieces(positions.len(), &simplices);
    let mesh = Mesh::new(positions, simplices).map_err(|source| MeshImportError::Mesh {
        path: path.clone(),
        source,
    })?;
    let report = ImportReport {
        path,
        format: imported.format,
        dimension: D,
        vertices: mesh.vertex_count(),
        elements: mesh.element_count(),
        ignored: imported.ignored,
        reoriented,
        dropped_vertices,
        merged_vertices,
        duplicate_elements,
        pieces,
    };
    Ok((mesh, report))
}

/// A simplex's corner positions as exact bit patterns, sorted: equal for
/// two simplices with the same corners in any order.
fn corner_key<const D: usize>(points: &[Vector<D>], simplex: &[usize]) -> Vec<[u64; 3]> {
    let mut corners: Vec<[u64; 3]> = simplex
        .iter()
        .map(|&v| {
            let mut bits = [0; 3];
            for (b, x) in bits.iter_mut().zip(points[v].iter()) {
                // +0 and -0 are one position.
                *b = (x + 0.0).to_bits();
            }
            bits
        })
        .collect();
    corners.sort_unstable();
    corners
}

fn validate<const D: usize>(options: &ImportOptions<D>) -> Result<(), MeshImportError> {
    let invalid = |key, reason: String| Err(MeshImportError::InvalidOption { key, reason });
    if !(options.scale > 0.0) || !options.scale.is_finite() {
        return invalid(
            "scale",
            format!("must be a finite number > 0, got {}", options.scale),
        );
    }
    if !(options.merge_tolerance >= 0.0) || !options.merge_tolerance.is_finite() {
        return invalid(
            "merge_tolerance",
            format!(
                "must be a finite number >= 0, got {}",
                options.merge_tolerance
            ),
        );
    }
    if options.rotate.iter().any(|a| !a.is_finite()) {
        return invalid(
            "rotate",
            format!("angles must be finite, got {:?}", options.rotate),
        );
    }
    if D == 2 && (options.rotate[0] != 0.0 || options.rotate[1] != 0.0) {
        return invalid(
            "rotate",
            format!(
                "a 2D mesh turns only about z: the x and y angles must be 0, got {:?}",
                options.rotate
            ),
        );
    }
    if options.translate.iter().any(|t| !t.is_finite()) {
        return invalid(
            "translate",
            format!("must be finite, got {:?}", options.translate.as_slice()),
        );
    }
    Ok(())
}

impl<const D: usize> ImportOptions<D> {
    /// `x' = R_z R_y R_x (s x) + t` of a point `x` (z = 0 in 2D).
    pub fn place(&self, x: &Vector<D>) -> Vector<D> {
        self.place_point(std::array::from_fn(|i| if i < D { x[i] } else { 0.0 }))
    }

    /// `x' = R_z R_y R_x (s x) + t` of a file's point `x` (its first `D`
    /// coordinates after the rotation).
    pub fn place_point(&self, x: [f64; 3]) -> Vector<D> {
        self.place_rotated(&rotation(self.rotate), x)
    }

    fn place_rotated(&self, rotation: &Matrix<3>, p: [f64; 3]) -> Vector<D> {
        let q = rotation * (self.scale * Vector::<3>::new(p[0], p[1], p[2]));
        Vector::<D>::from_fn(|i, _| q[i]) + self.translate
    }
}

/// `R_z R_y R_x` for angles in degrees about x, y and z.
fn rotation(degrees: [f64; 3]) -> Matrix<3> {
    let [x, y, z] = degrees.map(f64::to_radians);
    let (sx, cx) = x.sin_cos();
    let (sy, cy) = y.sin_cos();
    let (sz, cz) = z.sin_cos();
    let rx = Matrix::<3>::new(1.0, 0.0, 0.0, 0.0, cx, -sx, 0.0, sx, cx);
    let ry = Matrix::<3>::new(cy, 0.0, sy, 0.0, 1.0, 0.0, -sy, 0.0, cy);
    let rz = Matrix::<3>::new(cz, -sz, 0.0, sz, cz, 0.0, 0.0, 0.0, 1.0);
    rz * ry * rx
}

/// Maps each used vertex to the earliest used vertex within `tolerance`
/// (itself when there is none), and counts the merged ones. Representatives
/// are hashed by the grid cell of side `tolerance` they fall in, so only the
/// 3^D cells around a vertex are searched.
fn merge_close<const D: usize>(
    points: &[Vector<D>],
    used: &[bool],
    tolerance: f64,
) -> (Vec<usize>, usize) {
    let cell = |p: &Vector<D>| -> [i64; D] {
        // `as` saturates: far-away points share the extreme cells, which
        // only costs time, never a wrong merge (distances are checked).
        std::array::from_fn(|i| (p[i] / tolerance).floor() as i64)
    };
    let mut grid: HashMap<[i64; D], Vec<usize>> = HashMap::new();
    let mut representative: Vec<usize> = (0..points.len()).collect();
    let mut merged = 0;
    let neighbours = 3usize.pow(D as u32);
    for (i, p) in points.iter().enumerate() {
        if !used[i] {
            continue;
        }
        let home = cell(p);
        let mut found: Option<usize> = None;
        for k in 0..neighbours {
            let mut key = home;
            let mut code = k;
            for axis in key.iter_mut() {
                *axis = axis.saturating_add((code % 3) as i64 - 1);
                code /= 3;
            }
            if let Some(candidates) = grid.get(&key) {
                for &j in candidates {
                    if (points[j] - p).norm() <= tolerance && found.is_none_or(|f| j < f) {
                        found = Some(j);
                    }
                }
            }
        }
        match found {
            Some(j) => {
                representative[i] = j;
                merged += 1;
            }
            None => grid.entry(home).or_default().push(i),
        }
    }
    (representative, merged)
}

/// Connected components of the vertex graph of `simplices`.
fn count_pieces(vertex_count: usize, simplices: &[Vec<usize>]) -> usize {
    let mut parent: Vec<usize> = (0..vertex_count).collect();
    fn root(parent: &mut [usize], mut v: usize) -> usize {
        while parent[v] != v {
            parent[v] = parent[parent[v]];
            v = parent[v];
        }
        v
    }
    for simplex in simplices {
        let a = root(&mut parent, simplex[0]);
        for &v in &simplex[1..] {
            let b = root(&mut parent, v);
            if a != b {
                parent[b] = a;
            }
        }
    }
    (0..vertex_count).filter(|&v| parent[v] == v).count()
}

fn factorial(n: usize) -> f64 {
    (1..=n).product::<usize>() as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn imported(points: Vec<[f64; 3]>, simplices: Vec<usize>, dimension: usize) -> ImportedMesh {
        let count = simplices.len() / (dimension + 1);
        ImportedMesh {
            path: PathBuf::from("m.mesh"),
            format: "test".into(),
            dimension,
            point_labels: (1..=points.len() as i64).collect(),
            points,
            simplices,
            simplex_labels: (1..=count as i64).collect(),
            ignored: BTreeMap::new(),
        }
    }

    fn unit_tet() -> Vec<[f64; 3]> {
        vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    }

    #[test]
    fn rotations_apply_about_x_then_y_then_z() {
        // (0, 1, 0) about x by 90° -> (0, 0, 1); about y by 90° -> (1, 0, 0);
        // about z by 90° -> (0, 1, 0).
        let r = rotation([90.0, 90.0, 90.0]);
        let p = r * Vector::<3>::new(0.0, 1.0, 0.0);
        assert_relative_eq!(p, Vector::<3>::new(0.0, 1.0, 0.0), epsilon = 1e-15);
        // Order matters: x then y sends (0, 0, 1) to (0, -1, 0) then stays.
        let q = rotation([90.0, 90.0, 0.0]) * Vector::<3>::new(0.0, 0.0, 1.0);
        assert_relative_eq!(q, Vector::<3>::new(0.0, -1.0, 0.0), epsilon = 1e-15);
    }

    #[test]
    fn scale_rotate_translate_reach_the_mesh_and_keep_orientation() {
        let options = ImportOptions::<3> {
            scale: 2.0,
            rotate: [0.0, 0.0, 90.0],
            translate: Vector::<3>::new(10.0, 0.0, 0.0),
            ..Default::default()
        };
        let (mesh, report) = clean(imported(unit_tet(), vec![0, 1, 2, 3], 3), &options).unwrap();
        assert_relative_eq!(
            mesh.rest_positions()[1],
            Vector::<3>::new(10.0, 2.0, 0.0),
            epsilon = 1e-14
        );
        assert_relative_eq!(mesh.rest_volume(), 8.0 / 6.0, epsilon = 1e-14);
        assert_eq!(report.reoriented, 0);
    }

    #[test]
    fn merging_is_linear_and_takes_the_earliest_vertex() {
        // A row of points 0.01 apart: with tolerance 0.015 each merges into
        // its left neighbour's representative only if within reach of it.
        let points: Vec<Vector<1>> = (0..5).map(|i| Vector::<1>::new(i as f64 * 0.01)).collect();
        let (rep, merged) = merge_close(&points, &[true; 5], 0.015);
        assert_eq!(rep, vec![0, 0, 2, 2, 4]);
        assert_eq!(merged, 2);
    }

    #[test]
    fn two_separate_tetrahedra_are_two_pieces() {
        let mut points = unit_tet();
        points.extend(unit_tet().iter().map(|p| [p[0] + 5.0, p[1], p[2]]));
        let (_, report) = clean::<3>(
            imported(points, vec![0, 1, 2, 3, 4, 5, 6, 7], 3),
            &ImportOptions::default(),
        )
        .unwrap();
        assert_eq!(report.pieces, 2);
    }

    #[test]
    fn a_2d_mesh_cannot_turn_about_x() {
        let options = ImportOptions::<2> {
            rotate: [10.0, 0.0, 0.0],
            ..Default::default()
        };
        let points = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let err = clean(imported(points, vec![0, 1, 2], 2), &options).unwrap_err();
        assert!(
            matches!(err, MeshImportError::InvalidOption { key: "rotate", .. }),
            "{err}"
        );
    }
}
