//! Mesh files in scenes (`[mesh] generator = "file"`), `--save-surface` and
//! several bodies (`[[bodies]]`), through the real binary, plus the bodies'
//! masses and momentum through the library.
//!
//! Each `mod regression_*` here guards one fixed bug and is named after it
//! (`cargo test --test integration regression_` selects them all).

use crate::cli_common as common;
use common::*;

use elasto::material::{MaterialModel, YoungPoisson};
use elasto::math::Vector;
use elasto::mesh::Mesh;
use elasto::sim::{Body, Effects, Simulation, SimulationSettings};
use std::path::{Path, PathBuf};

/// The unit cube of the import tests (45 vertices, volume 1).
fn cube() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/meshes/cube.mesh")
}

/// A 3D scene of the unit cube scaled by 2 (volume 8), density 3 (mass 24),
/// moving at 1 along x, without gravity or ground.
fn cube_scene(path: &str) -> String {
    format!(
        "dimension = 3\n\
         [mesh]\ngenerator = \"file\"\npath = \"{path}\"\nscale = 2.0\n\
         rotate = [0.0, 0.0, 90.0]\ntranslate = [0.0, 1.0, 0.0]\nvelocity = [1.0, 0.0, 0.0]\n\
         [material]\nmodel = \"neo-hookean\"\nyoung = 300.0\npoisson = 0.3\ndensity = 3.0\n\
         [time]\nfps = 10.0\nsubsteps = 2\nframes = 4\n"
    )
}

fn column(header: &[String], rows: &[Vec<String>], name: &str) -> Vec<f64> {
    column_f64(header, rows, name)
}

#[test]
fn a_file_mesh_scene_runs_with_the_imported_mass() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::copy(cube(), tmp.path().join("cube.mesh")).unwrap();
    std::fs::write(tmp.path().join("cube.toml"), cube_scene("cube.mesh")).unwrap();
    // Relative to the scene file's folder, not the working folder.
    let elsewhere = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("cube.toml");
    let o = elasto(elsewhere.path(), &["check", scene.to_str().unwrap()]);
    assert_code(&o, 0);
    let text = stdout(&o);
    assert!(text.contains("45 vertices"), "{text}");
    assert!(
        text.contains("mesh file") && text.contains("cube.mesh (MEDIT"),
        "{text}"
    );
    assert!(text.contains("1 piece"), "{text}");

    let out = elsewhere.path().join("out");
    let o = elasto(
        elsewhere.path(),
        &[
            "run",
            scene.to_str().unwrap(),
            "--no-render",
            "-q",
            "-o",
            "out",
        ],
    );
    assert_code(&o, 0);
    let (header, rows) = read_csv(&out.join("stats.csv"));
    assert_eq!(rows.len(), 4);
    // Kinetic energy 1/2 m v^2 with m = density 3 x volume 1 x scale^3.
    let kinetic = column(&header, &rows, "kinetic");
    assert!((kinetic[0] - 0.5 * 24.0).abs() < 1e-9, "{}", kinetic[0]);
    // Free flight: the centre of mass moves at 1 along x.
    let com_x = column(&header, &rows, "com_x");
    let time = column(&header, &rows, "time");
    for (x, t) in com_x.iter().zip(&time) {
        assert!((x - com_x[0] - t).abs() < 1e-6, "{x} at {t}");
    }
    // The resolved scene keeps the file keys and reruns.
    let resolved = std::fs::read_to_string(out.join("scene.toml")).unwrap();
    for line in [
        "generator = \"file\"",
        "scale = 2.0",
        "rotate = [0.0, 0.0, 90.0]",
        "translate = [0.0, 1.0, 0.0]",
        "orient = true",
        "merge_tolerance = 0.0",
    ] {
        assert!(resolved.contains(line), "{line} missing in\n{resolved}");
    }
    let o = elasto(
        tmp.path(),
        &["check", out.join("scene.toml").to_str().unwrap()],
    );
    assert_code(&o, 0);
}

