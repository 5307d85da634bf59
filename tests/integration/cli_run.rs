//! `elasto run` end to end: outputs, overrides, meshes, refusing to overwrite, rendering.

use crate::cli_common as common;
use common::*;
use std::path::Path;

fn parse(cell: &str) -> f64 {
    cell.parse()
        .unwrap_or_else(|_| panic!("`{cell}` is not a number"))
}

fn column<'a>(header: &[String], row: &'a [String], name: &str) -> &'a str {
    &row[column_index(header, name)]
}

#[test]
fn default_scene_writes_scene_and_stats() {
    let tmp = tempfile::tempdir().unwrap();
    let o = elasto(tmp.path(), &["run", "--frames", "3", "--no-render"]);
    assert_code(&o, 0);
    let out = tmp.path().join("out/report-drop-2d");
    let (header, rows) = read_csv(&out.join("stats.csv"));
    assert_eq!(&header[..REQUIRED_COLUMNS.len()], REQUIRED_COLUMNS);
    assert_eq!(rows.len(), 3);
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row.len(), header.len());
        assert_eq!(column(&header, row, "frame"), i.to_string());
        assert!((parse(column(&header, row, "time")) - i as f64 / 30.0).abs() < 1e-9);
        assert_eq!(column(&header, row, "com_z"), "0");
        // The box starts 10 units above the ground and has fallen only a little.
        let h = parse(column(&header, row, "min_height"));
        assert!(h > 9.9 && h <= 10.0 + 1e-12, "{h}");
        let total = parse(column(&header, row, "total_energy"));
        let sum: f64 = ["kinetic", "elastic", "gravity", "barrier"]
            .iter()
            .map(|c| parse(column(&header, row, c)))
            .sum();
        assert!((total - sum).abs() <= 1e-9 * total.abs().max(1.0));
    }
    // Frame 0 is the initial state: at rest, undeformed, no iterations.
    assert_eq!(column(&header, &rows[0], "newton_iters"), "0");
    assert_eq!(parse(column(&header, &rows[0], "kinetic")), 0.0);
    assert!((parse(column(&header, &rows[0], "min_volume_ratio")) - 1.0).abs() < 1e-12);
    assert!((parse(column(&header, &rows[0], "com_y")) - 10.5).abs() < 1e-12);
    // Later frames moved down and took Newton iterations.
    assert!(parse(column(&header, &rows[2], "com_y")) < 10.5);
    assert!(parse(column(&header, &rows[2], "newton_iters")) >= 1.0);
    assert!(parse(column(&header, &rows[2], "kinetic")) > 0.0);
    // The resolved scene is a runnable scene with every default written out.
    let scene = std::fs::read_to_string(out.join("scene.toml")).unwrap();
    let table: toml::Table = scene.parse().unwrap();
    assert_eq!(table["time"]["frames"].as_integer(), Some(3));
    assert_eq!(table["time"]["substeps"].as_integer(), Some(10));
    assert_eq!(table["material"]["density"].as_float(), Some(1.0));
    assert!(!out.join("frames").exists());
    // Progress lines go to stderr when it is not a terminal.
    assert!(stderr(&o).contains("3/3 frames"), "{}", stderr(&o));
}

#[test]
fn quiet_prints_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let o = elasto(
        tmp.path(),
        &[
            "run",
            "--frames",
            "2",
            "--no-render",
            "--quiet",
            "--out",
            "q",
        ],
    );
    assert_code(&o, 0);
    assert_eq!(stderr(&o), "");
    assert_eq!(stdout(&o), "");
}

