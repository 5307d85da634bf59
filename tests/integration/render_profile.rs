//! `elasto run --profile`: the table names every phase, rendering included
//! (streamed or rendered after the simulation), with numbers that add up;
//! the run, and the rendering after the simulation, show the cores busy
//! over them. `stats.csv` has one row per frame whether or not the run
//! renders, and no rendering columns: its rows do not wait for the images.

use crate::cli_common as common;
use common::*;

/// The numbers of the table row of `phase` on stdout (for a span's row,
/// the wall time and the cores busy out of the machine's).
fn row(table: &str, phase: &str) -> Vec<f64> {
    let line = table
        .lines()
        .find(|l| l.starts_with(phase))
        .unwrap_or_else(|| panic!("no row `{phase}` in:\n{table}"));
    let line = line[phase.len()..].trim_end();
    let line = line.strip_suffix("cores busy").unwrap_or(line);
    line.split_whitespace()
        .filter(|&v| v != "of" && v != "+")
        .map(|v| v.parse().unwrap())
        .collect()
}

/// The wall time and cores busy of a span's row, checked against the
/// machine's cores: the process's CPU time over a stretch cannot exceed
/// its cores times the wall time.
fn span(table: &str, name: &str) -> (f64, f64) {
    let [wall, busy, cores] = row(table, name)[..] else {
        panic!("{name}: {table}")
    };
    let machine = std::thread::available_parallelism().unwrap().get() as f64;
    assert_eq!(cores, machine, "{table}");
    assert!(wall > 0.0 && busy > 0.0, "{table}");
    assert!(busy <= cores * 1.02 + 0.05, "{table}");
    (wall, busy)
}

fn cell(header: &[String], row: &[String], name: &str) -> f64 {
    let i = column_index(header, name);
    row[i]
        .parse()
        .unwrap_or_else(|_| panic!("{name} = `{}`", row[i]))
}

/// Runs the small scene, 5 frames at 64x48, with `extra` flags.
fn run(dir: &std::path::Path, extra: &[&str]) -> std::process::Output {
    std::fs::write(
        dir.join("scene.toml"),
        SMALL_SCENE.replace("frames = 4", "frames = 5"),
    )
    .unwrap();
    let mut args = vec!["run", "scene.toml", "--resolution", "64x48", "--out", "r"];
    args.extend(extra);
    elasto(dir, &args)
}

#[test]
fn profile_prints_every_phase_with_the_rendering_after_the_simulation() {
    let tmp = tempfile::tempdir().unwrap();
    // The automatic camera: rendered after the simulation, from kept frames.
    let o = run(tmp.path(), &["--profile", "--video", "apng", "--quiet"]);
    assert_code(&o, 0);
    let table = stdout(&o);
    for phase in [
        "assembly",
        "factorisation",
        "solve",
        "line search",
        "other simulation",
    ] {
        let [frames, median, total] = row(&table, phase)[..] else {
            panic!("{phase}: {table}")
        };
        assert_eq!(frames, 4.0, "frame 0 is not simulated: {table}");
        assert!(median >= 0.0 && total >= 0.0, "{table}");
    }
    let mut rendering_total = 0.0;
    for phase in [
        "draw",
        "readback",
        "paste + legend",
        "PNG encode + write",
        "video encode + write",
    ] {
        let [frames, median, total] = row(&table, phase)[..] else {
            panic!("{phase}: {table}")
        };
        assert_eq!(frames, 5.0, "{table}");
        // The median of 5 values is at most their sum.
        assert!(median / 1e3 <= total + 1e-3, "{phase}: {table}");
        rendering_total += total;
    }
    assert!(row(&table, "draw")[2] > 0.0, "{table}");
    let (wall, _) = span(&table, "wall time of the run");
    let (rendering, _) = span(&table, "rendering after the simulation");
    assert!(rendering < wall, "{table}");
    let (frames, _) = span(&table, "frames drawn, encoded and written");
    assert!(frames <= rendering, "{table}");

    assert!(rendering_total > 0.0, "{table}");
    assert_stats_rows(&tmp.path().join("r/stats.csv"));
}

/// `stats.csv` has one row per frame, in order, and no rendering columns.
fn assert_stats_rows(path: &std::path::Path) {
    let (header, rows) = read_csv(path);
    assert_eq!(rows.len(), 5);
    assert!(
        !header.iter().any(|c| c == "render_ms" || c == "encode_ms"),
        "{header:?}"
    );
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r.len(), header.len(), "row {i}");
        assert_eq!(cell(&header, r, "frame"), i as f64, "rows in frame order");
    }
}

#[test]
fn a_streamed_run_profiles_its_rendering_too() {
    let tmp = tempfile::tempdir().unwrap();
    // A fixed camera and range: frames are rendered while simulating.
    let streamed = [
        "--video",
        "none",
        "--quiet",
        "--set",
        "render.camera.center=[0.5, 1.0]",
        "--set",
        "render.camera.height=3.0",
        "--set",
        "render.range=[0.0, 1.0]",
    ];
    let o = run(tmp.path(), &streamed);
    assert_code(&o, 0);
    assert!(stdout(&o).is_empty(), "no table without --profile");
    let o = run(
        tmp.path(),
        &[&streamed[..], &["--force", "--profile"]].concat(),
    );
    assert_code(&o, 0);
    let table = stdout(&o);
    span(&table, "wall time of the run");
    assert!(
        !table.contains("rendering after") && !table.contains("frames drawn"),
        "nothing waits for the run: {table}"
    );
    for phase in ["draw", "PNG encode + write"] {
        let [frames, median, _] = row(&table, phase)[..] else {
            panic!("{phase}: {table}")
        };
        assert_eq!(frames, 5.0, "{table}");
        assert!(median > 0.0, "{phase}: {table}");
    }
    assert_stats_rows(&tmp.path().join("r/stats.csv"));
}

#[test]
fn without_rendering_the_table_has_no_rendering_phases() {
    let tmp = tempfile::tempdir().unwrap();
    let o = run(tmp.path(), &["--no-render", "--profile", "--quiet"]);
    assert_code(&o, 0);
    let table = stdout(&o);
    assert_eq!(row(&table, "assembly")[0], 4.0);
    assert!(!table.contains("draw"), "{table}");
    assert_stats_rows(&tmp.path().join("r/stats.csv"));
}
