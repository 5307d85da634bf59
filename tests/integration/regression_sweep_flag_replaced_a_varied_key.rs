//! Issue 33, item 19: `sweep --frames N` silently replaced a varied
//! `time.frames` in every run, and `sweep.csv` reported the varied values
//! that never ran. Now a shortcut flag that would replace a varied key
//! (`--frames` against `time.frames` or `time.duration`, `--resolution`
//! against `render.resolution`) is exit 2 naming both, before any work.

use crate::cli_common as common;
use common::*;

#[test]
fn a_shortcut_flag_that_would_replace_a_varied_key_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("s.toml"), SMALL_SCENE).unwrap();
    for (vary, flag, value, key) in [
        ("time.frames=3,4", "--frames", "5", "time.frames"),
        ("time.duration=0.1,0.2", "--frames", "5", "time.duration"),
        (
            "render.resolution=[64,48],[32,24]",
            "--resolution",
            "80x60",
            "render.resolution",
        ),
    ] {
        let o = elasto(
            tmp.path(),
            &[
                "sweep",
                "s.toml",
                "--vary",
                vary,
                flag,
                value,
                "-o",
                "sw",
                "--no-render",
            ],
        );
        assert_code(&o, 2);
        let err = stderr(&o);
        assert!(
            err.contains(&format!("`{flag} {value}`"))
                && err.contains(&format!("would replace the varied {key} in every run")),
            "{vary}: {err}"
        );
        assert!(!tmp.path().join("sw").exists(), "{vary}: wrote a folder");
    }
    // A flag that replaces no varied key still works.
    let o = elasto(
        tmp.path(),
        &[
            "sweep",
            "s.toml",
            "--vary",
            "material.young=100,200",
            "--frames",
            "3",
            "-o",
            "sw",
            "--no-render",
            "--quiet",
        ],
    );
    assert_code(&o, 0);
}
