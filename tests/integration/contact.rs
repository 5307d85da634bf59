//! Contact between and within bodies (IPC), through the binary: bodies that meet stay apart on every saved frame (checked by the independent intersection test of `support::intersection`), the same scenes without `[effects.contact]` pass through each other, and bodies that start intersecting are refused before any work.

use crate::cli_common::*;
use crate::support::intersection::{SavedSurface, find_intersections};
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
    let i = header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"));
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
    let distances: Vec<f64> = column(&header, &rows, "min_distance")
        .iter()
        .filter(|c| !c.is_empty())
        .map(|c| c.parse().unwrap())
        .collect();
    assert!(!distances.is_empty());
    assert!(
        distances.iter().all(|&d| d > 0.0 && d < 0.005),
        "{distances:?}"
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
            assert!(message.contains("effects.contact"), "{message}");
            assert!(message.contains("body 0 and body 1"), "{message}");
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
