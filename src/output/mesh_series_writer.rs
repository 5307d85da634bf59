//! `meshes/`: one VTK XML unstructured grid per frame and a ParaView collection.
//!
//! Each frame is `frame_NNNN.vtu` (ASCII, points always 3D with z = 0 in 2D,
//! triangles as VTK cell type 5 and tetrahedra as type 10, with per-element
//! scalars as cell data); `frames.pvd` lists them with `timestep` = the
//! frame's simulated time and is rewritten after every frame, so it is valid
//! even when a run stops early. Each file is written under a hidden
//! temporary name and renamed when complete, so a full disk leaves no cut
//! file under a final name. The format is small enough that a
//! hand-written writer is clearer than a dependency (the `vtkio` crate is
//! still a pre-release with a large dependency tree).

use super::OutputError;
use crate::encode::write_whole_file;
use crate::math::Vector;
use crate::mesh::Mesh;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Writes a series of meshes into one folder.
#[derive(Debug)]
pub struct MeshSeriesWriter {
    dir: PathBuf,
    entries: Vec<(f64, String)>,
}

impl MeshSeriesWriter {
    /// Creates the folder.
    pub fn create(dir: &Path) -> Result<Self, OutputError> {
        std::fs::create_dir_all(dir).map_err(OutputError::io("create folder", dir))?;
        Ok(Self {
            dir: dir.to_owned(),
            entries: Vec::new(),
        })
    }

    /// Writes `frame_NNNN.vtu` for the mesh at `positions` with the given
    /// per-element scalars and per-vertex vectors (3 components, z = 0 in
    /// 2D; e.g. `contact_force`), and updates `frames.pvd`.
    pub fn write_frame<const D: usize>(
        &mut self,
        frame: usize,
        time: f64,
        mesh: &Mesh<D>,
        positions: &[Vector<D>],
        cell_scalars: &[(&str, &[f64])],
        point_vectors: &[(&str, &[Vector<D>])],
    ) -> Result<PathBuf, OutputError> {
        let name = format!("frame_{frame:04}.vtu");
        let path = self.dir.join(&name);
        let grid = vtu(mesh, positions, cell_scalars, point_vectors);
        write_whole_file(&path, grid.as_bytes()).map_err(OutputError::io("write", &path))?;
        self.entries.push((time, name));
        let pvd_path = self.dir.join("frames.pvd");
        write_whole_file(&pvd_path, pvd(&self.entries).as_bytes())
            .map_err(OutputError::io("write", &pvd_path))?;
        Ok(path)
    }
}

/// The VTK cell type of a simplex in `d` dimensions.
fn cell_type(d: usize) -> u8 {
    match d {
        2 => 5,  // VTK_TRIANGLE
        3 => 10, // VTK_TETRA
        _ => panic!("no VTK simplex type for dimension {d}"),
    }
}

