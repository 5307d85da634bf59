//! Issue 33, item 22: a run's `scene.toml` named its mesh files by path
//! only, so running it again after a file had changed silently gave other
//! results. Now it records each mesh file's size and XXH3 checksum
//! (`mesh.file_size`, `mesh.file_checksum`); a scene that carries them and
//! meets a changed file is warned about before the run, by `check` and
//! `run`, and refused (exit 2) by `run --strict`.

use crate::cli_common as common;
use common::*;
use std::path::Path;

/// A 2D scene reading `sq.msh` (the test square), and the square beside it.
fn scene_with_mesh_file(dir: &Path) {
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/meshes/square_v2_ascii.msh"),
        dir.join("sq.msh"),
    )
    .unwrap();
    std::fs::write(
        dir.join("s.toml"),
        "dimension = 2\n[mesh]\ngenerator = \"file\"\npath = \"sq.msh\"\n\
         translate = [0.0, 1.0]\n[material]\nmodel = \"stvk\"\nyoung = 300.0\n\
         poisson = 0.3\n[time]\nframes = 3\n[effects.gravity]\n\
         acceleration = [0.0, -1.0]\n[effects.ground]\nheight = 0.0\n",
    )
    .unwrap();
}

/// `mesh.file_size` and `mesh.file_checksum` of a run's scene.toml.
fn recorded(folder: &Path) -> (i64, String) {
    let scene: toml::Table = std::fs::read_to_string(folder.join("scene.toml"))
        .unwrap()
        .parse()
        .unwrap();
    let mesh = &scene["mesh"];
    (
        mesh["file_size"].as_integer().unwrap(),
        mesh["file_checksum"].as_str().unwrap().to_owned(),
    )
}

#[test]
fn a_changed_mesh_file_is_warned_about_and_refused_with_strict() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    scene_with_mesh_file(dir);
    let run = |args: &[&str]| elasto(dir, &[&["run", "--no-render", "-q"][..], args].concat());
    assert_code(&run(&["s.toml", "-o", "a"]), 0);
    let (size, checksum) = recorded(&dir.join("a"));
    assert_eq!(
        size as u64,
        std::fs::metadata(dir.join("sq.msh")).unwrap().len()
    );
    assert!(
        checksum.starts_with("xxh3:") && checksum.len() == 21,
        "{checksum}"
    );
    // The same file: the recorded scene runs without a word, --strict too,
    // and records the same values.
    let o = run(&["a/scene.toml", "-o", "b", "--strict"]);
    assert_code(&o, 0);
    assert_eq!(stderr(&o), "");
    assert_eq!(recorded(&dir.join("b")), (size, checksum.clone()));

    // One byte more (a blank line: the mesh reads the same).
    let mut bytes = std::fs::read(dir.join("sq.msh")).unwrap();
    bytes.push(b'\n');
    std::fs::write(dir.join("sq.msh"), &bytes).unwrap();
    let changed = format!(
        "mesh.path: {} has changed since this scene was written ({size} bytes, {checksum} then, \
         {} bytes, ",
        dir.join("sq.msh").display(),
        size + 1
    );
    let o = run(&["a/scene.toml", "-o", "c"]);
    assert_code(&o, 0);
    assert!(
        stderr(&o).starts_with(&format!("elasto: warning: {changed}")),
        "{}",
        stderr(&o)
    );
    let o = elasto(dir, &["check", "a/scene.toml"]);
    assert_code(&o, 0);
    assert!(stdout(&o).contains(&changed), "{}", stdout(&o));
    let o = run(&["a/scene.toml", "-o", "d", "--strict"]);
    assert_code(&o, 2);
    assert!(
        stderr(&o).contains("`mesh.path`: ") && stderr(&o).contains("(--strict)"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.join("d").exists());

    // The same size, other bytes: the checksum tells.
    let last = bytes.len() - 1;
    bytes[last] = b' ';
    std::fs::write(dir.join("sq.msh"), &bytes).unwrap();
    let o = run(&[
        "a/scene.toml",
        "-o",
        "e",
        "--strict",
        "--set",
        "mesh.file_size=1376",
    ]);
    assert_code(&o, 2);
    assert!(stderr(&o).contains("has changed"), "{}", stderr(&o));
}

#[test]
fn recorded_values_are_checked_like_any_key() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    scene_with_mesh_file(dir);
    for (set, expected) in [
        (
            "mesh.file_checksum=\"md5:1234\"",
            "must be `xxh3:` and 16 hexadecimal digits",
        ),
        ("mesh.file_size=-1", "must be a whole number of bytes >= 0"),
    ] {
        let o = elasto(dir, &["check", "s.toml", "--set", set]);
        assert_code(&o, 2);
        assert!(stderr(&o).contains(expected), "{set}: {}", stderr(&o));
    }
    // A box has no file to record.
    let o = elasto(
        dir,
        &["check", "report-drop-2d", "--set", "mesh.file_size=3"],
    );
    assert_code(&o, 2);
    assert!(
        stderr(&o).contains("is only used with generator = \"file\""),
        "{}",
        stderr(&o)
    );
}
