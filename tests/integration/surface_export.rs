//! Surface sequences: the OBJ and PLY boundary of a box and of the shipped
//! meshes is closed (every edge in exactly two triangles, once each way) and
//! outward (the divergence theorem gives the body's volume, positive), the
//! 2D boundary is a set of loops with the body on the left, PLY files read
//! back with an independent reader (`ply-rs-bw`) and carry the field.

use elasto::math::{Vector2, Vector3};
use elasto::mesh::Mesh;
use elasto::mesh_io::{ImportOptions, load_mesh};
use elasto::output::{SurfaceFormat, SurfaceSeriesWriter, surface_file_name, write_surface};
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{DefaultElement, Property};
use std::collections::HashMap;
use std::path::Path;

/// Vertices and facets (0-based) of an OBJ file: `f` lines in 3D, `l` in 2D.
fn read_obj(text: &str) -> (Vec<[f64; 3]>, Vec<Vec<usize>>) {
    let mut vertices = Vec::new();
    let mut facets = Vec::new();
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let c: Vec<f64> = words.map(|w| w.parse().unwrap()).collect();
                vertices.push([c[0], c[1], c[2]]);
            }
            Some("f") | Some("l") => {
                facets.push(words.map(|w| w.parse::<usize>().unwrap() - 1).collect());
            }
            _ => {}
        }
    }
    (vertices, facets)
}

/// Vertices, facets and the named vertex property of a PLY file.
fn read_ply(path: &Path, property: Option<&str>) -> (Vec<[f64; 3]>, Vec<Vec<usize>>, Vec<f64>) {
    let mut file = std::fs::File::open(path).unwrap();
    let ply = Parser::<DefaultElement>::new().read_ply(&mut file).unwrap();
    let float = |p: &Property| match p {
        Property::Float(v) => *v as f64,
        other => panic!("expected a float, got {other:?}"),
    };
    let int = |p: &Property| match p {
        Property::Int(v) => *v as usize,
        other => panic!("expected an int, got {other:?}"),
    };
    let mut vertices = Vec::new();
    let mut field = Vec::new();
    for v in &ply.payload["vertex"] {
        vertices.push([float(&v["x"]), float(&v["y"]), float(&v["z"])]);
        if let Some(name) = property {
            field.push(float(&v[name]));
        }
    }
    let mut facets = Vec::new();
    if let Some(faces) = ply.payload.get("face") {
        for f in faces {
            match &f["vertex_indices"] {
                Property::ListInt(list) => facets.push(list.iter().map(|&i| i as usize).collect()),
                other => panic!("expected a list of ints, got {other:?}"),
            }
        }
    }
    if let Some(edges) = ply.payload.get("edge") {
        for e in edges {
            facets.push(vec![int(&e["vertex1"]), int(&e["vertex2"])]);
        }
    }
    (vertices, facets, field)
}

