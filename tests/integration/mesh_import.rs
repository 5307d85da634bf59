//! Mesh files in: every format read back against known meshes (the fixtures
//! in `tests/data/meshes/`, made by `make_fixtures.py` there), the cleaning
//! rules, the shipped meshes, the VTU round trip, and a clear error or notice
//! for each kind of bad file.

use elasto::math::{Vector, Vector3};
use elasto::mesh::Mesh;
use elasto::mesh_io::{
    ImportOptions, ImportReport, Location, MeshImportError, clean, load_mesh, read_mesh,
};
use elasto::output::MeshSeriesWriter;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The unit cube of the fixtures: 45 vertices, 100 tetrahedra, and in the
/// gmsh files also 84 boundary triangles, 24 lines and 8 points.
const CUBE_VERTICES: usize = 45;
const CUBE_TETRAHEDRA: usize = 100;
/// The unit square of the fixtures: 20 vertices, 26 triangles.
const SQUARE_VERTICES: usize = 20;
const SQUARE_TRIANGLES: usize = 26;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/meshes")
        .join(name)
}

fn shipped(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/meshes")
        .join(name)
}

fn counts(pairs: &[(&str, usize)]) -> BTreeMap<String, usize> {
    pairs.iter().map(|&(k, n)| (k.to_owned(), n)).collect()
}

