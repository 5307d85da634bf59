//! Issue 9, item 10: runs whose steps hit the iteration cap, or whose elements
//! inverted, finished with exit code 0 and not a word. They now end with a
//! one-line health summary on stderr, and `--strict` makes them exit 1.

#[path = "cli_common.rs"]
mod common;
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
    assert!(
        err.starts_with(
            "error: scene `report-drop-2d` ran with problems (--strict): 20 of 20 steps"
        ),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    // The outputs are complete all the same.
    let (_, rows) = read_csv(&tmp.path().join("strict/stats.csv"));
    assert_eq!(rows.len(), 3);
}

#[test]
fn inverted_elements_are_summarised_and_fail_strict_runs() {
    // A very soft St. Venant-Kirchhoff box thrown at the ground inverts.
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
    let line = health_line(&err).unwrap_or_else(|| panic!("no health line in: {err}"));
    assert!(
        line.contains("0 of 90 steps hit the iteration cap"),
        "{line}"
    );
    assert!(line.contains(": inverted elements"), "{line}");
    // The summary's minimum is the stats file's.
    let (header, rows) = read_csv(&tmp.path().join("thrown/stats.csv"));
    let j = header.iter().position(|h| h == "min_volume_ratio").unwrap();
    let (frame, lowest) = rows
        .iter()
        .enumerate()
        .map(|(i, r)| (i, r[j].parse::<f64>().unwrap()))
        .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
    assert!(lowest < 0.0, "{lowest}");
    assert!(
        line.contains(&format!("(frame {frame}): inverted elements")),
        "frame {frame}, J = {lowest}: {line}"
    );

    let o = elasto(tmp.path(), &[&args[..], &["--strict"]].concat());
    assert_code(&o, 1);
    assert!(stderr(&o).contains("inverted elements"), "{}", stderr(&o));
}