/// Asserts that the triangles form a closed, consistently oriented surface:
/// every directed edge appears exactly once and its reverse exactly once.
fn assert_closed(triangles: &[Vec<usize>]) {
    let mut directed: HashMap<(usize, usize), usize> = HashMap::new();
    for t in triangles {
        assert_eq!(t.len(), 3);
        for k in 0..3 {
            *directed.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    for (&(a, b), &n) in &directed {
        assert_eq!(n, 1, "edge ({a}, {b}) runs the same way in {n} triangles");
        assert_eq!(
            directed.get(&(b, a)),
            Some(&1),
            "edge ({a}, {b}) is not in exactly two triangles"
        );
    }
}

/// The volume enclosed by a triangle surface, by the divergence theorem:
/// `V = Σ (p0 · (p1 × p2)) / 6` over the triangles; positive when outward.
fn enclosed_volume(vertices: &[[f64; 3]], triangles: &[Vec<usize>]) -> f64 {
    let p = |i: usize| Vector3::from(vertices[i]);
    triangles
        .iter()
        .map(|t| p(t[0]).dot(&p(t[1]).cross(&p(t[2]))) / 6.0)
        .sum()
}

/// In 2D: every vertex starts exactly one edge and ends exactly one (closed
/// loops), and the shoelace area (positive with the body on the left).
fn loops_and_area(vertices: &[[f64; 3]], edges: &[Vec<usize>]) -> f64 {
    let mut starts = vec![0; vertices.len()];
    let mut ends = vec![0; vertices.len()];
    for e in edges {
        assert_eq!(e.len(), 2);
        starts[e[0]] += 1;
        ends[e[1]] += 1;
    }
    assert!(
        starts.iter().chain(&ends).all(|&n| n == 1),
        "not closed loops"
    );
    assert!(vertices.iter().all(|v| v[2] == 0.0));
    edges
        .iter()
        .map(|e| {
            let (a, b) = (vertices[e[0]], vertices[e[1]]);
            0.5 * (a[0] * b[1] - b[0] * a[1])
        })
        .sum()
}

/// A box of 2 x 3 x 2 cells, built like a scene's `[mesh] generator = "box"`,
/// and a deformed state of it: sheared and stretched (det 1.5).
fn box_3d() -> (Mesh<3>, Vec<Vector3>) {
    let mesh = Mesh::<3>::axis_aligned_box(
        Vector3::new(0.0, 1.0, 0.0),
        Vector3::new(1.0, 2.5, 0.5),
        [2, 3, 2],
    )
    .unwrap();
    let f = nalgebra::Matrix3::new(1.5, 0.3, 0.0, 0.0, 1.0, 0.2, 0.0, 0.0, 1.0);
    let positions = mesh.rest_positions().iter().map(|p| f * p).collect();
    (mesh, positions)
}

#[test]
fn the_obj_surface_of_a_box_is_closed_and_outward() {
    let (mesh, positions) = box_3d();
    let dir = tempfile::tempdir().unwrap();
    for (state, points, volume) in [
        ("rest", mesh.rest_positions().to_vec(), 0.75),
        ("deformed", positions, 0.75 * 1.5),
    ] {
        let path = dir.path().join(format!("{state}.obj"));
        write_surface(&path, SurfaceFormat::Obj, &mesh, &points, None).unwrap();
        let (vertices, triangles) = read_obj(&std::fs::read_to_string(&path).unwrap());
        // A box of 2 x 3 x 2 cells: 2 triangles per boundary cell face.
        assert_eq!(triangles.len(), 2 * 2 * (2 * 3 + 3 * 2 + 2 * 2));
        // Only the boundary vertices: all but the 1 x 2 x 1 interior ones.
        assert_eq!(vertices.len(), 3 * 4 * 3 - 2);
        assert_closed(&triangles);
        let enclosed = enclosed_volume(&vertices, &triangles);
        assert!(
            (enclosed - volume).abs() < 1e-6,
            "{state}: {enclosed} vs {volume}"
        );
    }
}

#[test]
fn the_ply_surface_of_a_box_is_closed_outward_and_carries_the_field() {
    let (mesh, positions) = box_3d();
    let dir = tempfile::tempdir().unwrap();
    let field: Vec<f64> = (0..mesh.element_count()).map(|e| e as f64).collect();
    let writer =
        SurfaceSeriesWriter::create(&dir.path().join("surfaces"), &mesh, SurfaceFormat::Ply, 120)
            .unwrap();
    let path = writer
        .write_frame(42, &positions, Some(("energy-density", &field)))
        .unwrap();
    assert_eq!(path, dir.path().join("surfaces/surface_0042.ply"));
    let (vertices, triangles, values) = read_ply(&path, Some("energy_density"));
    assert_closed(&triangles);
    assert!((enclosed_volume(&vertices, &triangles) - 1.125).abs() < 1e-6);
    // The field at each surface vertex is the mean over its elements: check
    // it against the mesh by matching positions.
    for (v, value) in vertices.iter().zip(&values) {
        let m = positions
            .iter()
            .position(|p| (p - Vector3::from(*v)).norm() < 1e-6)
            .unwrap();
        let around: Vec<f64> = mesh
            .simplices()
            .enumerate()
            .filter(|(_, s)| s.contains(&m))
            .map(|(e, _)| e as f64)
            .collect();
        let mean = around.iter().sum::<f64>() / around.len() as f64;
        assert!(
            (*value - mean).abs() < 1e-4 * mean.max(1.0),
            "{value} vs {mean}"
        );
    }
    // Without a field, no extra property.
    write_surface(&path, SurfaceFormat::Ply, &mesh, &positions, None).unwrap();
    let header = std::fs::read(&path).unwrap();
    let header = String::from_utf8_lossy(&header[..200]);
    assert!(header.starts_with("ply\nformat binary_little_endian 1.0\n"));
    assert!(!header.contains("energy"), "{header}");
}

#[test]
fn a_2d_box_boundary_is_a_counter_clockwise_loop_in_obj_and_ply() {
    let mesh = Mesh::<2>::axis_aligned_box(Vector2::new(0.0, 2.0), Vector2::new(2.0, 3.0), [4, 2])
        .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("box.obj");
    write_surface(&obj, SurfaceFormat::Obj, &mesh, mesh.rest_positions(), None).unwrap();
    let (vertices, edges) = read_obj(&std::fs::read_to_string(&obj).unwrap());
    assert_eq!(edges.len(), 2 * (4 + 2));
    assert!((loops_and_area(&vertices, &edges) - 2.0).abs() < 1e-12);

    let ply = dir.path().join("box.ply");
    let field = vec![0.5; mesh.element_count()];
    write_surface(
        &ply,
        SurfaceFormat::Ply,
        &mesh,
        mesh.rest_positions(),
        Some(("volume-ratio", &field)),
    )
    .unwrap();
    let (vertices, edges, values) = read_ply(&ply, Some("volume_ratio"));
    assert_eq!(edges.len(), 12);
    assert!((loops_and_area(&vertices, &edges) - 2.0).abs() < 1e-12);
    assert!(values.iter().all(|&v| v == 0.5));
}

#[test]
fn imported_meshes_have_closed_outward_surfaces_enclosing_their_volume() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().unwrap();
    for file in ["torus.msh", "bunny.msh"] {
        let (mesh, _) = load_mesh::<3>(
            &root.join("scenes/meshes").join(file),
            &ImportOptions::default(),
        )
        .unwrap();
        let path = dir.path().join("s.obj");
        write_surface(
            &path,
            SurfaceFormat::Obj,
            &mesh,
            mesh.rest_positions(),
            None,
        )
        .unwrap();
        let (vertices, triangles) = read_obj(&std::fs::read_to_string(&path).unwrap());
        assert_closed(&triangles);
        let enclosed = enclosed_volume(&vertices, &triangles);
        assert!(
            (enclosed - mesh.rest_volume()).abs() < 1e-5,
            "{file}: {enclosed} vs {}",
            mesh.rest_volume()
        );
    }
    // The annulus: an outer loop counter-clockwise, the hole clockwise.
    let (annulus, _) = load_mesh::<2>(
        &root.join("scenes/meshes/annulus.msh"),
        &ImportOptions::default(),
    )
    .unwrap();
    let path = dir.path().join("a.obj");
    write_surface(
        &path,
        SurfaceFormat::Obj,
        &annulus,
        annulus.rest_positions(),
        None,
    )
    .unwrap();
    let (vertices, edges) = read_obj(&std::fs::read_to_string(&path).unwrap());
    let area = loops_and_area(&vertices, &edges);
    assert!((area - annulus.rest_volume()).abs() < 1e-6, "{area}");
}

#[test]
fn surface_files_are_numbered_like_the_frames() {
    for (index, count) in [(0, 1), (42, 100), (9999, 10000), (7, 10001)] {
        let frame = elasto::encode::frame_file_name(index, count);
        let surface = surface_file_name(index, count, SurfaceFormat::Obj);
        assert_eq!(
            surface,
            frame.replace("frame_", "surface_").replace(".png", ".obj")
        );
    }
    let (mesh, positions) = box_3d();
    let dir = tempfile::tempdir().unwrap();
    let writer = SurfaceSeriesWriter::create(dir.path(), &mesh, SurfaceFormat::Obj, 3).unwrap();
    for frame in 0..3 {
        writer.write_frame(frame, &positions, None).unwrap();
    }
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["surface_0000.obj", "surface_0001.obj", "surface_0002.obj"]
    );
}
