//! Bad input exits with code 2 and a message naming the file, the key and the line.

use crate::cli_common as common;
use common::*;

/// Writes `text` as a scene file, runs `run` on it and returns stderr after checking exit code 2.
fn run_bad(text: &str, extra: &[&str]) -> String {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("bad.toml"), text).unwrap();
    let mut args = vec!["run", "bad.toml", "--no-render", "--out", "result"];
    args.extend_from_slice(extra);
    let o = elasto(tmp.path(), &args);
    assert_code(&o, 2);
    // Nothing was written.
    assert!(!tmp.path().join("result").exists());
    let err = stderr(&o);
    assert!(!err.contains("panicked"), "{err}");
    err
}

fn replace(old: &str, new: &str) -> String {
    assert!(SMALL_SCENE.contains(old));
    SMALL_SCENE.replacen(old, new, 1)
}

#[test]
fn bad_scene_files_name_file_key_and_line() {
    let cases: &[(String, &str, &str)] = &[
        (
            replace("young = 300.0", "young = 300.0\nyoungs = 1"),
            "bad.toml:11:",
            "material.youngs",
        ),
        (
            replace("young = 300.0", "young = -300.0"),
            "bad.toml:10:",
            "material.young",
        ),
        (
            replace("poisson = 0.3", "poisson = 0.5"),
            "bad.toml:11:",
            "material.poisson",
        ),
        (
            replace("offset = [0.0, 1.0]", "offset = [0.0, -0.5]"),
            "bad.toml:6:",
            "mesh.offset",
        ),
        (
            replace("young = 300.0", "young = 300.0.0"),
            "bad.toml:10:",
            "invalid TOML",
        ),
        (
            replace("young = 300.0", "young = \"hard\""),
            "bad.toml:10:",
            "material.young",
        ),
        (
            replace("frames = 4", "frames = 0"),
            "bad.toml:14:",
            "time.frames",
        ),
        (
            replace("frames = 4", "frames = 4\ndt = 0.0"),
            "bad.toml:15:",
            "time.dt",
        ),
        (
            replace("frames = 4", "frames = 4\ndt = -1e-3"),
            "bad.toml:15:",
            "time.dt",
        ),
    ];
    for (text, position, key) in cases {
        let err = run_bad(text, &[]);
        assert!(err.contains(position), "expected {position} in: {err}");
        assert!(err.contains(key), "expected {key} in: {err}");
        assert_eq!(err.lines().count(), 1, "one clear line: {err}");
    }
}

#[test]
fn bad_overrides_name_the_flag() {
    let err = run_bad(SMALL_SCENE, &["--set", "material.stiffness=3"]);
    assert!(
        err.contains("--set material.stiffness=3") && err.contains("unknown field"),
        "{err}"
    );
    let err = run_bad(SMALL_SCENE, &["--set", "physics.gravity=3"]);
    assert!(err.contains("--set physics.gravity=3"), "{err}");
    let err = run_bad(SMALL_SCENE, &["--set", "material.young"]);
    assert!(
        err.contains("--set material.young") && err.contains("key.path=value"),
        "{err}"
    );
    let err = run_bad(SMALL_SCENE, &["--set", "time.frames=-2"]);
    assert!(err.contains("time.frames"), "{err}");
    let err = run_bad(SMALL_SCENE, &["--frames", "0"]);
    assert!(
        err.contains("--frames 0") && err.contains("time.frames"),
        "{err}"
    );
}

#[test]
fn bad_flags_and_missing_scenes_exit_2() {
    let tmp = tempfile::tempdir().unwrap();
    for args in [
        &["run", "missing.toml"][..],
        &["run", "no-such-builtin"],
        &["run", "--resolution", "wide"],
        &["run", "--video", "avi"],
        &["run", "--frames", "many"],
        &["check"],
        &["frobnicate"],
    ] {
        let o = elasto(tmp.path(), args);
        assert_code(&o, 2);
        assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
    }
    let o = elasto(tmp.path(), &["run", "missing.toml"]);
    assert!(stderr(&o).contains("missing.toml"), "{}", stderr(&o));
    let o = elasto(tmp.path(), &["--help"]);
    assert_code(&o, 0);
    for command in ["run", "scenes", "check", "compare"] {
        assert!(stdout(&o).contains(command));
    }
}
