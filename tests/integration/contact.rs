//! Contact between and within bodies (IPC), through the binary: bodies that meet stay apart on every saved frame (checked by the independent intersection test of `support/intersection/`), the same scenes without `[effects.contact]` pass through each other, and bodies that start intersecting are refused before any work.

use crate::cli_common::*;
use crate::intersection::{SavedSurface, find_intersections};
use std::path::Path;

/// Two boxes in 2D: the upper one falls onto the lower one, which rests on the ground.
const TWO_BOXES_2D: &str = r#"dimension = 2

[[bodies]]
[bodies.mesh]
size = [1.0, 0.5]
cells = [6, 3]
offset = [0.0, 0.05]
[bodies.material]
model = "neo-hookean"
young = 500.0
poisson = 0.3

[[bodies]]
[bodies.mesh]
size = [0.5, 0.5]
cells = [3, 3]
offset = [0.3, 0.9]
velocity = [0.0, -3.0]
[bodies.material]
model = "neo-hookean"
young = 500.0
poisson = 0.3

[time]
fps = 30.0
substeps = 3
frames = 24

[effects.gravity]
acceleration = [0.0, -9.81]

[effects.ground]
height = 0.0
a = 0.02

[effects.contact]
distance = 0.005
"#;

/// The same in 3D, with two cubes.
const TWO_BOXES_3D: &str = r#"dimension = 3

[[bodies]]
[bodies.mesh]
size = [1.0, 0.4, 1.0]
cells = [3, 2, 3]
offset = [0.0, 0.05, 0.0]
[bodies.material]
model = "neo-hookean"
young = 500.0
poisson = 0.3

[[bodies]]
[bodies.mesh]
size = [0.5, 0.5, 0.5]
cells = [2, 2, 2]
offset = [0.2, 0.8, 0.3]
velocity = [0.0, -3.0, 0.0]
[bodies.material]
model = "neo-hookean"
young = 500.0
poisson = 0.3

[time]
fps = 30.0
substeps = 3
frames = 20

[effects.gravity]
acceleration = [0.0, -9.81, 0.0]

[effects.ground]
height = 0.0
a = 0.02

[effects.contact]
distance = 0.005
"#;

/// Runs `scene` without rendering, saving every frame's surface as OBJ;
/// returns the output folder's stats rows (header, rows).
fn run_saving_surfaces(dir: &Path, scene: &str, out: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let path = dir.join(format!("{out}.toml"));
    std::fs::write(&path, scene).unwrap();
    let o = elasto(
        dir,
        &[
            "run",
            path.to_str().unwrap(),
            "--no-render",
            "--save-surface",
            "obj",
            "--quiet",
            "--out",
            out,
        ],
    );
    assert_code(&o, 0);
    read_csv(&dir.join(out).join("stats.csv"))
}

