//! `surfaces/`: each frame's boundary surface as OBJ or binary PLY, one file
//! per frame, for Blender's and Houdini's sequence importers.
//!
//! The boundary is [`Mesh::boundary_facets`]: the facets held by exactly one
//! simplex, oriented away from that simplex's remaining vertex. In 3D these
//! are triangles with outward normals (counter-clockwise seen from outside).
//! In 2D they are edges, written as two-point polylines (OBJ `l`, PLY
//! `edge` elements) rather than extruded into a strip: the curve is the
//! exact boundary, any extrusion depth would be made up, and both Blender and
//! Houdini extrude or sweep a curve in one step. Each edge runs with the body
//! on its left, so outer boundaries run counter-clockwise and holes clockwise.
//! Only the vertices on the boundary are written, renumbered in mesh order.
//!
//! The render field, given per element, becomes a per-vertex value: the mean
//! over the elements that hold the vertex. Binary PLY stores it as a `float`
//! vertex property named after the field (characters other than letters,
//! digits and `_` become `_`); OBJ has no per-vertex scalar, so OBJ files
//! carry geometry only. Coordinates are written as 32-bit floats (PLY
//! `float`, and OBJ numbers printed from the same `f32`), z = 0 in 2D.
//!
//! File names follow the frames': `frame_0042.png` is `surface_0042.obj`
//! (the same number of digits, see [`crate::encode::frame_file_name`]). Each
//! file is written under a hidden temporary name and renamed when complete.
//! PLY is written by hand: a header and two little-endian arrays is all the
//! format needs, where the `ply-rs-bw` crate would build a map per vertex
//! (the tests read the files back with `ply-rs-bw`).

use super::{OutputError, format_number};
use crate::encode::write_whole_file;
use crate::math::Vector;
use crate::mesh::{Mesh, SurfaceMesh};
use std::fmt::{self, Write as _};
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// The file format of a surface sequence.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SurfaceFormat {
    /// Wavefront OBJ (text; geometry only).
    Obj,
    /// Binary little-endian PLY (with the field as a vertex property).
    Ply,
}

impl SurfaceFormat {
    /// The file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            SurfaceFormat::Obj => "obj",
            SurfaceFormat::Ply => "ply",
        }
    }
}

impl fmt::Display for SurfaceFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.extension())
    }
}

impl FromStr for SurfaceFormat {
    type Err = String;

    /// `obj` or `ply` (any case).
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "obj" => Ok(SurfaceFormat::Obj),
            "ply" => Ok(SurfaceFormat::Ply),
            _ => Err(format!(
                "unknown surface format `{s}`: expected `obj` or `ply`"
            )),
        }
    }
}

/// The file name of frame `index`'s surface in a run of `frame_count`
/// frames: `surface_0042.obj` beside `frame_0042.png`.
pub fn surface_file_name(index: usize, frame_count: usize, format: SurfaceFormat) -> String {
    let frame = crate::encode::frame_file_name(index, frame_count);
    let number = frame.trim_start_matches("frame_").trim_end_matches(".png");
    format!("surface_{number}.{}", format.extension())
}

/// The file name of frame `index`'s obstacles in a run of `frame_count`
/// frames: `obstacles_0042.obj` beside `surface_0042.obj`.
pub fn obstacles_file_name(index: usize, frame_count: usize, format: SurfaceFormat) -> String {
    surface_file_name(index, frame_count, format).replacen("surface_", "obstacles_", 1)
}

/// The boundary of a mesh, found once and written for any positions.
#[derive(Debug, Clone)]
pub struct Surface<const D: usize> {
    /// Outward boundary facets, as indices into `vertices`.
    facets: Vec<[usize; D]>,
    /// The mesh vertex of each surface vertex, in mesh order.
    vertices: Vec<usize>,
    /// Elements around each surface vertex: `elements[offsets[i]..offsets[i + 1]]`.
    offsets: Vec<usize>,
    elements: Vec<usize>,
}

