//! Issue 33, item 5: valid-looking extreme parameters passed `check` and
//! then failed at step 0 (`--set material.density=1e-20`,
//! `--set effects.ground.a=1e50`) or ran every step into the iteration cap
//! (`--set material.young=1e20` with Neo-Hookean, stable Neo-Hookean and
//! fixed corotated). Now `check` and `run` refuse them with exit 2 before
//! any work, naming the key and the limit: the masses lost beside dt² times
//! the stiffness (more than 1e12 between them at a vertex), a ground barrier
//! wider than 100 times the scene's size.

use crate::cli_common as common;
use common::*;

/// `check` and `run` both refuse `sets` on the default scene with exit 2,
/// naming `key` and saying `expected`; the run writes nothing.
fn refused(sets: &[&str], key: &str, expected: &[&str]) {
    let tmp = tempfile::tempdir().unwrap();
    let mut with_sets: Vec<&str> = Vec::new();
    for set in sets {
        with_sets.extend(["--set", set]);
    }
    for command in [
        &["check", "report-drop-2d"][..],
        &["run", "--no-render", "-q", "-o", "o"],
    ] {
        let o = elasto(tmp.path(), &[command, &with_sets[..]].concat());
        assert_code(&o, 2);
        let err = stderr(&o);
        assert!(
            err.contains(&format!("`{key}`: ")) && !err.contains("{ "),
            "{sets:?}: {err}"
        );
        for part in expected {
            assert!(err.contains(part), "{sets:?}: {part:?} not in {err}");
        }
    }
    assert!(!tmp.path().join("o").exists());
}

#[test]
fn masses_lost_beside_the_stiffness_are_refused_naming_the_key_and_limit() {
    refused(
        &["material.density=1e-20"],
        "material.density",
        &[
            "the masses are lost beside the stiffness: dt² (λ + 2μ) / mass reaches 6.731e19",
            "more than the 1e12 up to which",
            "by a factor of at least 6.731e7",
        ],
    );
    for model in [
        "stvk",
        "neo-hookean",
        "stable-neo-hookean",
        "fixed-corotated",
    ] {
        refused(
            &[&format!("material.model={model}"), "material.young=1e20"],
            "material.young",
            &["reaches 2.244e17", "more than the 1e12"],
        );
    }
    // The key the user changed last is the one named.
    refused(
        &["material.young=1e16", "time.substeps=1"],
        "time.substeps",
        &["more than the 1e12"],
    );
}

#[test]
fn a_ground_barrier_far_wider_than_the_scene_is_refused() {
    refused(
        &["effects.ground.a=1e50"],
        "effects.ground.a",
        &[
            "1e50 is more than 100 times the scene's size 11.41",
            "at most 1141 here",
        ],
    );
}

#[test]
fn stiff_but_representable_parameters_still_run() {
    let tmp = tempfile::tempdir().unwrap();
    // young = 1e14: dt² (λ + 2μ) / mass = 2.2e11, below the limit: the box
    // falls as backward Euler drops it, g dt² n (n + 1) / 2 after n steps
    // (frame 9: n = 90 steps of 1/300 s, 0.0455).
    let o = elasto(
        tmp.path(),
        &[
            "run",
            "--no-render",
            "-q",
            "--strict",
            "--frames",
            "10",
            "-o",
            "o",
            "--set",
            "material.young=1e14",
        ],
    );
    assert_code(&o, 0);
    let (header, rows) = read_csv(&tmp.path().join("o/stats.csv"));
    let com_y = header.iter().position(|c| c == "com_y").unwrap();
    let fall = 10.5 - rows[9][com_y].parse::<f64>().unwrap();
    let expected = 90.0 * 91.0 / 2.0 / 300.0_f64.powi(2);
    assert!(
        (fall - expected).abs() < 1e-6,
        "fell {fall}, not {expected}"
    );
    // A barrier wider than the gap but within 100 times the scene: a warning.
    let o = elasto(
        tmp.path(),
        &["check", "report-drop-2d", "--set", "effects.ground.a=1000"],
    );
    assert_code(&o, 0);
    assert!(stdout(&o).contains("warning"), "{}", stdout(&o));
}