/// The frames whose saved surface the independent check finds intersecting.
fn intersecting_frames(folder: &Path) -> Vec<(String, usize)> {
    let mut files: Vec<_> = std::fs::read_dir(folder.join("surfaces"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no surfaces in {}", folder.display());
    files
        .iter()
        .filter_map(|f| {
            let found = find_intersections(&SavedSurface::read_obj(f).unwrap());
            (!found.is_empty()).then(|| {
                (
                    f.file_name().unwrap().to_string_lossy().into_owned(),
                    found.len(),
                )
            })
        })
        .collect()
}

fn column(header: &[String], rows: &[Vec<String>], name: &str) -> Vec<String> {
    let i = column_index(header, name);
    rows.iter().map(|r| r[i].clone()).collect()
}

fn without_contact(scene: &str) -> String {
    let at = scene.find("[effects.contact]").unwrap();
    scene[..at].to_owned()
}

fn check_contact_scene(scene: &str) {
    let dir = tempfile::tempdir().unwrap();
    let (header, rows) = run_saving_surfaces(dir.path(), scene, "with");
    let crossing = intersecting_frames(&dir.path().join("with"));
    assert!(
        crossing.is_empty(),
        "intersecting frames with contact: {crossing:?}"
    );
    // The bodies met: pairs were active, the pattern grew, and every
    // recorded distance is positive.
    let pairs: Vec<usize> = column(&header, &rows, "contact_pairs")
        .iter()
        .map(|c| c.parse().unwrap())
        .collect();
    assert!(
        pairs.iter().any(|&p| p > 0),
        "no contact pair was ever active: {pairs:?}"
    );
    let reanalyses: usize = column(&header, &rows, "reanalyses")
        .iter()
        .map(|c| c.parse::<usize>().unwrap())
        .sum();
    assert!(reanalyses > 0);
    // Every recorded distance is positive and within the larger reach
    // (the ground's a = 0.02; the pairs' d_hat = 0.005), and the ground
    // counts: where the lowest vertex is within a, min_distance is at
    // most its height.
    let distances: Vec<f64> = column(&header, &rows, "min_distance")
        .iter()
        .filter(|c| !c.is_empty())
        .map(|c| c.parse().unwrap())
        .collect();
    assert!(!distances.is_empty());
    assert!(
        distances.iter().all(|&d| d > 0.0 && d < 0.02),
        "{distances:?}"
    );
    let heights = column(&header, &rows, "min_height");
    let mut near_ground = 0;
    for (height, distance) in heights.iter().zip(column(&header, &rows, "min_distance")) {
        let height: f64 = height.parse().unwrap();
        if height < 0.02 {
            near_ground += 1;
            let distance: f64 = distance
                .parse()
                .expect("min_distance empty near the ground");
            assert!(
                distance <= height,
                "min_distance {distance} above min_height {height}"
            );
        }
    }
    assert!(
        near_ground > 0,
        "the lower box never came within a of the ground"
    );
    let stalled: usize = column(&header, &rows, "stalled_steps")
        .iter()
        .map(|c| c.parse::<usize>().unwrap())
        .sum();
    assert_eq!(stalled, 0);
    // The negative control: without [effects.contact] the bodies pass
    // through each other, and the check sees it.
    let (header, rows) = run_saving_surfaces(dir.path(), &without_contact(scene), "without");
    assert!(
        !intersecting_frames(&dir.path().join("without")).is_empty(),
        "the bodies never intersected without contact: the test scene does not test contact"
    );
    // A scene without contact pays nothing for it.
    assert!(
        column(&header, &rows, "min_distance")
            .iter()
            .all(String::is_empty)
    );
    for name in ["contact_pairs", "reanalyses", "ccd_budget_exhausted"] {
        assert!(
            column(&header, &rows, name).iter().all(|c| c == "0"),
            "{name}"
        );
    }
}

#[test]
fn two_boxes_in_2d_stay_apart_and_pass_through_each_other_without_contact() {
    check_contact_scene(TWO_BOXES_2D);
}

#[test]
fn two_boxes_in_3d_stay_apart_and_pass_through_each_other_without_contact() {
    check_contact_scene(TWO_BOXES_3D);
}

#[test]
fn bodies_that_start_intersecting_are_refused_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    for (dimension, scene) in [(2, TWO_BOXES_2D), (3, TWO_BOXES_3D)] {
        // Move the upper box down into the lower one.
        let overlapping = scene
            .replace("offset = [0.3, 0.9]", "offset = [0.3, 0.4]")
            .replace("offset = [0.2, 0.8, 0.3]", "offset = [0.2, 0.3, 0.3]");
        let path = dir.path().join(format!("overlap-{dimension}.toml"));
        std::fs::write(&path, overlapping).unwrap();
        let scene_path = path.to_str().unwrap();
        for args in [
            vec!["check", scene_path],
            vec!["run", scene_path, "--no-render"],
        ] {
            let o = elasto(dir.path(), &args);
            assert_code(&o, 2);
            let message = stderr(&o);
            assert!(
                message.contains("`effects.contact`: body 0 and body 1"),
                "{message}"
            );
            assert!(
                message.contains("closer than the contact distance"),
                "{message}"
            );
        }
        assert!(
            !dir.path().join("out").exists(),
            "a refused run wrote its folder"
        );
    }
}

#[test]
fn a_body_that_starts_inside_another_is_refused_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    // The upper box made small and put wholly inside the lower one: no
    // surfaces cross and no pair is within d_hat.
    let inside = [
        (
            2,
            TWO_BOXES_2D.replace(
                "size = [0.5, 0.5]\ncells = [3, 3]\noffset = [0.3, 0.9]",
                "size = [0.2, 0.2]\ncells = [2, 2]\noffset = [0.4, 0.2]",
            ),
        ),
        (
            3,
            TWO_BOXES_3D.replace(
                "size = [0.5, 0.5, 0.5]\ncells = [2, 2, 2]\noffset = [0.2, 0.8, 0.3]",
                "size = [0.2, 0.1, 0.2]\ncells = [1, 1, 1]\noffset = [0.4, 0.2, 0.4]",
            ),
        ),
    ];
    for (dimension, scene) in inside {
        assert!(
            scene.contains("offset = [0.4, 0.2"),
            "the scene was changed"
        );
        let path = dir.path().join(format!("inside-{dimension}.toml"));
        std::fs::write(&path, &scene).unwrap();
        let scene_path = path.to_str().unwrap();
        for args in [
            vec!["check", scene_path],
            vec!["run", scene_path, "--no-render"],
        ] {
            let o = elasto(dir.path(), &args);
            assert_code(&o, 2);
            let message = stderr(&o);
            assert!(
                message.contains("`bodies[1]`: body 1 starts inside body 0"),
                "{message}"
            );
        }
        // Without contact the same scene runs (bodies pass through).
        let without = scene.replace("[effects.contact]\ndistance = 0.005\n", "");
        std::fs::write(&path, without).unwrap();
        assert_code(&elasto(dir.path(), &["check", scene_path]), 0);
        assert!(
            !dir.path().join("out").exists(),
            "a refused run wrote its folder"
        );
    }
}