impl<const D: usize> Surface<D> {
    /// Finds the boundary of `mesh`.
    pub fn new(mesh: &Mesh<D>) -> Self {
        let boundary = mesh.boundary_facets();
        let mut surface_index = vec![usize::MAX; mesh.vertex_count()];
        for facet in &boundary {
            for &v in facet {
                surface_index[v] = 0;
            }
        }
        let mut vertices = Vec::new();
        for (v, index) in surface_index.iter_mut().enumerate() {
            if *index == 0 {
                *index = vertices.len();
                vertices.push(v);
            }
        }
        let facets = boundary
            .iter()
            .map(|facet| facet.map(|v| surface_index[v]))
            .collect();
        let mut counts = vec![0usize; vertices.len() + 1];
        for simplex in mesh.simplices() {
            for &v in simplex {
                if surface_index[v] != usize::MAX {
                    counts[surface_index[v] + 1] += 1;
                }
            }
        }
        let mut offsets = counts;
        for i in 1..offsets.len() {
            offsets[i] += offsets[i - 1];
        }
        let mut next = offsets.clone();
        let mut elements = vec![0; offsets[vertices.len()]];
        for (e, simplex) in mesh.simplices().enumerate() {
            for &v in simplex {
                if surface_index[v] != usize::MAX {
                    let s = surface_index[v];
                    elements[next[s]] = e;
                    next[s] += 1;
                }
            }
        }
        Self {
            facets,
            vertices,
            offsets,
            elements,
        }
    }

    /// The obstacles' surfaces as one surface (no field): obstacle after
    /// obstacle, the points of each that a facet uses; positions are then
    /// the obstacles' points, concatenated in the same order.
    pub fn of_obstacles(surfaces: &[&SurfaceMesh<D>]) -> Self {
        let (mut vertices, mut facets) = (Vec::new(), Vec::new());
        let mut offset = 0;
        for surface in surfaces {
            let mut index = vec![usize::MAX; surface.points().len()];
            for &p in surface.facets().iter().flatten() {
                index[p] = 0;
            }
            for (p, slot) in index.iter_mut().enumerate() {
                if *slot == 0 {
                    *slot = vertices.len();
                    vertices.push(offset + p);
                }
            }
            facets.extend(surface.facets().iter().map(|f| f.map(|p| index[p])));
            offset += surface.points().len();
        }
        Self {
            offsets: vec![0; vertices.len() + 1],
            elements: Vec::new(),
            facets,
            vertices,
        }
    }

    /// The outward boundary facets (triangles in 3D, edges in 2D), as indices
    /// into [`Self::vertices`].
    pub fn facets(&self) -> &[[usize; D]] {
        &self.facets
    }

    /// The mesh vertex of each surface vertex.
    pub fn vertices(&self) -> &[usize] {
        &self.vertices
    }

    /// Per surface vertex, the mean of `element_field` over the elements that
    /// hold the vertex.
    pub fn vertex_field(&self, element_field: &[f64]) -> Vec<f64> {
        (0..self.vertices.len())
            .map(|s| {
                let around = &self.elements[self.offsets[s]..self.offsets[s + 1]];
                around.iter().map(|&e| element_field[e]).sum::<f64>() / around.len() as f64
            })
            .collect()
    }

    /// The file content for mesh positions `positions` and an optional
    /// per-element field `(name, values)`.
    ///
    /// # Panics
    /// When `positions` or the field's values do not match the mesh.
    pub fn encode(
        &self,
        format: SurfaceFormat,
        positions: &[Vector<D>],
        field: Option<(&str, &[f64])>,
    ) -> Vec<u8> {
        if let Some(&last) = self.vertices.last() {
            assert!(last < positions.len(), "positions do not match the mesh");
        }
        let xyz = |s: usize| -> [f32; 3] {
            let p = positions[self.vertices[s]];
            std::array::from_fn(|i| if i < D { p[i] as f32 } else { 0.0 })
        };
        match format {
            SurfaceFormat::Obj => self.obj(xyz),
            SurfaceFormat::Ply => {
                let field = field.map(|(name, values)| {
                    assert!(
                        self.elements.iter().all(|&e| e < values.len()),
                        "field `{name}` needs one value per element"
                    );
                    (property_name(name), self.vertex_field(values))
                });
                self.ply(xyz, field)
            }
        }
    }

    fn obj(&self, xyz: impl Fn(usize) -> [f32; 3]) -> Vec<u8> {
        let mut s = String::new();
        let (what, keyword) = if D == 3 {
            ("outward triangles", "f")
        } else {
            ("boundary edges, body on the left", "l")
        };
        let _ = writeln!(
            s,
            "# elasto boundary surface: {} vertices, {} {what}",
            self.vertices.len(),
            self.facets.len()
        );
        for i in 0..self.vertices.len() {
            let [x, y, z] = xyz(i);
            let _ = writeln!(
                s,
                "v {} {} {}",
                format_number(x),
                format_number(y),
                format_number(z)
            );
        }
        for facet in &self.facets {
            s.push_str(keyword);
            for &v in facet {
                let _ = write!(s, " {}", v + 1);
            }
            s.push('\n');
        }
        s.into_bytes()
    }