#[test]
fn a_missing_or_broken_mesh_file_is_exit_2_at_mesh_path() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("gone.toml"), cube_scene("nowhere.mesh")).unwrap();
    let o = elasto(tmp.path(), &["check", "gone.toml"]);
    assert_code(&o, 2);
    let err = stderr(&o);
    assert!(
        err.contains("mesh.path") && err.contains("nowhere.mesh"),
        "{err}"
    );

    std::fs::write(tmp.path().join("broken.msh"), "this is not a mesh\n").unwrap();
    std::fs::write(tmp.path().join("broken.toml"), cube_scene("broken.msh")).unwrap();
    let o = elasto(tmp.path(), &["run", "broken.toml", "--no-render", "-q"]);
    assert_code(&o, 2);
    let err = stderr(&o);
    assert!(
        err.contains("mesh.path") && err.contains("broken.msh"),
        "{err}"
    );
    assert!(!tmp.path().join("out").exists(), "nothing is written");

    // Box keys with a file mesh, and file keys with a box, are refused.
    std::fs::write(
        tmp.path().join("mixed.toml"),
        cube_scene("cube.mesh").replace("scale = 2.0", "cells = [1, 1, 1]"),
    )
    .unwrap();
    let o = elasto(tmp.path(), &["check", "mixed.toml"]);
    assert_code(&o, 2);
    assert!(stderr(&o).contains("mesh.cells"), "{}", stderr(&o));
}

#[test]
fn save_surface_writes_one_file_per_frame() {
    let tmp = tempfile::tempdir().unwrap();
    for format in ["obj", "ply"] {
        let o = elasto(
            tmp.path(),
            &[
                "run",
                "hanging-bar-2d",
                "--frames",
                "3",
                "--no-render",
                "-q",
                "--save-surface",
                format,
                "-o",
                format,
            ],
        );
        assert_code(&o, 0);
        let mut names: Vec<String> = std::fs::read_dir(tmp.path().join(format).join("surfaces"))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        let expected: Vec<String> = (0..3).map(|i| format!("surface_{i:04}.{format}")).collect();
        assert_eq!(names, expected);
    }
    let ply = std::fs::read(tmp.path().join("ply/surfaces/surface_0002.ply")).unwrap();
    let header = String::from_utf8_lossy(&ply[..200.min(ply.len())]).into_owned();
    assert!(header.contains("property float von_mises"), "{header}");
    // --force clears the surfaces of an earlier, longer run.
    let o = elasto(
        tmp.path(),
        &[
            "run",
            "hanging-bar-2d",
            "--frames",
            "2",
            "--no-render",
            "-q",
            "--save-surface",
            "obj",
            "-o",
            "obj",
            "--force",
        ],
    );
    assert_code(&o, 0);
    assert_eq!(
        std::fs::read_dir(tmp.path().join("obj/surfaces"))
            .unwrap()
            .count(),
        2
    );
    let o = elasto(tmp.path(), &["run", "--save-surface", "stl"]);
    assert_code(&o, 2);
}

/// Two 2D boxes far apart, each with its own velocity and density, and an
/// optional pinned region and gravity.
fn two_boxes(extra: &str, soft: &str, stiff: &str, pins: bool) -> String {
    let pin = |x: f64| {
        if pins {
            format!(
                "[bodies.pinned]\nmin = [{}, 2.9]\nmax = [{}, 3.1]\n",
                x - 0.1,
                x + 1.1
            )
        } else {
            String::new()
        }
    };
    format!(
        "dimension = 2\n{extra}\
         [[bodies]]\n[bodies.mesh]\nsize = [1.0, 3.0]\ncells = [2, 6]\noffset = [-3.0, 0.0]\n\
         velocity = [1.0, 0.5]\n\
         [bodies.material]\nmodel = \"neo-hookean\"\nyoung = {soft}\npoisson = 0.3\ndensity = 2.0\n{}\
         [[bodies]]\n[bodies.mesh]\nsize = [1.0, 3.0]\ncells = [2, 6]\noffset = [3.0, 0.0]\n\
         velocity = [-2.0, 0.0]\n\
         [bodies.material]\nmodel = \"neo-hookean\"\nyoung = {stiff}\npoisson = 0.3\ndensity = 0.5\n{}",
        pin(-3.0),
        pin(3.0),
    )
}