#[test]
fn set_overrides_take_effect_and_land_in_scene_toml() {
    let tmp = tempfile::tempdir().unwrap();
    let o = elasto(
        tmp.path(),
        &[
            "run",
            "--set",
            "time.frames=2",
            "--set",
            "material.young=1234.5",
            "--no-render",
            "--out",
            "o",
            "-q",
        ],
    );
    assert_code(&o, 0);
    let (_, rows) = read_csv(&tmp.path().join("o/stats.csv"));
    assert_eq!(rows.len(), 2);
    let table: toml::Table = std::fs::read_to_string(tmp.path().join("o/scene.toml"))
        .unwrap()
        .parse()
        .unwrap();
    assert_eq!(table["material"]["young"].as_float(), Some(1234.5));
    // Re-running the resolved scene reproduces the data exactly (deterministic).
    let o = elasto(
        tmp.path(),
        &["run", "o/scene.toml", "--no-render", "--out", "again", "-q"],
    );
    assert_code(&o, 0);
    let strip = |p: &Path| {
        let (h, rows) = read_csv(p);
        let timing: Vec<usize> = h
            .iter()
            .enumerate()
            .filter(|(_, c)| c.ends_with("_ms"))
            .map(|(i, _)| i)
            .collect();
        rows.into_iter()
            .map(|r| {
                r.into_iter()
                    .enumerate()
                    .filter(|(i, _)| !timing.contains(i))
                    .map(|(_, c)| c)
                    .collect::<Vec<_>>()
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(
        strip(&tmp.path().join("o/stats.csv")),
        strip(&tmp.path().join("again/stats.csv"))
    );
}

#[test]
fn save_meshes_writes_vtu_and_pvd() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("small.toml"), SMALL_SCENE).unwrap();
    let o = elasto(
        tmp.path(),
        &[
            "run",
            "small.toml",
            "--frames",
            "3",
            "--no-render",
            "--save-meshes",
            "-q",
        ],
    );
    assert_code(&o, 0);
    let meshes = tmp.path().join("out/small/meshes");
    for i in 0..3 {
        let vtu = std::fs::read_to_string(meshes.join(format!("frame_{i:04}.vtu"))).unwrap();
        assert!(
            vtu.contains("NumberOfPoints=\"9\" NumberOfCells=\"8\""),
            "{vtu}"
        );
        assert!(vtu.contains("Name=\"energy_density\""));
    }
    assert!(!meshes.join("frame_0003.vtu").exists());
    let pvd = std::fs::read_to_string(meshes.join("frames.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), 3);
    assert!(
        pvd.contains(&format!("timestep=\"{}\"", 2.0 / 30.0)),
        "{pvd}"
    );
}

#[test]
fn existing_output_is_kept_without_force_and_replaced_with_it() {
    let tmp = tempfile::tempdir().unwrap();
    let first = elasto(
        tmp.path(),
        &["run", "--frames", "2", "--no-render", "--out", "o", "-q"],
    );
    assert_code(&first, 0);
    let read = |name: &str| std::fs::read(tmp.path().join("o").join(name)).unwrap();
    let (scene, stats) = (read("scene.toml"), read("stats.csv"));

    let again = elasto(
        tmp.path(),
        &["run", "--frames", "3", "--no-render", "--out", "o"],
    );
    assert_code(&again, 2);
    assert!(stderr(&again).contains("--force"), "{}", stderr(&again));
    assert_eq!(read("scene.toml"), scene);
    assert_eq!(read("stats.csv"), stats);

    let forced = elasto(
        tmp.path(),
        &[
            "run",
            "--frames",
            "3",
            "--no-render",
            "--out",
            "o",
            "--force",
            "-q",
        ],
    );
    assert_code(&forced, 0);
    assert_eq!(read_csv(&tmp.path().join("o/stats.csv")).1.len(), 3);
}

#[test]
fn every_builtin_runs_a_few_frames() {
    let tmp = tempfile::tempdir().unwrap();
    for name in ["drop-3d", "hanging-bar-2d", "hanging-bar-3d"] {
        let o = elasto(
            tmp.path(),
            &["run", name, "--frames", "3", "--no-render", "-q"],
        );
        assert_code(&o, 0);
        let (header, rows) = read_csv(&tmp.path().join("out").join(name).join("stats.csv"));
        assert_eq!(rows.len(), 3);
        let without_ground = name.starts_with("hanging");
        assert_eq!(
            column(&header, &rows[2], "min_height").is_empty(),
            without_ground,
            "{name}"
        );
        // Everything falls or sags: the centre of mass goes down.
        assert!(
            parse(column(&header, &rows[2], "com_y")) < parse(column(&header, &rows[0], "com_y")),
            "{name}"
        );
    }
}

/// Issue 31, item 6: the data files write numbers in the shortest round-trip
/// form, with an exponent where that is shorter (docs/reference.md), so no
/// cell of `stats.csv` is a long run of zeros, and the OBJ's coordinates
/// are as short.
#[test]
fn stats_and_surfaces_write_short_numbers() {
    let tmp = tempfile::tempdir().unwrap();
    let o = elasto(
        tmp.path(),
        &[
            "run",
            "drop-3d",
            "--frames",
            "4",
            "--no-render",
            "--save-surface",
            "obj",
            "--out",
            "o",
        ],
    );
    assert_code(&o, 0);
    let (header, rows) = read_csv(&tmp.path().join("o/stats.csv"));
    assert_eq!(rows.len(), 4);
    for row in &rows {
        for (name, cell) in header.iter().zip(row) {
            assert!(
                cell.len() <= 24,
                "{name} = {cell}: {} characters",
                cell.len()
            );
            // The timings are milliseconds with three decimals; every other
            // number is the shorter of its plain and exponent forms.
            if !cell.is_empty() && !name.ends_with("_ms") {
                let x = parse(cell);
                let shortest = x.to_string().len().min(format!("{x:e}").len());
                assert_eq!(
                    cell.len(),
                    shortest,
                    "{name} = {cell} is not as short as it can be"
                );
            }
        }
    }
    let obj = std::fs::read_to_string(tmp.path().join("o/surfaces/surface_0003.obj")).unwrap();
    let mut vertices = 0;
    for line in obj.lines().filter(|l| l.starts_with("v ")) {
        for word in line.split_whitespace().skip(1) {
            assert!(word.len() <= 15, "{line}");
            let x: f32 = word.parse().unwrap();
            assert!(x.is_finite(), "{line}");
        }
        vertices += 1;
    }
    assert!(vertices > 0, "{obj}");
}
