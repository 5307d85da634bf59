//! `elasto scenes`, `scenes show` and `check` on every built-in scene.

use crate::cli_common as common;
use common::*;

const BUILTINS: [&str; 6] = [
    "report-drop-2d",
    "drop-3d",
    "hanging-bar-2d",
    "hanging-bar-3d",
    "bunny-drop",
    "two-bodies",
];

#[test]
fn scenes_lists_all_builtins() {
    let tmp = tempfile::tempdir().unwrap();
    let o = elasto(tmp.path(), &["scenes"]);
    assert_code(&o, 0);
    let text = stdout(&o);
    assert_eq!(text.lines().count(), BUILTINS.len(), "{text}");
    for (line, name) in text.lines().zip(BUILTINS) {
        assert!(line.starts_with(name), "{line}");
    }
}

#[test]
fn scenes_show_prints_toml_that_parses_and_checks() {
    let tmp = tempfile::tempdir().unwrap();
    // Scenes with mesh files name them relative to the scene: a copy of the
    // scene needs the meshes beside it, as in `scenes/`.
    let meshes = tmp.path().join("meshes");
    std::fs::create_dir(&meshes).unwrap();
    let shipped = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/meshes");
    for entry in std::fs::read_dir(shipped).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), meshes.join(entry.file_name())).unwrap();
    }
    for name in BUILTINS {
        let o = elasto(tmp.path(), &["scenes", "show", name]);
        assert_code(&o, 0);
        let text = stdout(&o);
        let table: toml::Table = text.parse().unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(table["name"].as_str(), Some(name));
        // The printed scene, saved as a file, is a valid scene of its own.
        let file = tmp.path().join(format!("{name}-copy.toml"));
        std::fs::write(&file, &text).unwrap();
        let o = elasto(tmp.path(), &["check", file.to_str().unwrap()]);
        assert_code(&o, 0);
    }
    let o = elasto(tmp.path(), &["scenes", "show", "nope"]);
    assert_code(&o, 2);
    assert!(stderr(&o).contains("nope"), "{}", stderr(&o));
}

#[test]
fn every_builtin_passes_check_with_a_summary() {
    let tmp = tempfile::tempdir().unwrap();
    for name in BUILTINS {
        let o = elasto(tmp.path(), &["check", name]);
        assert_code(&o, 0);
        let text = stdout(&o);
        assert!(text.contains(&format!("scene `{name}`")), "{text}");
        for word in [
            "dimension",
            "vertices",
            "elements",
            "effects",
            "dt =",
            "substeps",
            "frames",
            "material",
        ] {
            assert!(text.contains(word), "{name}: `{word}` missing in\n{text}");
        }
    }
    let o = elasto(tmp.path(), &["check", "report-drop-2d"]);
    let text = stdout(&o);
    assert!(text.contains("36 vertices, 50 elements"), "{text}");
    assert!(text.contains("gravity, ground"), "{text}");
    assert!(text.contains("stiffness kappa = "), "{text}");
    let o = elasto(tmp.path(), &["check", "hanging-bar-3d"]);
    let text = stdout(&o);
    assert!(
        text.contains("dimension       3") && text.contains("gravity, pinned"),
        "{text}"
    );
}

#[test]
fn check_applies_overrides() {
    let tmp = tempfile::tempdir().unwrap();
    let o = elasto(
        tmp.path(),
        &[
            "check",
            "report-drop-2d",
            "--set",
            "mesh.cells=[2, 3]",
            "--set",
            "time.substeps=4",
        ],
    );
    assert_code(&o, 0);
    let text = stdout(&o);
    assert!(text.contains("12 vertices, 12 elements"), "{text}");
    assert!(text.contains("4 substeps"), "{text}");
}

/// `check` prints the initial energy of each term the scene has, from the
/// terms themselves: no barrier without a ground.
#[test]
fn check_prints_the_initial_energy_of_each_term() {
    let tmp = tempfile::tempdir().unwrap();
    let o = elasto(tmp.path(), &["check", "report-drop-2d"]);
    assert_code(&o, 0);
    // Mass 1 at height 10.5 under g = 1: gravity 10.5; at rest and undeformed.
    assert!(
        stdout(&o).contains(
            "  energy at t = 0 kinetic = 0.000000e0, elastic = 0.000000e0, \
             gravity = 1.050000e1, barrier = 0.000000e0, total = 1.050000e1\n"
        ),
        "{}",
        stdout(&o)
    );
    let o = elasto(tmp.path(), &["check", "hanging-bar-2d"]);
    assert_code(&o, 0);
    let line = stdout(&o)
        .lines()
        .find(|l| l.starts_with("  energy at t = 0"))
        .unwrap()
        .to_owned();
    assert!(
        line.contains("gravity = ") && !line.contains("barrier"),
        "{line}"
    );
}