#[test]
fn two_bodies_keep_their_own_velocities_and_total_momentum() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(
        tmp.path().join("two.toml"),
        two_boxes(
            "[time]\nfps = 10.0\nsubsteps = 2\nframes = 6\n",
            "300.0",
            "3000.0",
            false,
        ),
    )
    .unwrap();
    let o = elasto(tmp.path(), &["check", "two.toml"]);
    assert_code(&o, 0);
    assert!(stdout(&o).contains("bodies          2"), "{}", stdout(&o));
    assert!(
        stdout(&o).contains("42 vertices, 48 elements"),
        "{}",
        stdout(&o)
    );
    let o = elasto(tmp.path(), &["run", "two.toml", "--no-render", "-q"]);
    assert_code(&o, 0);
    let (header, rows) = read_csv(&tmp.path().join("out/two/stats.csv"));
    // Masses: 2 x 3 (area) = 6 and 0.5 x 3 = 1.5.
    let (m1, m2) = (6.0, 1.5);
    let kinetic = column(&header, &rows, "kinetic");
    let expected = 0.5 * m1 * (1.0 + 0.25) + 0.5 * m2 * 4.0;
    let elastic = column(&header, &rows, "elastic");
    let time = column(&header, &rows, "time");
    let (com_x, com_y) = (
        column(&header, &rows, "com_x"),
        column(&header, &rows, "com_y"),
    );
    let velocity = [(m1 * 1.0 + m2 * -2.0) / (m1 + m2), (m1 * 0.5) / (m1 + m2)];
    for f in 0..rows.len() {
        // Each body moves rigidly at its own velocity: no strain, the same
        // kinetic energy, and the centre of mass at the total momentum over the mass.
        assert!(
            (kinetic[f] - expected).abs() < 1e-6 * expected,
            "{f}: {}",
            kinetic[f]
        );
        assert!(elastic[f].abs() < 1e-9, "{f}: {}", elastic[f]);
        assert!((com_x[f] - com_x[0] - velocity[0] * time[f]).abs() < 1e-6);
        assert!((com_y[f] - com_y[0] - velocity[1] * time[f]).abs() < 1e-6);
    }
}

#[test]
fn bodies_of_different_stiffness_deform_differently() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = two_boxes(
        "[time]\nfps = 10.0\nsubsteps = 4\nframes = 6\n[effects.gravity]\nacceleration = [0.0, -10.0]\n",
        "30.0",
        "3000.0",
        true,
    )
    .replace("velocity = [1.0, 0.5]", "velocity = [0.0, 0.0]")
    .replace("velocity = [-2.0, 0.0]", "velocity = [0.0, 0.0]");
    std::fs::write(tmp.path().join("hang.toml"), scene).unwrap();
    let o = elasto(
        tmp.path(),
        &[
            "run",
            "hang.toml",
            "--no-render",
            "-q",
            "--save-surface",
            "obj",
        ],
    );
    assert_code(&o, 0);
    let obj =
        std::fs::read_to_string(tmp.path().join("out/hang/surfaces/surface_0005.obj")).unwrap();
    let lowest = |left: bool| {
        obj.lines()
            .filter_map(|l| l.strip_prefix("v "))
            .map(|l| {
                let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
                (v[0], v[1])
            })
            .filter(|(x, _)| (*x < 0.0) == left)
            .map(|(_, y)| y)
            .fold(f64::INFINITY, f64::min)
    };
    let (soft, stiff) = (lowest(true), lowest(false));
    // Both hang from y = 3 and start at y = 0; the soft bar stretches more.
    assert!(stiff < 0.0 && stiff > -0.05, "stiff bottom at {stiff}");
    assert!(
        soft < stiff - 0.1,
        "soft bottom at {soft}, stiff at {stiff}"
    );
}