/// A mesh file whose own surface crosses itself (two overlapping triangles
/// of one body) is refused at the body's `mesh` under self-contact, by the
/// validator on the built mesh; with `self = false` it is accepted.
#[test]
fn a_mesh_whose_surface_crosses_itself_is_refused_at_its_mesh() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("cross.node"),
        "6 2 0 0\n1 0 0\n2 1 0\n3 0 1\n4 0.2 0.2\n5 1.2 0.2\n6 0.2 1.2\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("cross.ele"), "2 3 0\n1 1 2 3\n2 4 5 6\n").unwrap();
    let scene = "dimension = 2\n\n[mesh]\ngenerator = \"file\"\npath = \"cross.node\"\n\n\
                 [material]\nmodel = \"neo-hookean\"\nyoung = 100.0\npoisson = 0.3\n\n\
                 [effects.contact]\ndistance = 0.001\n";
    std::fs::write(dir.path().join("cross.toml"), scene).unwrap();
    for args in [
        vec!["check", "cross.toml"],
        vec!["run", "cross.toml", "--no-render"],
    ] {
        let o = elasto(dir.path(), &args);
        assert_code(&o, 2);
        let message = stderr(&o);
        assert!(message.contains("cross.toml:3:1: `mesh`"), "{message}");
        assert!(
            message.contains("parts of body 0 (its surface self-intersects or folds within d_hat)"),
            "{message}"
        );
    }
    assert!(
        !dir.path().join("out").exists(),
        "a refused run wrote its folder"
    );
    let without_self = scene.replace("distance = 0.001\n", "distance = 0.001\nself = false\n");
    std::fs::write(dir.path().join("cross.toml"), without_self).unwrap();
    assert_code(&elasto(dir.path(), &["check", "cross.toml"]), 0);
}

/// Runs a scene of the repository (a path under `scenes/`) with `extra`
/// flags; returns its folder's stats.
fn run_repository_scene(
    dir: &Path,
    scene: &str,
    out: &str,
    extra: &[&str],
) -> (Vec<String>, Vec<Vec<String>>) {
    let path = format!("{}/scenes/{scene}", env!("CARGO_MANIFEST_DIR"));
    let mut args = vec![
        "run",
        path.as_str(),
        "--no-render",
        "--save-surface",
        "obj",
        "--quiet",
        "--out",
        out,
    ];
    args.extend_from_slice(extra);
    let o = elasto(dir, &args);
    assert_code(&o, 0);
    read_csv(&dir.join(out).join("stats.csv"))
}