fn load3(path: &Path) -> (Mesh<3>, ImportReport) {
    load_mesh::<3>(path, &ImportOptions::default())
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Writes `text` to a file named `name` in a fresh folder.
fn write_temp(dir: &tempfile::TempDir, name: &str, text: impl AsRef<[u8]>) -> PathBuf {
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Every element of a mesh has positive rest volume (`Mesh::new` checks it;
/// this states it for the imported meshes).
fn all_positive<const D: usize>(mesh: &Mesh<D>) -> bool {
    mesh.rest_elements().iter().all(|e| e.volume > 0.0)
}

#[test]
fn every_format_reads_the_unit_cube() {
    let gmsh_extras = counts(&[("triangle", 84), ("line", 24), ("point", 8)]);
    let cases = [
        (
            "cube_v2_ascii.msh",
            "gmsh MSH 2.2 ASCII",
            0,
            gmsh_extras.clone(),
        ),
        (
            "cube_v2_binary.msh",
            "gmsh MSH 2.2 binary",
            0,
            gmsh_extras.clone(),
        ),
        (
            "cube_v41_ascii.msh",
            "gmsh MSH 4.1 ASCII",
            0,
            gmsh_extras.clone(),
        ),
        ("cube_v41_binary.msh", "gmsh MSH 4.1 binary", 0, gmsh_extras),
        (
            "cube.mesh",
            "MEDIT 2 ASCII",
            0,
            counts(&[("triangle", 84), ("line", 24)]),
        ),
        // Every tetrahedron of the TetGen files has the other winding.
        (
            "cube.node",
            "TetGen .node/.ele",
            CUBE_TETRAHEDRA,
            counts(&[]),
        ),
        (
            "cube.ele",
            "TetGen .node/.ele",
            CUBE_TETRAHEDRA,
            counts(&[]),
        ),
        (
            "cube.vtu",
            "VTK XML unstructured grid",
            0,
            counts(&[("triangle", 84)]),
        ),
    ];
    for (file, format, reoriented, ignored) in cases {
        let (mesh, report) = load3(&data(file));
        assert_eq!(report.format, format, "{file}");
        assert_eq!(mesh.vertex_count(), CUBE_VERTICES, "{file}");
        assert_eq!(mesh.element_count(), CUBE_TETRAHEDRA, "{file}");
        assert!(
            (mesh.rest_volume() - 1.0).abs() < 1e-12,
            "{file}: volume {}",
            mesh.rest_volume()
        );
        assert!(all_positive(&mesh), "{file}");
        assert_eq!(report.reoriented, reoriented, "{file}");
        assert_eq!(report.ignored, ignored, "{file}");
        assert_eq!(
            (
                report.pieces,
                report.dropped_vertices,
                report.merged_vertices
            ),
            (1, 0, 0),
            "{file}"
        );
    }
}

#[test]
fn ascii_and_binary_msh_files_of_both_versions_give_the_same_mesh() {
    // Same encoding, other version: bit for bit the same.
    let ascii = read_mesh(&data("cube_v41_ascii.msh"), 3).unwrap();
    let binary = read_mesh(&data("cube_v41_binary.msh"), 3).unwrap();
    for (file, reference) in [
        ("cube_v2_ascii.msh", &ascii),
        ("cube_v2_binary.msh", &binary),
    ] {
        let other = read_mesh(&data(file), 3).unwrap();
        assert_eq!(other.points, reference.points, "{file}");
        assert_eq!(other.point_labels, reference.point_labels, "{file}");
        assert_eq!(other.simplices, reference.simplices, "{file}");
        assert_eq!(other.simplex_labels, reference.simplex_labels, "{file}");
        assert_eq!(other.ignored, reference.ignored, "{file}");
    }
    // ASCII against binary: gmsh prints 16 significant digits, so the last
    // bit of a coordinate may differ; the connectivity may not.
    assert_eq!(ascii.simplices, binary.simplices);
    assert_eq!(ascii.simplex_labels, binary.simplex_labels);
    assert_eq!(ascii.ignored, binary.ignored);
    assert_close(&ascii.points, &binary.points, 1e-15);
    // The other formats list the same vertices in gmsh's order (gmsh's
    // MEDIT writer prints fewer digits).
    for file in ["cube.mesh", "cube.node", "cube.vtu"] {
        let other = read_mesh(&data(file), 3).unwrap();
        assert_close(&other.points, &binary.points, 1e-12);
    }
}

fn assert_close(a: &[[f64; 3]], b: &[[f64; 3]], tolerance: f64) {
    assert_eq!(a.len(), b.len());
    for (p, q) in a.iter().zip(b) {
        for k in 0..3 {
            assert!((p[k] - q[k]).abs() <= tolerance, "{p:?} vs {q:?}");
        }
    }
}

#[test]
fn the_2d_square_reads_from_msh_and_triangle_files() {
    for (file, ignored) in [
        (
            "square_v41_ascii.msh",
            counts(&[("line", 12), ("point", 4)]),
        ),
        ("square_v2_ascii.msh", counts(&[("line", 12), ("point", 4)])),
        ("square.node", counts(&[])),
    ] {
        let (mesh, report) = load_mesh::<2>(&data(file), &ImportOptions::default()).unwrap();
        assert_eq!(mesh.vertex_count(), SQUARE_VERTICES, "{file}");
        assert_eq!(mesh.element_count(), SQUARE_TRIANGLES, "{file}");
        assert!((mesh.rest_volume() - 1.0).abs() < 1e-12, "{file}");
        assert!(all_positive(&mesh), "{file}");
        assert_eq!(report.ignored, ignored, "{file}");
        assert!(report.to_string().contains("26 triangles"), "{report}");
    }
}

#[test]
fn a_mesh_of_the_wrong_dimension_is_named_as_such() {
    let err = read_mesh(&data("cube_v41_ascii.msh"), 2).unwrap_err();
    assert!(
        matches!(err, MeshImportError::NotTwoDimensional { count: 100, .. }),
        "{err}"
    );
    let err = read_mesh(&data("square_v41_ascii.msh"), 3).unwrap_err();
    assert!(
        err.to_string()
            .ends_with("square_v41_ascii.msh: the file holds no tetrahedra, only 26 triangles, 12 lines, 4 points"),
        "{err}"
    );
}

/// Two tetrahedra sharing the face (2, 3, 4), as MEDIT text; `extra`
/// vertices are appended after the five.
fn two_tets(first: &str, second: &str, extra: &str) -> String {
    format!(
        "MeshVersionFormatted 2\nDimension 3\nVertices\n{}\n\
         0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n1 1 1 0\n{extra}\
         Tetrahedra\n2\n{first} 0\n{second} 0\nEnd\n",
        5 + extra.lines().count()
    )
}

#[test]
fn a_flipped_element_is_reoriented_and_counted_unless_orient_is_off() {
    let dir = tempfile::tempdir().unwrap();
    // Element 2 = (2, 4, 3, 5) has negative volume; (2, 3, 4, 5) is positive.
    let path = write_temp(&dir, "flipped.mesh", two_tets("1 2 3 4", "2 4 3 5", ""));
    let (mesh, report) = load3(&path);
    assert_eq!(report.reoriented, 1);
    assert!(all_positive(&mesh));
    assert!((mesh.rest_volume() - (1.0 / 6.0 + 1.0 / 3.0)).abs() < 1e-15);
    assert!(
        report.to_string().contains("re-oriented 1 inverted"),
        "{report}"
    );

    let options = ImportOptions::<3> {
        orient: false,
        ..Default::default()
    };
    let err = load_mesh(&path, &options).unwrap_err();
    assert!(
        err.to_string().ends_with(
            "flipped.mesh: element 2 with vertices [2, 4, 3, 5] is inverted (signed volume -3.333e-1); re-orienting is off (`orient = false`)"
        ),
        "{err}"
    );
}

#[test]
fn a_degenerate_element_is_an_error_naming_it_and_its_vertices() {
    let dir = tempfile::tempdir().unwrap();
    // Vertex 6 lies in the plane of 1, 2, 3.
    let path = write_temp(
        &dir,
        "flat.mesh",
        two_tets("1 2 3 4", "1 2 3 6", "0.3 0.3 0 0\n"),
    );
    let err = load_mesh::<3>(&path, &ImportOptions::default()).unwrap_err();
    match &err {
        MeshImportError::Degenerate {
            element, vertices, ..
        } => {
            assert_eq!(*element, 2);
            assert_eq!(vertices, &vec![1, 2, 3, 6]);
        }
        other => panic!("expected a degenerate element, got {other}"),
    }
    assert!(
        err.to_string().ends_with(
            "flat.mesh: element 2 with vertices [1, 2, 3, 6] is degenerate (signed volume 0.000e0)"
        ),
        "{err}"
    );
}

#[test]
fn a_dangling_vertex_is_dropped_and_counted() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_temp(
        &dir,
        "dangling.mesh",
        two_tets("1 2 3 4", "2 3 4 5", "7 7 7 0\n"),
    );
    let (mesh, report) = load3(&path);
    assert_eq!(report.dropped_vertices, 1);
    assert_eq!(mesh.vertex_count(), 5);
    assert!(
        mesh.rest_positions()
            .iter()
            .all(|p| *p != Vector3::new(7.0, 7.0, 7.0))
    );
    assert!(
        report.to_string().contains("dropped 1 unreferenced vertex"),
        "{report}"
    );
}

#[test]
fn duplicate_vertices_are_merged_within_the_tolerance_only() {
    let dir = tempfile::tempdir().unwrap();
    // The second tetrahedron uses copies 6, 7, 8 of vertices 2, 3, 4, moved by
    // up to 1e-7: without merging, two pieces of 4 vertices each.
    let path = write_temp(
        &dir,
        "duplicates.mesh",
        two_tets(
            "1 2 3 4",
            "6 7 8 5",
            "1.0000001 0 0 0\n0 1 0.00000005 0\n0 0 0.9999999 0\n",
        ),
    );
    let (mesh, report) = load3(&path);
    assert_eq!(
        (mesh.vertex_count(), report.pieces, report.merged_vertices),
        (8, 2, 0)
    );

    let merge = |tolerance| {
        load_mesh::<3>(
            &path,
            &ImportOptions {
                merge_tolerance: tolerance,
                ..Default::default()
            },
        )
        .unwrap()
    };
    let (mesh, report) = merge(1e-6);
    assert_eq!(
        (mesh.vertex_count(), report.pieces, report.merged_vertices),
        (5, 1, 3)
    );
    // Merged into the earlier vertex: vertex 2 keeps its exact position.
    assert_eq!(mesh.rest_positions()[1], Vector3::new(1.0, 0.0, 0.0));
    assert!(mesh.simplex(1).contains(&1), "{:?}", mesh.simplex(1));
    // A tolerance below the offsets merges only the 5e-8 one.
    let (mesh, report) = merge(8e-8);
    assert_eq!((mesh.vertex_count(), report.merged_vertices), (7, 1));
}

#[test]
fn a_file_with_mixed_element_types_keeps_the_tetrahedra_and_counts_the_rest() {
    let dir = tempfile::tempdir().unwrap();
    let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n9\n\
        1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 0\n6 1 1 1\n7 0 1 1\n8 1 0 1\n9 0.5 0.5 0.5\n$EndNodes\n\
        $Elements\n8\n\
        1 15 1 1 1\n\
        2 1 1 1 1 2\n\
        3 3 1 1 1 2 5 3\n\
        4 5 1 1 1 2 5 3 4 8 6 7\n\
        5 6 1 1 1 2 3 4 8 7\n\
        6 4 1 1 1 2 3 4\n\
        7 11 1 1 1 2 3 4 9 9 9 9 9 9\n\
        8 4 1 1 2 5 3 6\n\
        $EndElements\n";
    let path = write_temp(&dir, "mixed.msh", text);
    let (mesh, report) = load3(&path);
    assert_eq!(mesh.element_count(), 2);
    assert_eq!(
        report.ignored,
        counts(&[
            ("point", 1),
            ("line", 1),
            ("quadrangle", 1),
            ("hexahedron", 1),
            ("prism", 1),
            ("10-node tetrahedron", 1),
        ])
    );
    assert_eq!(report.ignored_count(), 6);
    // Vertices only the ignored elements use are dropped: 7, 8 and 9.
    assert_eq!((mesh.vertex_count(), report.dropped_vertices), (6, 3));
}

/// Cuts a file to its first `fraction` of bytes.
fn cut(file: &str, fraction: f64) -> Vec<u8> {
    let bytes = std::fs::read(data(file)).unwrap();
    bytes[..(bytes.len() as f64 * fraction) as usize].to_vec()
}

#[test]
fn a_truncated_file_is_reported_as_truncated_in_every_format() {
    let dir = tempfile::tempdir().unwrap();
    for (file, fraction) in [
        ("cube_v2_ascii.msh", 0.5),
        ("cube_v2_binary.msh", 0.3),
        ("cube_v2_binary.msh", 0.8),
        ("cube_v41_ascii.msh", 0.5),
        ("cube_v41_binary.msh", 0.5),
        ("cube.mesh", 0.6),
        ("cube.vtu", 0.5),
    ] {
        let path = write_temp(&dir, file, cut(file, fraction));
        let err = read_mesh(&path, 3).unwrap_err();
        // A count the rest of the file cannot hold is found before reading on.
        assert!(
            matches!(
                err,
                MeshImportError::Truncated { .. } | MeshImportError::CountBeyondFile { .. }
            ),
            "{file} at {fraction}: {err}"
        );
        assert!(err.to_string().contains("the file is truncated"), "{err}");
    }
    // TetGen: the element file ends early.
    std::fs::copy(data("cube.node"), dir.path().join("cut.node")).unwrap();
    let path = write_temp(&dir, "cut.ele", cut("cube.ele", 0.5));
    let err = read_mesh(&path, 3).unwrap_err();
    match &err {
        MeshImportError::Truncated { path, location, .. }
        | MeshImportError::CountBeyondFile { path, location, .. } => {
            assert!(path.ends_with("cut.ele"));
            assert!(matches!(location, Location::Line(_)));
        }
        other => panic!("expected a truncation, got {other}"),
    }
    // ASCII truncation names the line and what was expected there.
    let path = write_temp(
        &dir,
        "lines.msh",
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 3 1 3\n2 1 0 3\n1\n2\n3\n0.0 0.0 0.0\n1.0 0.0",
    );
    assert_eq!(
        read_mesh(&path, 3).unwrap_err().to_string(),
        format!(
            "{}:11: the file is truncated: it ends where the coordinates of node 2 (node block 1) should be",
            path.display()
        )
    );
}

#[test]
fn a_file_that_is_not_a_mesh_is_named_as_such_in_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let png = b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR";
    for name in ["picture.msh", "picture.mesh", "picture.vtu", "picture.node"] {
        let path = write_temp(&dir, name, png);
        if name.ends_with(".node") {
            write_temp(&dir, "picture.ele", png);
        }
        let err = read_mesh(&path, 3).unwrap_err();
        assert!(
            matches!(err, MeshImportError::NotAMesh { .. }),
            "{name}: {err}"
        );
    }
    let path = write_temp(&dir, "notes.msh", "hello, this is not a mesh\n");
    assert_eq!(
        read_mesh(&path, 3).unwrap_err().to_string(),
        format!(
            "{}: not a gmsh MSH mesh: it does not start with `$MeshFormat`",
            path.display()
        )
    );
    let path = write_temp(
        &dir,
        "poly.vtu",
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\">\n<PolyData>\n\
         <Piece NumberOfPoints=\"0\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n\
         </Piece>\n</PolyData>\n</VTKFile>\n",
    );
    let err = read_mesh(&path, 3).unwrap_err();
    assert!(
        err.to_string().contains("not an unstructured grid"),
        "{err}"
    );
}

#[test]
fn other_bad_input_gets_its_own_message() {
    let dir = tempfile::tempdir().unwrap();
    let err = read_mesh(&dir.path().join("bunny.stl"), 3).unwrap_err();
    assert!(
        matches!(&err, MeshImportError::UnknownExtension { extension, .. } if extension == "stl"),
        "{err}"
    );
    let err = read_mesh(&dir.path().join("missing.msh"), 3).unwrap_err();
    assert!(matches!(err, MeshImportError::Io { .. }), "{err}");
    assert!(err.to_string().contains("missing.msh"), "{err}");
    // TetGen: the partner file is missing.
    std::fs::copy(data("cube.node"), dir.path().join("alone.node")).unwrap();
    let err = read_mesh(&dir.path().join("alone.node"), 3).unwrap_err();
    assert!(err.to_string().contains("alone.ele"), "{err}");
    // A vertex number the file does not define.
    let path = write_temp(
        &dir,
        "bad.msh",
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n\
         $Elements\n1\n12 4 0 1 2 3 44\n$EndElements\n",
    );
    assert_eq!(
        read_mesh(&path, 3).unwrap_err().to_string(),
        format!(
            "{}: element 12 refers to vertex 44, which the file does not define",
            path.display()
        )
    );
    // A word where a coordinate belongs, with its line.
    let path = write_temp(
        &dir,
        "word.mesh",
        "MeshVersionFormatted 2\nDimension 3\nVertices\n1\n0 zero 0 0\n",
    );
    assert_eq!(
        read_mesh(&path, 3).unwrap_err().to_string(),
        format!("{}:5: expected vertex 1 of 1, found `zero`", path.display())
    );
    // A 2D file off the plane z = 0.
    let path = write_temp(
        &dir,
        "tilted.mesh",
        "MeshVersionFormatted 2\nDimension 3\nVertices 3\n0 0 0 0\n1 0 0.5 0\n0 1 0 0\nTriangles 1\n1 2 3 0\n",
    );
    assert!(matches!(
        read_mesh(&path, 2).unwrap_err(),
        MeshImportError::NotPlanar { vertex: 2, .. }
    ));
    // An option out of range.
    let err = load_mesh::<3>(
        &data("cube.mesh"),
        &ImportOptions {
            scale: -1.0,
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(
        matches!(err, MeshImportError::InvalidOption { key: "scale", .. }),
        "{err}"
    );
}

#[test]
fn transforms_scale_then_rotate_then_translate() {
    let options = ImportOptions::<3> {
        scale: 2.0,
        rotate: [90.0, 0.0, 90.0],
        translate: Vector3::new(0.0, 5.0, 0.0),
        ..Default::default()
    };
    let (mesh, report) = load_mesh(&data("cube_v41_ascii.msh"), &options).unwrap();
    assert!((mesh.rest_volume() - 8.0).abs() < 1e-12);
    assert_eq!(report.reoriented, 0);
    // The cube [0, 2]^3 after x by 90° is [0,2] x [-2,0] x [0,2]; then z by
    // 90° sends (x, y) to (-y, x): [0, 2] x [0, 2] x [0, 2]; then up by 5.
    let (min, max) = bounds(mesh.rest_positions());
    assert!((min - Vector3::new(0.0, 5.0, 0.0)).norm() < 1e-12, "{min}");
    assert!((max - Vector3::new(2.0, 7.0, 2.0)).norm() < 1e-12, "{max}");
}

fn bounds<const D: usize>(points: &[Vector<D>]) -> (Vector<D>, Vector<D>) {
    let mut min = Vector::<D>::repeat(f64::INFINITY);
    let mut max = Vector::<D>::repeat(f64::NEG_INFINITY);
    for p in points {
        min = min.inf(p);
        max = max.sup(p);
    }
    (min, max)
}

#[test]
fn an_imported_mesh_survives_a_round_trip_through_the_vtu_writer() {
    let (mesh, _) = load3(&data("cube_v41_binary.msh"));
    let dir = tempfile::tempdir().unwrap();
    let mut writer = MeshSeriesWriter::create(dir.path()).unwrap();
    let field: Vec<f64> = (0..mesh.element_count()).map(|e| e as f64).collect();
    let path = writer
        .write_frame(0, 0.0, &mesh, mesh.rest_positions(), &[("j", &field)], &[])
        .unwrap();
    let (again, report) = load3(&path);
    assert_eq!(report.format, "VTK XML unstructured grid");
    assert_eq!(again.rest_positions(), mesh.rest_positions());
    assert_eq!(
        again.simplices().collect::<Vec<_>>(),
        mesh.simplices().collect::<Vec<_>>()
    );
    assert_eq!(again.rest_volume(), mesh.rest_volume());
    assert_eq!(report.reoriented, 0);

    // 2D too: the writer's z = 0 points come back as a 2D mesh.
    let (square, _) =
        load_mesh::<2>(&data("square_v41_ascii.msh"), &ImportOptions::default()).unwrap();
    let path = writer
        .write_frame(1, 0.1, &square, square.rest_positions(), &[], &[])
        .unwrap();
    let (again, _) = load_mesh::<2>(&path, &ImportOptions::default()).unwrap();
    assert_eq!(again.rest_positions(), square.rest_positions());
    assert_eq!(
        again.simplices().collect::<Vec<_>>(),
        square.simplices().collect::<Vec<_>>()
    );
}

#[test]
fn the_shipped_meshes_are_single_bodies_of_the_expected_size() {
    use std::f64::consts::PI;
    // (file, volume of the smooth shape, relative tolerance): the flat
    // facets cut the curved surface, more so on the torus's thin tube.
    for (file, volume, tolerance) in [
        ("sphere.msh", 4.0 / 3.0 * PI * 0.125, 0.03),
        ("torus.msh", 2.0 * PI * PI * 0.5 * 0.04, 0.05),
    ] {
        let (mesh, report) = load3(&shipped(file));
        assert_eq!(report.pieces, 1, "{file}");
        assert!(
            (300..=2500).contains(&mesh.element_count()),
            "{file}: {} tetrahedra",
            mesh.element_count()
        );
        let relative = (mesh.rest_volume() - volume).abs() / volume;
        assert!(
            relative < tolerance,
            "{file}: volume {} vs {volume}",
            mesh.rest_volume()
        );
        assert_eq!(report.ignored.get("tetrahedron"), None);
        assert!(
            report.ignored.get("triangle").is_some_and(|&n| n > 0),
            "{report}"
        );
    }
    let (bunny, report) = load3(&shipped("bunny.msh"));
    assert_eq!(report.pieces, 1);
    let (min, max) = bounds(bunny.rest_positions());
    assert!(min.y.abs() < 0.02 && max.y > 1.1, "{min} {max}");
    let (annulus, report) =
        load_mesh::<2>(&shipped("annulus.msh"), &ImportOptions::default()).unwrap();
    assert_eq!(report.pieces, 1);
    let area = PI * (0.25 - 0.04);
    assert!((annulus.rest_volume() - area).abs() / area < 0.01);
    for file in ["sphere.msh", "torus.msh", "bunny.msh", "annulus.msh"] {
        let size = std::fs::metadata(shipped(file)).unwrap().len();
        assert!(size < 300_000, "{file}: {size} bytes");
    }
}

#[test]
fn clean_can_be_called_on_a_mesh_read_separately() {
    let imported = read_mesh(&data("cube.node"), 3).unwrap();
    assert_eq!(imported.simplex_count(), CUBE_TETRAHEDRA);
    assert_eq!(imported.point_labels.first(), Some(&1));
    let (mesh, report) = clean::<3>(imported, &ImportOptions::default()).unwrap();
    assert_eq!(report.reoriented, CUBE_TETRAHEDRA);
    assert!((mesh.rest_volume() - 1.0).abs() < 1e-12);
}

#[test]
fn cut_or_corrupted_files_give_errors_never_panics() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(data("cube.node"), dir.path().join("c.node")).unwrap();
    let mut errors = 0;
    for file in [
        "cube_v2_ascii.msh",
        "cube_v2_binary.msh",
        "cube_v41_ascii.msh",
        "cube_v41_binary.msh",
        "cube.mesh",
        "cube.ele",
        "cube.vtu",
    ] {
        let original = std::fs::read(data(file)).unwrap();
        let name = if file == "cube.ele" {
            "c.ele".to_owned()
        } else {
            file.to_owned()
        };
        let path = dir.path().join(&name);
        let mut variants: Vec<Vec<u8>> = (0..original.len())
            .step_by(original.len() / 150 + 1)
            .map(|n| original[..n].to_vec())
            .collect();
        // Overwrite one byte at a time with digits, signs and junk.
        for (k, at) in (0..original.len())
            .step_by(original.len() / 150 + 1)
            .enumerate()
        {
            let mut bytes = original.clone();
            bytes[at] = b"9-x\xff\n0"[k % 6];
            variants.push(bytes);
        }
        for bytes in variants {
            std::fs::write(&path, &bytes).unwrap();
            if let Err(err) = load_mesh::<3>(&path, &ImportOptions::default()) {
                assert!(
                    err.to_string().contains(&name)
                        || matches!(err, MeshImportError::InvalidOption { .. }),
                    "{file}: the message does not name the file: {err}"
                );
                errors += 1;
            }
        }
    }
    assert!(
        errors > 1000,
        "only {errors} of the damaged files were refused"
    );
}
