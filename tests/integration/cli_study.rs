//! `elasto study`: the files it writes, the errors and orders it measures, and bad input.

use crate::cli_common as common;
use common::*;

use std::path::Path;

/// A 2D bar pinned at its left end, released from rest under gravity: a
/// smooth free vibration without contact.
const HANGING_BAR: &str = r#"name = "hanging-bar"
dimension = 2

[mesh]
size = [2.0, 0.25]
cells = [8, 1]

[material]
model = "neo-hookean"
young = 2000.0
poisson = 0.3
density = 100.0

[time]
fps = 10
frames = 11

[effects.gravity]
acceleration = [0.0, -9.81]

[effects.pinned]
min = [-0.01, -1.0]
max = [0.01, 1.0]
"#;

/// The study's CSV: header and rows (RFC 4180 quoting: a value such as
/// `[8, 1]` is quoted).
fn study_csv(dir: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    read_csv(&dir.join("study.csv"))
}

fn column(header: &[String], name: &str) -> usize {
    column_index(header, name)
}

/// The order printed for a series, from stdout.
fn printed_order(out: &str, series: &str) -> f64 {
    let line = out
        .lines()
        .find(|l| l.trim_start().starts_with(series))
        .unwrap_or_else(|| panic!("no order for {series} in:\n{out}"));
    line.split(':')
        .nth(1)
        .unwrap()
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn a_study_writes_its_files_and_measures_the_orders_of_the_integrators() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bar.toml"), HANGING_BAR).unwrap();
    let out = elasto(
        dir.path(),
        &[
            "study",
            "bar.toml",
            "--vary",
            "time.substeps=8,16,32",
            "--vary",
            "time.integrator=backward-euler,bdf2,newmark",
            "--repeat",
            "3",
            "-o",
            "study",
        ],
    );
    assert_code(&out, 0);
    let study = dir.path().join("study");

    // One row per run plus the reference, which has no error.
    let (header, rows) = study_csv(&study);
    assert_eq!(rows.len(), 1 + 9, "{rows:?}");
    let (run, substeps, series, dt, status, repeats, error, energy, kind) = (
        column(&header, "run"),
        column(&header, "time.substeps"),
        column(&header, "series"),
        column(&header, "dt"),
        column(&header, "status"),
        column(&header, "repeats"),
        column(&header, "trajectory_error"),
        column(&header, "energy_error"),
        column(&header, "error_kind"),
    );
    assert_eq!(rows[0][run], "reference");
    assert_eq!(rows[0][substeps], "128", "the finest step / 4");
    assert_eq!(rows[0][series], "newton / bdf2");
    assert_eq!(rows[0][error].parse::<f64>().unwrap(), 0.0);
    for row in &rows[1..] {
        assert_eq!(row[status], "ok");
        assert_eq!(row[repeats], "3");
        let cpu: f64 = row[column(&header, "cpu_ms")].parse().unwrap();
        assert!(cpu > 0.0, "{row:?}");
        assert_eq!(row[kind], "vertices");
        let e: f64 = row[error].parse().unwrap();
        assert!(e > 0.0 && e < 0.5, "error {e} of {row:?}");
        assert!(row[energy].parse::<f64>().unwrap().is_finite());
        let dt: f64 = row[dt].parse().unwrap();
        let n: f64 = row[substeps].parse().unwrap();
        assert!((dt * 10.0 * n - 1.0).abs() < 1e-12);
    }
    // Backward Euler's error halves with the step; the second-order
    // schemes are far more accurate at the same step.
    let error_of = |series_name: &str, n: &str| -> f64 {
        rows[1..]
            .iter()
            .find(|r| r[series] == series_name && r[substeps] == n)
            .unwrap()[error]
            .parse()
            .unwrap()
    };
    let be = [8, 16, 32].map(|n| error_of("newton / backward-euler", &n.to_string()));
    assert!(be[0] > 1.6 * be[1] && be[1] > 1.6 * be[2], "{be:?}");
    for second in ["newton / bdf2", "newton / newmark"] {
        assert!(error_of(second, "32") < be[2] / 5.0, "{second}");
    }

    // The printed orders: 1 for backward Euler, 2 for BDF2 and Newmark.
    let text = stdout(&out);
    let be_order = printed_order(&text, "newton / backward-euler");
    assert!((be_order - 1.0).abs() < 0.15, "{text}");
    for second in ["newton / bdf2", "newton / newmark"] {
        let order = printed_order(&text, second);
        assert!((order - 2.0).abs() < 0.3, "{second}: {text}");
    }

    // The Markdown table has a line per row, and the plot is a real plot.
    let md = std::fs::read_to_string(study.join("study.md")).unwrap();
    assert_eq!(md.lines().count(), 2 + 10);
    let plot = image::open(study.join("study.png")).unwrap().to_rgb8();
    assert_eq!(plot.dimensions(), (1200, 800));
    let coloured = plot
        .pixels()
        .filter(|p| p.0.iter().max().unwrap() - p.0.iter().min().unwrap() > 80)
        .count();
    let dark = plot
        .pixels()
        .filter(|p| p.0.iter().all(|&c| c < 80))
        .count();
    assert!(
        coloured > 1000,
        "{coloured} coloured pixels: the three series"
    );
    assert!(dark > 2000, "{dark} dark pixels: axes, ticks and labels");
}