fn total(header: &[String], rows: &[Vec<String>], name: &str) -> usize {
    column(header, rows, name)
        .iter()
        .map(|c| c.parse::<usize>().unwrap())
        .sum()
}

#[test]
fn the_contact_scenes_stay_intersection_free_on_every_frame() {
    let dir = tempfile::tempdir().unwrap();
    // The 3D scenes are cut short to their first contacts (the whole runs
    // take tens of seconds in the test build).
    let runs: [(&str, &[&str]); 5] = [
        ("contact/squares-2d.toml", &[]),
        ("contact/self-friction-2d.toml", &[]),
        ("contact/ring-fold-2d.toml", &[]),
        ("two-bodies.toml", &["--frames", "14"]),
        ("contact/box-stack-3d.toml", &["--frames", "8"]),
    ];
    for (i, (scene, extra)) in runs.iter().enumerate() {
        let out = format!("run{i}");
        let (header, rows) = run_repository_scene(dir.path(), scene, &out, extra);
        let crossing = intersecting_frames(&dir.path().join(&out));
        assert!(
            crossing.is_empty(),
            "{scene}: intersecting frames {crossing:?}"
        );
        assert!(
            column(&header, &rows, "contact_pairs")
                .iter()
                .any(|c| c != "0"),
            "{scene}: the bodies never came within d_hat"
        );
        for name in ["stalled_steps", "unconverged_steps"] {
            assert_eq!(total(&header, &rows, name), 0, "{scene}: {name}");
        }
        let j = column(&header, &rows, "min_volume_ratio");
        assert!(
            j.iter().all(|j| j.parse::<f64>().unwrap() > 0.0),
            "{scene}: J {j:?}"
        );
    }
}

#[test]
fn a_soft_ring_folds_onto_itself_only_with_self_contact() {
    let dir = tempfile::tempdir().unwrap();
    let (header, rows) = run_repository_scene(dir.path(), "contact/ring-fold-2d.toml", "self", &[]);
    assert!(intersecting_frames(&dir.path().join("self")).is_empty());
    assert!(total(&header, &rows, "contact_pairs") > 0);
    // Self-contact off: the ring is one body, so nothing keeps its inner
    // surface from passing through itself.
    let (header, rows) = run_repository_scene(
        dir.path(),
        "contact/ring-fold-2d.toml",
        "no-self",
        &["--set", "effects.contact.self=false"],
    );
    assert_eq!(total(&header, &rows, "contact_pairs"), 0);
    assert!(!intersecting_frames(&dir.path().join("no-self")).is_empty());
}

/// The `contact_force` point data of a saved VTU file: one vector per vertex.
fn contact_forces(vtu: &str) -> Vec<[f64; 3]> {
    let start = vtu
        .find("Name=\"contact_force\"")
        .expect("a contact_force array");
    let body = &vtu[start + vtu[start..].find('>').unwrap() + 1..];
    let numbers: Vec<f64> = body[..body.find("</DataArray>").unwrap()]
        .split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect();
    numbers.chunks(3).map(|c| [c[0], c[1], c[2]]).collect()
}