    fn ply(&self, xyz: impl Fn(usize) -> [f32; 3], field: Option<(String, Vec<f64>)>) -> Vec<u8> {
        let mut header = String::from("ply\nformat binary_little_endian 1.0\n");
        header.push_str("comment elasto boundary surface\n");
        let _ = writeln!(header, "element vertex {}", self.vertices.len());
        header.push_str("property float x\nproperty float y\nproperty float z\n");
        if let Some((name, _)) = &field {
            let _ = writeln!(header, "property float {name}");
        }
        if D == 3 {
            let _ = writeln!(header, "element face {}", self.facets.len());
            header.push_str("property list uchar int vertex_indices\n");
        } else {
            let _ = writeln!(header, "element edge {}", self.facets.len());
            header.push_str("property int vertex1\nproperty int vertex2\n");
        }
        header.push_str("end_header\n");
        let per_vertex = 12 + if field.is_some() { 4 } else { 0 };
        let per_facet = 4 * D + usize::from(D == 3);
        let mut out = Vec::with_capacity(
            header.len() + per_vertex * self.vertices.len() + per_facet * self.facets.len(),
        );
        out.extend_from_slice(header.as_bytes());
        for i in 0..self.vertices.len() {
            for c in xyz(i) {
                out.extend_from_slice(&c.to_le_bytes());
            }
            if let Some((_, values)) = &field {
                out.extend_from_slice(&finite_f32(values[i]).to_le_bytes());
            }
        }
        for facet in &self.facets {
            if D == 3 {
                out.push(3);
            }
            for &v in facet {
                // A surface of more than 2^31 vertices is not a thing we write.
                out.extend_from_slice(&(v as i32).to_le_bytes());
            }
        }
        out
    }

    /// Writes one frame's surface to `path` (through a temporary file).
    pub fn write(
        &self,
        path: &Path,
        format: SurfaceFormat,
        positions: &[Vector<D>],
        field: Option<(&str, &[f64])>,
    ) -> Result<(), OutputError> {
        let bytes = self.encode(format, positions, field);
        write_whole_file(path, &bytes).map_err(OutputError::io("write", path))
    }
}

/// Writes one frame's boundary surface: `mesh` at `positions`, with an
/// optional per-element field `(name, values)` (PLY only), to `path`.
pub fn write_surface<const D: usize>(
    path: &Path,
    format: SurfaceFormat,
    mesh: &Mesh<D>,
    positions: &[Vector<D>],
    field: Option<(&str, &[f64])>,
) -> Result<(), OutputError> {
    Surface::new(mesh).write(path, format, positions, field)
}

/// Writes the surfaces of a run, one file per frame, into one folder.
#[derive(Debug)]
pub struct SurfaceSeriesWriter<const D: usize> {
    dir: PathBuf,
    format: SurfaceFormat,
    frame_count: usize,
    surface: Surface<D>,
    /// The obstacles' surface, and whether any obstacle moves (then it is
    /// written with every frame, else with frame 0 only).
    obstacles: Option<(Surface<D>, bool)>,
}

impl<const D: usize> SurfaceSeriesWriter<D> {
    /// Creates the folder and finds the boundary of `mesh` once.
    pub fn create(
        dir: &Path,
        mesh: &Mesh<D>,
        format: SurfaceFormat,
        frame_count: usize,
    ) -> Result<Self, OutputError> {
        std::fs::create_dir_all(dir).map_err(OutputError::io("create folder", dir))?;
        Ok(Self {
            dir: dir.to_owned(),
            format,
            frame_count,
            surface: Surface::new(mesh),
            obstacles: None,
        })
    }

    /// Also writes `obstacles_NNNN.obj|ply`: the obstacles' `surfaces`,
    /// with frame 0 only, or with every frame when one `moves`.
    pub fn with_obstacles(mut self, surfaces: &[&SurfaceMesh<D>], moves: bool) -> Self {
        if !surfaces.is_empty() {
            self.obstacles = Some((Surface::of_obstacles(surfaces), moves));
        }
        self
    }