#[test]
fn mesh_and_bodies_together_are_exit_2() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = two_boxes("", "300.0", "300.0", false).replacen(
        "dimension = 2\n",
        "dimension = 2\n[mesh]\nsize = [1.0, 1.0]\ncells = [1, 1]\n[material]\nmodel = \"stvk\"\nyoung = 300.0\npoisson = 0.3\n",
        1,
    );
    std::fs::write(tmp.path().join("both.toml"), scene).unwrap();
    let o = elasto(tmp.path(), &["check", "both.toml"]);
    assert_code(&o, 2);
    let err = stderr(&o);
    assert!(
        err.contains("[[bodies]]") && err.contains("not both"),
        "{err}"
    );
    // A body's key is named with its index.
    let bad = two_boxes("", "300.0", "-1.0", false);
    std::fs::write(tmp.path().join("bad.toml"), bad).unwrap();
    let o = elasto(tmp.path(), &["check", "bad.toml"]);
    assert_code(&o, 2);
    assert!(
        stderr(&o).contains("bodies[1].material.young"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn bodies_get_their_own_masses_and_velocities() {
    let settings = SimulationSettings::default();
    let material = |young| {
        MaterialModel::NeoHookean.with_lame(
            YoungPoisson {
                young,
                poisson: 0.3,
            }
            .into(),
        )
    };
    let cube = |x: f64| {
        Mesh::<3>::axis_aligned_box(
            Vector::<3>::new(x, 0.0, 0.0),
            Vector::<3>::new(x + 1.0, 2.0, 1.0),
            [2, 2, 2],
        )
        .unwrap()
    };
    let bodies = vec![
        Body {
            mesh: cube(0.0),
            material: material(100.0),
            density: 2.0,
            velocity: Vector::<3>::new(1.0, 0.0, 0.0),
            pinned: None,
        },
        Body {
            mesh: cube(5.0),
            material: material(1000.0),
            density: 0.5,
            velocity: Vector::<3>::new(0.0, 0.0, -4.0),
            pinned: None,
        },
    ];
    let vertices = bodies[0].mesh.vertex_count();
    let mut sim = Simulation::with_bodies(bodies, Effects::default(), settings).unwrap();
    assert_eq!(sim.mesh().vertex_count(), 2 * vertices);
    let mass = |range: std::ops::Range<usize>| sim.masses()[range].iter().sum::<f64>();
    assert!((mass(0..vertices) - 4.0).abs() < 1e-12);
    assert!((mass(vertices..2 * vertices) - 1.0).abs() < 1e-12);
    let momentum = |sim: &Simulation<3>| {
        sim.velocities()
            .iter()
            .zip(sim.masses())
            .map(|(v, m)| v * *m)
            .sum::<Vector<3>>()
    };
    let p0 = momentum(&sim);
    assert!(
        (p0 - Vector::<3>::new(4.0, 0.0, -4.0)).norm() < 1e-12,
        "{p0}"
    );
    for _ in 0..5 {
        sim.step().unwrap();
    }
    assert!((momentum(&sim) - p0).norm() < 1e-9);
    assert!(
        sim.velocities()[..vertices]
            .iter()
            .all(|v| (v - Vector::<3>::new(1.0, 0.0, 0.0)).norm() < 1e-6)
    );
    assert!(
        sim.velocities()[vertices..]
            .iter()
            .all(|v| (v - Vector::<3>::new(0.0, 0.0, -4.0)).norm() < 1e-6)
    );
}

/// The strain energy of two bodies is each body's own, on its vertices: the
/// value, the gradient and the assembled Hessian (block diagonal) match the
/// bodies' `Elasticity` terms evaluated apart.
#[test]
fn body_elasticity_is_the_sum_of_the_bodies_terms() {
    use elasto::assembly::SparseHessian;
    use elasto::energy::{BodyElasticity, Elasticity, EnergyTerm};
    use std::sync::Arc;
    let material = |young| {
        MaterialModel::NeoHookean.with_lame(
            YoungPoisson {
                young,
                poisson: 0.3,
            }
            .into(),
        )
    };
    let first = Arc::new(
        Mesh::<2>::axis_aligned_box(Vector::<2>::zeros(), Vector::<2>::new(1.0, 2.0), [2, 3])
            .unwrap(),
    );
    let second = Arc::new(
        Mesh::<2>::axis_aligned_box(
            Vector::<2>::new(3.0, 0.0),
            Vector::<2>::new(4.0, 1.0),
            [1, 2],
        )
        .unwrap(),
    );
    let (n1, n2) = (first.vertex_count(), second.vertex_count());
    let terms = [
        Elasticity::new(first.clone(), material(100.0)),
        Elasticity::new(second.clone(), material(5000.0)),
    ];
    let both = BodyElasticity::bodies(vec![
        (first.clone(), material(100.0)),
        (second.clone(), material(5000.0)),
    ])
    .unwrap();
    let mut positions: Vec<Vector<2>> = first
        .rest_positions()
        .iter()
        .chain(second.rest_positions())
        .copied()
        .collect();
    for (i, x) in positions.iter_mut().enumerate() {
        *x += Vector::<2>::new(0.03 * (i as f64).sin(), 0.05 * (i as f64 * 1.7).cos());
    }
    let (x1, x2) = positions.split_at(n1);
    let value = both.value(&positions);
    let apart = terms[0].value(x1) + terms[1].value(x2);
    assert!(
        (value - apart).abs() <= 1e-12 * apart.abs(),
        "{value} {apart}"
    );

    let mut gradient = vec![Vector::<2>::zeros(); n1 + n2];
    both.add_gradient(&positions, 1.0, &mut gradient);
    let mut g1 = vec![Vector::<2>::zeros(); n1];
    let mut g2 = vec![Vector::<2>::zeros(); n2];
    terms[0].add_gradient(x1, 1.0, &mut g1);
    terms[1].add_gradient(x2, 1.0, &mut g2);
    assert_eq!(gradient, [g1, g2].concat());

    let mut simplices: Vec<Vec<usize>> = first.simplices().map(<[usize]>::to_vec).collect();
    simplices.extend(
        second
            .simplices()
            .map(|s| s.iter().map(|v| v + n1).collect()),
    );
    let scene = Mesh::<2>::new(positions_at_rest(&first, &second), simplices).unwrap();
    let mut hessian = SparseHessian::new(&scene, (0..n1 + n2).map(Some).collect()).unwrap();
    both.add_hessian(&positions, 1.0, &mut hessian);
    let dense = hessian.to_dense();
    let block = |term: &Elasticity<2>, mesh: &Mesh<2>, x: &[Vector<2>]| {
        let mut h = SparseHessian::new(mesh, (0..mesh.vertex_count()).map(Some).collect()).unwrap();
        term.add_hessian(x, 1.0, &mut h);
        h.to_dense()
    };
    let (h1, h2) = (block(&terms[0], &first, x1), block(&terms[1], &second, x2));
    let (d1, d2) = (2 * n1, 2 * n2);
    assert_eq!(dense.view((0, 0), (d1, d1)), h1);
    assert_eq!(dense.view((d1, d1), (d2, d2)), h2);
    assert!(dense.view((0, d1), (d1, d2)).iter().all(|&v| v == 0.0));
}

fn positions_at_rest(first: &Mesh<2>, second: &Mesh<2>) -> Vec<Vector<2>> {
    first
        .rest_positions()
        .iter()
        .chain(second.rest_positions())
        .copied()
        .collect()
}

/// Issue 33, item 7: duplicated elements in a mesh file were accepted and
/// doubled the mass and stiffness (every tetrahedron listed twice: gravity
/// energy 2.0 instead of 1.0), and a repeated piece with vertices of its
/// own became a second body overlapping the first. Now an element whose
/// corners are at the same positions as an earlier one's (in any order) is
/// dropped and counted in the import summary.
mod regression_duplicate_elements_doubled_the_mass {
    use crate::cli_common as common;
    use common::*;

    /// Two tetrahedra sharing a face as MEDIT text, with `extra` elements
    /// appended; vertices 6-9 repeat the positions of vertices 1-4.
    fn medit(extra: &[&str]) -> String {
        let mut elements = vec!["1 2 3 4", "2 3 4 5"];
        elements.extend(extra);
        let mut text = String::from(
            "MeshVersionFormatted 2\nDimension 3\nVertices\n9\n\
         0 0 1 0\n1 0 1 0\n0 1 1 0\n0 0 2 0\n1 1 2 0\n\
         0 0 1 0\n1 0 1 0\n0 1 1 0\n0 0 2 0\n",
        );
        text.push_str(&format!("Tetrahedra\n{}\n", elements.len()));
        for e in elements {
            text.push_str(&format!("{e} 0\n"));
        }
        text.push_str("End\n");
        text
    }

    const SCENE: &str = r#"dimension = 3

[mesh]
generator = "file"
path = "m.mesh"

[material]
model = "neo-hookean"
young = 100.0
poisson = 0.3
density = 1.0

[effects.gravity]
acceleration = [0.0, -10.0, 0.0]
"#;

    /// `elasto check`'s output for the mesh text `mesh`.
    fn check(dir: &std::path::Path, mesh: &str) -> String {
        std::fs::write(dir.join("m.mesh"), mesh).unwrap();
        std::fs::write(dir.join("s.toml"), SCENE).unwrap();
        let o = elasto(dir, &["check", "s.toml"]);
        assert_code(&o, 0);
        stdout(&o)
    }

    fn energy_line(summary: &str) -> &str {
        summary
            .lines()
            .find(|l| l.contains("energy at t = 0"))
            .unwrap_or_else(|| panic!("{summary}"))
    }

    #[test]
    fn duplicate_elements_are_dropped_and_counted() {
        let tmp = tempfile::tempdir().unwrap();
        let single = check(tmp.path(), &medit(&[]));
        // The first listed again, again with its corners in another order (an
        // inverted copy, re-oriented first), and as a copy with its own vertices.
        let doubled = check(tmp.path(), &medit(&["1 2 3 4", "4 3 2 1", "6 7 8 9"]));
        assert!(
            doubled.contains("2 tetrahedra")
                && doubled.contains(
                    "dropped 3 duplicate tetrahedra (the same corners as an earlier one)"
                )
                && doubled.contains("dropped 4 unreferenced vertices"),
            "{doubled}"
        );
        assert!(!single.contains("duplicate"), "{single}");
        // The same mass: the same gravity energy.
        assert_eq!(energy_line(&doubled), energy_line(&single));
    }
}

/// Issue 33, item 8: an overflowing coordinate (a vertex at 1e308 in the
/// file, `scale = 1e300`, `translate = [0, 1e39, 0]`) was reported as a
/// "degenerate element (signed volume 2.083e-2)". Now the vertex and its
/// coordinate are named, with the limit (the renderer's 32-bit floats) and,
/// when the file itself is fine, the transforms that moved it there.
mod regression_overflowing_coordinates_called_degenerate {
    use crate::cli_common as common;
    use common::*;

    /// Two tetrahedra as MEDIT text, vertex 5 at `x`.
    fn medit(x: &str) -> String {
        format!(
            "MeshVersionFormatted 2\nDimension 3\nVertices\n5\n\
         0 0 1 0\n1 0 1 0\n0 1 1 0\n0 0 2 0\n{x} 1 2 0\n\
         Tetrahedra\n2\n1 2 3 4 0\n2 3 4 5 0\nEnd\n"
        )
    }

    fn scene(mesh_keys: &str) -> String {
        format!(
            "dimension = 3\n\n[mesh]\ngenerator = \"file\"\npath = \"m.mesh\"\n{mesh_keys}\n\
         [material]\nmodel = \"neo-hookean\"\nyoung = 100.0\npoisson = 0.3\n"
        )
    }

    #[test]
    fn a_coordinate_beyond_the_renderers_range_is_named() {
        let tmp = tempfile::tempdir().unwrap();
        let cases = [
            ("1e308", "", "vertex 5 lies at 1e308, beyond ±3.4e38"),
            (
                "1",
                "scale = 1e300\n",
                "lies at 1e300 after scale, rotate and translate",
            ),
            (
                "1",
                "translate = [0.0, 1e39, 0.0]\n",
                "vertex 1 lies at 1e39 after scale, rotate and translate",
            ),
        ];
        for (x, keys, expected) in cases {
            std::fs::write(tmp.path().join("m.mesh"), medit(x)).unwrap();
            std::fs::write(tmp.path().join("s.toml"), scene(keys)).unwrap();
            let o = elasto(tmp.path(), &["check", "s.toml"]);
            assert_code(&o, 2);
            let err = stderr(&o);
            assert!(
                err.contains(expected)
                    && err.contains("32-bit floats")
                    && !err.contains("degenerate"),
                "{x} {keys}: {err}"
            );
        }
    }
}