fn vtu<const D: usize>(
    mesh: &Mesh<D>,
    positions: &[Vector<D>],
    cell_scalars: &[(&str, &[f64])],
    point_vectors: &[(&str, &[Vector<D>])],
) -> String {
    let mut s = String::new();
    let n = D + 1;
    let cells = mesh.element_count();
    s.push_str("<?xml version=\"1.0\"?>\n");
    s.push_str("<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n");
    s.push_str("  <UnstructuredGrid>\n");
    let _ = writeln!(
        s,
        "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{cells}\">",
        positions.len()
    );
    s.push_str("      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for p in positions {
        let c = |i: usize| if i < D { p[i] } else { 0.0 };
        let _ = writeln!(s, "          {} {} {}", c(0), c(1), c(2));
    }
    s.push_str("        </DataArray>\n      </Points>\n      <Cells>\n");
    s.push_str("        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for simplex in mesh.simplices() {
        let ids: Vec<String> = simplex.iter().map(|v| v.to_string()).collect();
        let _ = writeln!(s, "          {}", ids.join(" "));
    }
    s.push_str("        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    for e in 0..cells {
        let _ = writeln!(s, "          {}", (e + 1) * n);
    }
    s.push_str("        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for _ in 0..cells {
        let _ = writeln!(s, "          {}", cell_type(D));
    }
    s.push_str("        </DataArray>\n      </Cells>\n");
    if let Some((first, _)) = point_vectors.first() {
        let _ = writeln!(s, "      <PointData Vectors=\"{first}\">");
        for (name, values) in point_vectors {
            assert_eq!(
                values.len(),
                positions.len(),
                "point data `{name}` needs one value per vertex"
            );
            let _ = writeln!(
                s,
                "        <DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"3\" format=\"ascii\">"
            );
            for p in values.iter() {
                let c = |i: usize| if i < D { p[i] } else { 0.0 };
                let _ = writeln!(s, "          {} {} {}", c(0), c(1), c(2));
            }
            s.push_str("        </DataArray>\n");
        }
        s.push_str("      </PointData>\n");
    }
    if let Some((first, _)) = cell_scalars.first() {
        let _ = writeln!(s, "      <CellData Scalars=\"{first}\">");
        for (name, values) in cell_scalars {
            assert_eq!(
                values.len(),
                cells,
                "cell data `{name}` needs one value per element"
            );
            let _ = writeln!(
                s,
                "        <DataArray type=\"Float64\" Name=\"{name}\" format=\"ascii\">"
            );
            for v in values.iter() {
                // Non-finite values are written as they are (`NaN`, `inf`,
                // `-inf`, which VTK's ASCII parser reads since VTK 9.1): an
                // element without a defined value must not stretch a colour
                // range to 1.8e308.
                let _ = writeln!(s, "          {v}");
            }
            s.push_str("        </DataArray>\n");
        }
        s.push_str("      </CellData>\n");
    }
    s.push_str("    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
    s
}

fn pvd(entries: &[(f64, String)]) -> String {
    let mut s = String::from("<?xml version=\"1.0\"?>\n");
    s.push_str("<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n");
    for (time, file) in entries {
        let _ = writeln!(
            s,
            "    <DataSet timestep=\"{time}\" group=\"\" part=\"0\" file=\"{file}\"/>"
        );
    }
    s.push_str("  </Collection>\n</VTKFile>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Vector2, Vector3};

    /// The numbers between `<DataArray ... Name="name" ...>` and `</DataArray>`.
    fn data_array(xml: &str, name: &str) -> Vec<f64> {
        let start = xml.find(&format!("Name=\"{name}\"")).unwrap();
        let body_start = start + xml[start..].find('>').unwrap() + 1;
        let body_end = body_start + xml[body_start..].find("</DataArray>").unwrap();
        xml[body_start..body_end]
            .split_whitespace()
            .map(|t| t.parse().unwrap())
            .collect()
    }

    #[test]
    fn triangles_are_written_with_3d_points_and_cell_type_5() {
        let mesh =
            Mesh::<2>::axis_aligned_box(Vector2::new(0.0, 0.0), Vector2::new(2.0, 1.0), [2, 1])
                .unwrap();
        let values: Vec<f64> = (0..mesh.element_count()).map(|e| e as f64 * 0.5).collect();
        let xml = vtu(
            &mesh,
            mesh.rest_positions(),
            &[("energy_density", &values)],
            &[],
        );
        assert!(xml.contains("NumberOfPoints=\"6\" NumberOfCells=\"4\""));
        let offsets = data_array(&xml, "offsets");
        assert_eq!(offsets, vec![3.0, 6.0, 9.0, 12.0]);
        assert_eq!(data_array(&xml, "types"), vec![5.0; 4]);
        let connectivity = data_array(&xml, "connectivity");
        let flat: Vec<f64> = mesh.simplices().flatten().map(|&v| v as f64).collect();
        assert_eq!(connectivity, flat);
        assert_eq!(data_array(&xml, "energy_density"), values);
        // The points block: 6 points of 3 coordinates, z = 0, last point (2, 1).
        let points_start = xml.find("NumberOfComponents=\"3\"").unwrap();
        let body = &xml[points_start + xml[points_start..].find('>').unwrap() + 1..];
        let coords: Vec<f64> = body[..body.find("</DataArray>").unwrap()]
            .split_whitespace()
            .map(|t| t.parse().unwrap())
            .collect();
        assert_eq!(coords.len(), 18);
        assert!(coords.iter().skip(2).step_by(3).all(|z| *z == 0.0));
        assert_eq!(&coords[15..], &[2.0, 1.0, 0.0]);
    }

    #[test]
    fn tetrahedra_use_cell_type_10_and_the_series_is_listed_in_the_pvd() {
        let mesh =
            Mesh::<3>::axis_aligned_box(Vector3::zeros(), Vector3::new(1.0, 1.0, 1.0), [1, 1, 1])
                .unwrap();
        let tmp = tempfile::tempdir().unwrap();
        let mut writer = MeshSeriesWriter::create(&tmp.path().join("meshes")).unwrap();
        let values = vec![1.0; mesh.element_count()];
        for frame in 0..3 {
            writer
                .write_frame(
                    frame,
                    frame as f64 / 30.0,
                    &mesh,
                    mesh.rest_positions(),
                    &[("j", &values)],
                    &[],
                )
                .unwrap();
        }
        let xml = std::fs::read_to_string(tmp.path().join("meshes/frame_0002.vtu")).unwrap();
        assert_eq!(data_array(&xml, "types"), vec![10.0; 6]);
        assert_eq!(data_array(&xml, "offsets").last(), Some(&24.0));
        let pvd = std::fs::read_to_string(tmp.path().join("meshes/frames.pvd")).unwrap();
        assert_eq!(pvd.matches("<DataSet ").count(), 3);
        assert!(pvd.contains(&format!(
            "timestep=\"{}\" group=\"\" part=\"0\" file=\"frame_0001.vtu\"",
            1.0 / 30.0
        )));
    }

    /// Regression: non-finite element values were written as `f64::MAX`, so
    /// one bad element stretched ParaView's colour range to 1.8e308.
    #[test]
    fn non_finite_element_values_are_written_as_nan_and_inf() {
        let mesh =
            Mesh::<2>::axis_aligned_box(Vector2::new(0.0, 0.0), Vector2::new(2.0, 1.0), [2, 1])
                .unwrap();
        let values = [0.5, f64::NAN, f64::INFINITY, f64::NEG_INFINITY];
        let xml = vtu(&mesh, mesh.rest_positions(), &[("von_mises", &values)], &[]);
        let written = data_array(&xml, "von_mises");
        assert_eq!(written[0], 0.5);
        assert!(written[1].is_nan());
        assert_eq!(&written[2..], &[f64::INFINITY, f64::NEG_INFINITY]);
        assert!(!xml.contains(&f64::MAX.to_string()));
    }
}