#[test]
fn a_series_of_the_reports_method_and_a_mesh_study_by_centre_of_mass() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bar.toml"), HANGING_BAR).unwrap();
    let out = elasto(
        dir.path(),
        &[
            "study",
            "bar.toml",
            "--frames",
            "4",
            "--vary",
            "mesh.cells=[8,1],[16,2]",
            "--series",
            "time.integrator=backward-euler",
            "--series",
            "solver.method=gradient-descent;solver.max_iterations=100000",
            // A series that fixes the varied key: one run, not two.
            "--series",
            "time.integrator=newmark;mesh.cells=[16,2]",
            "--reference",
            "mesh.cells=[32,4]",
            "--clock",
            "cpu",
            "-o",
            "s",
            "-q",
        ],
    );
    assert_code(&out, 0);
    let (header, rows) = study_csv(&dir.path().join("s"));
    assert_eq!(rows.len(), 1 + 2 + 2 + 1, "{rows:?}");
    let (series, kind, error, iterations) = (
        column(&header, "series"),
        column(&header, "error_kind"),
        column(&header, "trajectory_error"),
        column(&header, "iterations_per_step"),
    );
    assert_eq!(rows[0][kind], "vertices", "the reference against itself");
    let fixed: Vec<_> = rows
        .iter()
        .filter(|r| r[series] == "newton / newmark")
        .collect();
    assert_eq!(fixed.len(), 1);
    assert_eq!(fixed[0][column(&header, "mesh.cells")], "[16, 2]");
    for row in &rows[1..] {
        assert_eq!(row[kind], "centre_of_mass", "{row:?}");
        assert!(row[error].parse::<f64>().unwrap() > 0.0);
    }
    let newton: Vec<&Vec<String>> = rows[1..]
        .iter()
        .filter(|r| r[series] == "newton / backward-euler")
        .collect();
    let descent: Vec<&Vec<String>> = rows[1..]
        .iter()
        .filter(|r| r[series] == "gradient-descent / backward-euler")
        .collect();
    assert_eq!((newton.len(), descent.len()), (2, 2));
    // Gradient descent converges to the same step, at many more iterations.
    for (n, d) in newton.iter().zip(&descent) {
        let (en, ed): (f64, f64) = (n[error].parse().unwrap(), d[error].parse().unwrap());
        assert!(
            (en - ed).abs() < 0.05 * en + 1e-4,
            "newton {en} vs descent {ed}"
        );
        let (itn, itd): (f64, f64) = (
            n[iterations].parse().unwrap(),
            d[iterations].parse().unwrap(),
        );
        assert!(itd > 10.0 * itn, "{itd} vs {itn} iterations per step");
    }
}

#[test]
fn bad_study_input_is_exit_2_before_any_run() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bar.toml"), HANGING_BAR).unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["--vary", "material.yung=1,2"], "yung"),
        (&["--vary", "time.substeps="], "empty"),
        (
            &[
                "--vary",
                "time.substeps=1,2",
                "--vary",
                "time.integrator=bdf2",
                "--zip",
            ],
            "same length",
        ),
        (&["--vary", "time.fps=10,20"], "same output frames"),
        (&["--repeat", "0"], "--repeat 0"),
        (&["--series", "solver.method"], "KEY=VALUE"),
        (&["--reference", "time.substeps=0"], "substeps"),
    ];
    for (flags, expected) in cases {
        let mut args = vec!["study", "bar.toml", "-o", "bad"];
        args.extend_from_slice(flags);
        let out = elasto(dir.path(), &args);
        assert_code(&out, 2);
        assert!(
            stderr(&out).contains(expected),
            "{flags:?}: {}",
            stderr(&out)
        );
        assert!(!dir.path().join("bad").exists(), "{flags:?} wrote files");
    }
}
