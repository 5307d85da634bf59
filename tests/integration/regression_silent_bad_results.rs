//! Issue 9, item 10: runs whose steps hit the iteration cap, stalled, or whose
//! elements inverted, finished with exit code 0 and not a word. They now end with a
//! one-line health summary on stderr, and `--strict` makes them exit 1.

use crate::cli_common as common;
use common::*;

fn health_line(err: &str) -> Option<&str> {
    err.lines().find(|l| l.contains("health:"))
}

#[test]
fn a_healthy_run_says_nothing_and_passes_strict() {
    let tmp = tempfile::tempdir().unwrap();
    let o = elasto(
        tmp.path(),
        &[
            "run",
            "--no-render",
            "--frames",
            "3",
            "-q",
            "--strict",
            "-o",
            "a",
        ],
    );
    assert_code(&o, 0);
    assert_eq!(stderr(&o), "");
}

#[test]
fn steps_at_the_iteration_cap_are_summarised_and_fail_strict_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let args = [
        "run",
        "--no-render",
        "--frames",
        "3",
        "--set",
        "solver.max_iterations=1",
        "--set",
        "solver.max_subdivisions=0",
    ];
    let o = elasto(tmp.path(), &[&args[..], &["-o", "lenient", "-q"]].concat());
    assert_code(&o, 0);
    let err = stderr(&o);
    let line = health_line(&err).unwrap_or_else(|| panic!("no health line in: {err}"));
    // 2 frames of 10 substeps, each stopped after its single Newton iteration.
    assert!(
        line.starts_with(
            "warning: report-drop-2d: health: 20 of 20 steps hit the iteration cap \
             (max_iterations = 1), 0 stalled in the line search"
        ) && line.contains("min volume ratio 1 (frame 0)")
            && line.contains("lowest ground gap"),
        "{line}"
    );
    let (_, rows) = read_csv(&tmp.path().join("lenient/stats.csv"));
    assert_eq!(rows.len(), 3);

    let o = elasto(
        tmp.path(),
        &[&args[..], &["-o", "strict", "-q", "--strict"]].concat(),
    );
    assert_code(&o, 1);
    let err = stderr(&o);
    // --strict stops at the first frame with an unconverged step, saying so.
    assert!(
        err.starts_with(
            "error: scene `report-drop-2d` ran with problems (--strict): frame 1 \
             (t = 0.033333 s): 10 step(s) hit the iteration cap"
        ),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    // The frames simulated so far are kept.
    let (_, rows) = read_csv(&tmp.path().join("strict/stats.csv"));
    assert_eq!(rows.len(), 2);
}

#[test]
fn a_thrown_soft_stvk_box_no_longer_stalls() {
    // A very soft St. Venant-Kirchhoff box thrown at the ground used to
    // invert (issue 12), then, held above a J floor, to stall (issue 30).
    // Its volume barrier keeps it uninverted and its steps converge: no
    // health line, no stalled step.
    let tmp = tempfile::tempdir().unwrap();
    let args = [
        "run",
        "--no-render",
        "--frames",
        "10",
        "--set",
        "material.young=1",
        "--set",
        "mesh.velocity=[0, -20]",
        "--set",
        "mesh.offset=[0, 0.5]",
        "-o",
        "thrown",
        "--force",
    ];
    let o = elasto(tmp.path(), &args);
    assert_code(&o, 0);
    let err = stderr(&o);
    assert!(health_line(&err).is_none(), "{err}");
    let (header, rows) = read_csv(&tmp.path().join("thrown/stats.csv"));
    let column = |name: &str| header.iter().position(|h| h == name).unwrap();
    let stalled: usize = rows
        .iter()
        .map(|r| r[column("stalled_steps")].parse::<usize>().unwrap())
        .sum();
    assert_eq!(stalled, 0, "the thrown box stalled: {err}");
    for row in &rows {
        let j: f64 = row[column("min_volume_ratio")].parse().unwrap();
        assert!(j > 0.0, "an element inverted: {row:?}");
    }

    // Healthy, so --strict passes too.
    let o = elasto(tmp.path(), &[&args[..], &["--strict"]].concat());
    assert_code(&o, 0);
}