    /// Writes frame `index`'s obstacles at `positions` (their points,
    /// concatenated), if the run has obstacles and they are written with
    /// this frame.
    pub fn write_obstacles(
        &self,
        index: usize,
        positions: &[Vector<D>],
    ) -> Result<(), OutputError> {
        match &self.obstacles {
            Some((surface, moves)) if index == 0 || *moves => {
                let name = obstacles_file_name(index, self.frame_count, self.format);
                surface.write(&self.dir.join(name), self.format, positions, None)
            }
            _ => Ok(()),
        }
    }

    /// Writes frame `index`'s surface at `positions`, with the optional
    /// per-element field, and returns its path.
    pub fn write_frame(
        &self,
        index: usize,
        positions: &[Vector<D>],
        field: Option<(&str, &[f64])>,
    ) -> Result<PathBuf, OutputError> {
        let path = self
            .dir
            .join(surface_file_name(index, self.frame_count, self.format));
        self.surface.write(&path, self.format, positions, field)?;
        Ok(path)
    }
}

/// A PLY property name from a field name: `energy-density` → `energy_density`.
fn property_name(name: &str) -> String {
    let cleaned: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if cleaned.is_empty() {
        "field".to_owned()
    } else {
        cleaned
    }
}

/// The value as `f32`, with infinities and NaN clamped to the largest finite
/// `f32` (as the VTU writer does) so that importers read plain numbers.
fn finite_f32(v: f64) -> f32 {
    let v = v as f32;
    if v.is_finite() {
        v
    } else {
        f32::MAX.copysign(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vector2;

    #[test]
    fn names_follow_the_frames() {
        assert_eq!(
            surface_file_name(42, 100, SurfaceFormat::Obj),
            "surface_0042.obj"
        );
        assert_eq!(
            surface_file_name(7, 10001, SurfaceFormat::Ply),
            "surface_00007.ply"
        );
        assert_eq!("PLY".parse::<SurfaceFormat>(), Ok(SurfaceFormat::Ply));
        assert!("stl".parse::<SurfaceFormat>().is_err());
    }

    #[test]
    fn a_2d_square_is_a_counter_clockwise_loop_of_edges() {
        let mesh =
            Mesh::<2>::axis_aligned_box(Vector2::zeros(), Vector2::new(1.0, 1.0), [1, 1]).unwrap();
        let surface = Surface::new(&mesh);
        assert_eq!(surface.facets().len(), 4);
        // Shoelace over the edges: +1 for a counter-clockwise unit square.
        let p = |s: usize| mesh.rest_positions()[surface.vertices()[s]];
        let area: f64 = surface
            .facets()
            .iter()
            .map(|[a, b]| 0.5 * (p(*a).x * p(*b).y - p(*b).x * p(*a).y))
            .sum();
        assert!((area - 1.0).abs() < 1e-15, "{area}");
        let obj =
            String::from_utf8(surface.encode(SurfaceFormat::Obj, mesh.rest_positions(), None))
                .unwrap();
        assert_eq!(obj.lines().filter(|l| l.starts_with("l ")).count(), 4);
        assert!(obj.contains("v 1 1 0\n"), "{obj}");
    }

    #[test]
    fn the_field_is_averaged_over_the_elements_around_a_vertex() {
        // Two triangles; the corner (0, 0) is in both, (1, 0) in one of them.
        let mesh =
            Mesh::<2>::axis_aligned_box(Vector2::zeros(), Vector2::new(1.0, 1.0), [1, 1]).unwrap();
        let surface = Surface::new(&mesh);
        let values = [1.0, 3.0];
        let field = surface.vertex_field(&values);
        for (s, &v) in surface.vertices().iter().enumerate() {
            let around: Vec<f64> = mesh
                .simplices()
                .zip(values)
                .filter(|(simplex, _)| simplex.contains(&v))
                .map(|(_, value)| value)
                .collect();
            let mean = around.iter().sum::<f64>() / around.len() as f64;
            assert_eq!(field[s], mean);
        }
        assert!(field.contains(&2.0) && (field.contains(&1.0) || field.contains(&3.0)));
        assert_eq!(property_name("energy-density"), "energy_density");
        assert_eq!(finite_f32(f64::INFINITY), f32::MAX);
    }
}