#[test]
fn saved_meshes_carry_contact_forces_that_sum_to_zero() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("boxes.toml");
    std::fs::write(&path, TWO_BOXES_2D).unwrap();
    let o = elasto(
        dir.path(),
        &[
            "run",
            path.to_str().unwrap(),
            "--no-render",
            "--save-meshes",
            "-q",
            "--out",
            "o",
        ],
    );
    assert_code(&o, 0);
    let (header, rows) = read_csv(&dir.path().join("o/stats.csv"));
    let pairs = column(&header, &rows, "contact_pairs");
    let frame = pairs
        .iter()
        .position(|p| p != "0")
        .expect("a frame in contact");
    let vtu =
        std::fs::read_to_string(dir.path().join(format!("o/meshes/frame_{frame:04}.vtu"))).unwrap();
    let forces = contact_forces(&vtu);
    // 4 x 7 + 7 x 4 vertices: the lower box's first.
    assert_eq!(forces.len(), 28 + 16);
    let largest = forces.iter().map(|f| f[0].hypot(f[1])).fold(0.0, f64::max);
    assert!(largest > 0.0, "no contact force at frame {frame}");
    // The barrier depends on differences of positions only: the forces on
    // the two bodies are equal and opposite (Newton's third law), and the
    // upper box is pushed up.
    let sum = |range: std::ops::Range<usize>| {
        forces[range]
            .iter()
            .fold([0.0, 0.0], |s, f| [s[0] + f[0], s[1] + f[1]])
    };
    let (lower, upper) = (sum(0..28), sum(28..44));
    for k in 0..2 {
        assert!(
            (lower[k] + upper[k]).abs() <= 1e-9 * largest,
            "{lower:?} {upper:?}"
        );
    }
    assert!(upper[1] > 0.0, "{upper:?}");
    // Vertices away from the contact carry none.
    assert!(forces.iter().filter(|f| f[0] == 0.0 && f[1] == 0.0).count() > 20);
    // A scene without contact writes no such array.
    let vtu = std::fs::read_to_string(dir.path().join("o/meshes/frame_0000.vtu")).unwrap();
    assert!(vtu.contains("contact_force"));
    std::fs::write(&path, without_contact(TWO_BOXES_2D)).unwrap();
    let o = elasto(
        dir.path(),
        &[
            "run",
            path.to_str().unwrap(),
            "--no-render",
            "--save-meshes",
            "-q",
            "--out",
            "n",
            "--frames",
            "2",
        ],
    );
    assert_code(&o, 0);
    let vtu = std::fs::read_to_string(dir.path().join("n/meshes/frame_0001.vtu")).unwrap();
    assert!(!vtu.contains("contact_force"));
}

#[test]
fn check_prints_the_contact_distance_and_stiffness_and_the_default_distance_is_a_thousandth_of_the_diagonal()
 {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("boxes.toml");
    std::fs::write(&path, TWO_BOXES_2D).unwrap();
    let o = elasto(dir.path(), &["check", path.to_str().unwrap()]);
    assert_code(&o, 0);
    let text = stdout(&o);
    assert!(
        text.contains("contact         d_hat = 0.005, stiffness kappa = "),
        "{text}"
    );
    assert!(
        text.contains("(adaptive (IPC), before the first step), self-contact on"),
        "{text}"
    );
    // Without `distance`: 1e-3 times the diagonal of the bodies' box,
    // here [0, 1] x [0.05, 1.4], recorded in the resolved scene.
    std::fs::write(
        &path,
        TWO_BOXES_2D.replace("distance = 0.005\n", "kappa = 1e4\nself = false\n"),
    )
    .unwrap();
    let o = elasto(
        dir.path(),
        &[
            "run",
            path.to_str().unwrap(),
            "--no-render",
            "-q",
            "--frames",
            "2",
        ],
    );
    assert_code(&o, 0);
    let resolved = std::fs::read_to_string(dir.path().join("out/boxes/scene.toml")).unwrap();
    let table: toml::Table = resolved.parse().unwrap();
    let contact = &table["effects"]["contact"];
    let expected = 1e-3 * (1.0f64 + 1.35 * 1.35).sqrt();
    let distance = contact["distance"].as_float().unwrap();
    assert!(
        (distance - expected).abs() < 1e-15,
        "{distance} against {expected}"
    );
    assert_eq!(contact["kappa"].as_float(), Some(1e4));
    assert_eq!(contact["self"].as_bool(), Some(false));
    let o = elasto(dir.path(), &["check", path.to_str().unwrap()]);
    assert!(
        stdout(&o).contains("stiffness kappa = 1.000000e4 (fixed), self-contact off"),
        "{}",
        stdout(&o)
    );
}
