//! `elasto sweep` end to end: grids, zip, sweep files, determinism across --jobs,
//! failures, validation, the contact sheet and the comparison video (resuming
//! and shards: `sweep_processes.rs`).

use crate::cli_common as common;
use crate::mp4_file::Mp4File;
use common::*;
use std::path::{Path, PathBuf};

/// stats.csv without its timing columns (every `*_ms` column is a wall
/// time, which differs between any two runs).
fn stats_without_timing(path: &Path) -> Vec<Vec<String>> {
    let (header, rows) = read_csv(path);
    let keep: Vec<usize> = (0..header.len())
        .filter(|&i| !header[i].ends_with("_ms"))
        .collect();
    std::iter::once(header)
        .chain(rows)
        .map(|row| keep.iter().map(|&i| row[i].clone()).collect())
        .collect()
}

/// The rows of sweep.csv as maps from column to value.
pub(crate) fn sweep_table(dir: &Path) -> Vec<std::collections::BTreeMap<String, String>> {
    let (header, rows) = read_csv(&dir.join("sweep.csv"));
    rows.into_iter()
        .map(|r| header.iter().cloned().zip(r).collect())
        .collect()
}

pub(crate) fn folders(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.path().is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn a_2x2_grid_runs_every_combination_like_elasto_run() {
    let tmp = tempfile::tempdir().unwrap();
    let o = elasto(
        tmp.path(),
        &[
            "sweep",
            "report-drop-2d",
            "--vary",
            "material.young=100,1000",
            "--vary",
            "time.substeps=1,2",
            "--frames",
            "4",
            "--no-render",
            "--out",
            "grid",
            "--jobs",
            "2",
        ],
    );
    assert_code(&o, 0);
    // stderr is not a terminal: one plain progress line per finished run.
    let err = stderr(&o);
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("runs done")).collect();
    assert_eq!(lines.len(), 4, "{}", stderr(&o));
    assert!(
        lines[3].starts_with("sweep: 4/4 runs done, 0 failed"),
        "{}",
        lines[3]
    );
    let dir = tmp.path().join("grid");
    assert_eq!(
        folders(&dir),
        [
            "0000_material.young=100_time.substeps=1",
            "0001_material.young=100_time.substeps=2",
            "0002_material.young=1000_time.substeps=1",
            "0003_material.young=1000_time.substeps=2",
        ]
    );
    let table = sweep_table(&dir);
    assert_eq!(table.len(), 4);
    for (row, (young, substeps)) in table.iter().zip([(100, 1), (100, 2), (1000, 1), (1000, 2)]) {
        assert_eq!(row["material.young"], young.to_string());
        assert_eq!(row["time.substeps"], substeps.to_string());
        assert_eq!(row["status"], "ok");
        assert_eq!(row["exit_code"], "0");
        assert_eq!(row["frames"], "4");
        // 3 frames of `substeps` steps, at least one Newton iteration each.
        let iterations: u64 = row["newton_iterations"].parse().unwrap();
        assert!(iterations >= 3 * substeps, "{row:?}");
        let gap: f64 = row["min_ground_gap"].parse().unwrap();
        assert!(gap > 9.0 && gap < 10.0, "still falling: {gap}");
        let folder = dir.join(&row["folder"]);
        let scene = std::fs::read_to_string(folder.join("scene.toml")).unwrap();
        assert!(scene.contains(&format!("substeps = {substeps}")), "{scene}");
    }
    // The run is the same as `elasto run` with the same overrides.
    let o = elasto(
        tmp.path(),
        &[
            "run",
            "report-drop-2d",
            "--set",
            "material.young=1000",
            "--set",
            "time.substeps=2",
            "--frames",
            "4",
            "--no-render",
            "--out",
            "single",
            "--quiet",
        ],
    );
    assert_code(&o, 0);
    assert_eq!(
        stats_without_timing(&tmp.path().join("single/stats.csv")),
        stats_without_timing(&dir.join("0003_material.young=1000_time.substeps=2/stats.csv"))
    );
    // Summary columns agree with the run's own stats.csv.
    let (header, rows) = read_csv(&dir.join(&table[3]["folder"]).join("stats.csv"));
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let total: u64 = rows
        .iter()
        .map(|r| r[col("newton_iters")].parse::<u64>().unwrap())
        .sum();
    assert_eq!(table[3]["newton_iterations"], total.to_string());
    assert_eq!(table[3]["energy_end"], rows[3][col("total_energy")]);
    assert_eq!(table[3]["com_y"], rows[3][col("com_y")]);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("sweep.json")).unwrap()).unwrap();
    assert_eq!(json["runs"].as_array().unwrap().len(), 4);
    assert_eq!(json["vary"][0]["key"], "material.young");
}

#[test]
fn zip_pairs_three_lists_and_vectors_split_at_top_level_commas() {
    let tmp = tempfile::tempdir().unwrap();
    let o = elasto(
        tmp.path(),
        &[
            "sweep",
            "report-drop-2d",
            "--zip",
            "--vary",
            "material.young=100,200,300",
            "--vary",
            "mesh.velocity=[0,-1],[0, -2],[1,0]",
            "--vary",
            "time.substeps=1,2,3",
            "--frames",
            "2",
            "--no-render",
            "--out",
            "zipped",
            "-q",
        ],
    );
    assert_code(&o, 0);
    let dir = tmp.path().join("zipped");
    assert_eq!(
        folders(&dir),
        [
            "0000_material.young=100_mesh.velocity=0,-1_time.substeps=1",
            "0001_material.young=200_mesh.velocity=0,-2_time.substeps=2",
            "0002_material.young=300_mesh.velocity=1,0_time.substeps=3",
        ]
    );
    for (folder, velocity) in folders(&dir)
        .iter()
        .zip(["[0.0, -1.0]", "[0.0, -2.0]", "[1.0, 0.0]"])
    {
        let scene = std::fs::read_to_string(dir.join(folder).join("scene.toml")).unwrap();
        assert!(
            scene.contains(&format!("velocity = {velocity}")),
            "{folder}: {scene}"
        );
    }
    let table = sweep_table(&dir);
    assert_eq!(table[1]["mesh.velocity"], "[0, -2]");
}

#[test]
fn a_sweep_file_names_the_scene_the_shared_overrides_and_the_ranges() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::create_dir(tmp.path().join("study")).unwrap();
    std::fs::write(tmp.path().join("study/small.toml"), SMALL_SCENE).unwrap();
    std::fs::write(
        tmp.path().join("study/stiff.toml"),
        "scene = \"small.toml\"\nset = { \"time.frames\" = 3 }\n[vary]\n\
         \"time.substeps\" = \"linspace(1, 3, 2)\"\n\"material.young\" = [50, 500]\n",
    )
    .unwrap();
    let o = elasto(tmp.path(), &["sweep", "study/stiff.toml", "--list"]);
    assert_code(&o, 0);
    assert_eq!(
        stdout(&o),
        "0\t0000_time.substeps=1_material.young=50\ttime.substeps=1, material.young=50\n\
         1\t0001_time.substeps=1_material.young=500\ttime.substeps=1, material.young=500\n\
         2\t0002_time.substeps=3_material.young=50\ttime.substeps=3, material.young=50\n\
         3\t0003_time.substeps=3_material.young=500\ttime.substeps=3, material.young=500\n"
    );
    assert!(!tmp.path().join("out").exists(), "--list runs nothing");
    let o = elasto(
        tmp.path(),
        &["sweep", "study/stiff.toml", "--no-render", "-q"],
    );
    assert_code(&o, 0);
    let table = sweep_table(&tmp.path().join("out/sweeps/stiff"));
    assert_eq!(table.len(), 4);
    assert!(
        table
            .iter()
            .all(|r| r["frames"] == "3" && r["status"] == "ok")
    );
}

#[test]
fn every_bad_vary_is_exit_2_before_any_run() {
    let tmp = tempfile::tempdir().unwrap();
    let cases: [(&[&str], &str); 7] = [
        (&["--vary", "material.yung=1,2"], "unknown field `yung`"),
        (
            &["--vary", "material.young="],
            "the list of values is empty",
        ),
        (&["--vary", "material.young=1,,2"], "an empty value"),
        (
            &["--vary", "material.young=linspace(1,10,0)"],
            "the count `0`",
        ),
        (
            &["--vary", "material.young=logspace(-1,10,3)"],
            "both ends must be positive",
        ),
        (
            &[
                "--zip",
                "--vary",
                "material.young=1,2,3",
                "--vary",
                "time.substeps=1,2",
            ],
            "material.young: 3, time.substeps: 2",
        ),
        // A bad value in the middle: nothing runs, not even the good ones before it.
        (
            &["--vary", "material.young=100,-5,300"],
            "--vary material.young=-5",
        ),
    ];
    for (flags, needle) in cases {
        let mut args = vec![
            "sweep",
            "report-drop-2d",
            "--frames",
            "2",
            "--no-render",
            "--out",
            "bad",
        ];
        args.extend_from_slice(flags);
        let o = elasto(tmp.path(), &args);
        assert_code(&o, 2);
        assert!(stderr(&o).contains(needle), "{flags:?}: {}", stderr(&o));
        assert!(
            !tmp.path().join("bad").exists(),
            "{flags:?}: nothing may be written"
        );
    }
}

#[test]
fn a_failing_run_does_not_stop_the_others_and_the_sweep_exits_1() {
    let tmp = tempfile::tempdir().unwrap();
    // One Newton iteration per step hits the cap: with --strict that run fails
    // at run time (its scene is valid).
    let o = elasto(
        tmp.path(),
        &[
            "sweep",
            "report-drop-2d",
            "--vary",
            "solver.max_iterations=50,1,50",
            "--set",
            "solver.max_subdivisions=0",
            "--strict",
            "--frames",
            "3",
            "--no-render",
            "--out",
            "fail",
            "--jobs",
            "1",
        ],
    );
    assert_code(&o, 1);
    assert!(stderr(&o).contains("1 of 3 runs failed"), "{}", stderr(&o));
    let table = sweep_table(&tmp.path().join("fail"));
    let status: Vec<&str> = table.iter().map(|r| r["status"].as_str()).collect();
    assert_eq!(status[0], "ok");
    assert!(
        status[1].starts_with("failed: ") && status[1].contains("--strict"),
        "{status:?}"
    );
    assert_eq!(status[2], "ok", "the run after the failed one ran");
    assert_eq!(table[1]["exit_code"], "1");
    // Its outputs are still summarised: every step hit the cap of one iteration.
    let capped: u64 = table[1]["unconverged_steps"].parse().unwrap();
    assert!(capped > 0);
    assert_eq!(table[1]["newton_iterations"], capped.to_string());
    assert_eq!(table[0]["unconverged_steps"], "0");
}

fn png_pixels(path: &Path) -> image::RgbaImage {
    image::open(path).unwrap().to_rgba8()
}

fn frame_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir.join("frames"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    files
}

#[test]
fn results_do_not_depend_on_jobs_and_the_contact_sheet_has_a_labelled_tile_per_run() {
    let tmp = tempfile::tempdir().unwrap();
    let sweep = |out: &str, jobs: &str| {
        let o = elasto(
            tmp.path(),
            &[
                "sweep",
                "report-drop-2d",
                "--vary",
                "mesh.velocity=[0,0],[3,0],[-3,0],[0,4]",
                "--vary",
                "material.young=100,3000",
                "--set",
                "time.fps=10",
                "--frames",
                "4",
                "--resolution",
                "64x48",
                "--video",
                "apng",
                "--out",
                out,
                "--jobs",
                jobs,
                "-q",
            ],
        );
        assert_code(&o, 0);
        tmp.path().join(out)
    };
    let one = sweep("one", "1");
    let two = sweep("two", "2");
    let runs = folders(&one);
    assert_eq!(runs.len(), 8);
    assert_eq!(runs, folders(&two));
    for run in &runs {
        assert_eq!(
            stats_without_timing(&one.join(run).join("stats.csv")),
            stats_without_timing(&two.join(run).join("stats.csv")),
            "{run}"
        );
        let (a, b) = (frame_files(&one.join(run)), frame_files(&two.join(run)));
        assert_eq!(a.len(), 4);
        for (fa, fb) in a.iter().zip(&b) {
            assert_eq!(
                std::fs::read(fa).unwrap(),
                std::fs::read(fb).unwrap(),
                "{}",
                fa.display()
            );
        }
    }

    // 8 runs: 3 columns, 3 rows of equal cells; the tile is the run's last
    // frame, pixel for pixel (64x48 is not scaled), over its label band.
    let sheet = png_pixels(&one.join("contact_sheet.png"));
    assert_eq!(sheet.width() % 3, 0);
    assert_eq!(sheet.height() % 3, 0);
    let (cell_w, cell_h) = (sheet.width() / 3, sheet.height() / 3);
    assert_eq!(cell_w, 64);
    let mut tiles = Vec::new();
    let mut bands = Vec::new();
    for (i, run) in runs.iter().enumerate() {
        let (x0, y0) = ((i as u32 % 3) * cell_w, (i as u32 / 3) * cell_h);
        let tile = image::imageops::crop_imm(&sheet, x0, y0, 64, 48).to_image();
        let last = png_pixels(frame_files(&one.join(run)).last().unwrap());
        assert_eq!(tile, last, "tile {i} is the last frame of {run}");
        let band = image::imageops::crop_imm(&sheet, x0, y0 + 48, cell_w, cell_h - 48).to_image();
        let ink = band.pixels().filter(|p| p.0[0] < 128).count();
        assert!(ink > 20, "tile {i} is labelled ({ink} dark pixels)");
        tiles.push(tile);
        bands.push(band);
    }
    for i in 0..runs.len() {
        for j in 0..i {
            assert_ne!(bands[i], bands[j], "labels {i} and {j} differ");
        }
    }
    // Different initial velocities: the last frames differ.
    for i in (0..8).step_by(2) {
        for j in (0..i).step_by(2) {
            assert_ne!(tiles[i], tiles[j], "tiles {i} and {j} differ");
        }
    }
    // The comparison video: an APNG with a frame per frame of the runs.
    let decoder = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(one.join("comparison.png")).unwrap(),
    ));
    let reader = decoder.read_info().unwrap();
    let info = reader.info();
    assert_eq!(info.animation_control.unwrap().num_frames, 4);
    assert_eq!((info.width, info.height), (sheet.width(), sheet.height()));

    // --sheet-frame 0: every run's first frame; --collect rebuilds without running.
    let o = elasto(
        tmp.path(),
        &[
            "sweep",
            "report-drop-2d",
            "--vary",
            "mesh.velocity=[0,0],[3,0],[-3,0],[0,4]",
            "--vary",
            "material.young=100,3000",
            "--set",
            "time.fps=10",
            "--frames",
            "4",
            "--resolution",
            "64x48",
            "--video",
            "apng",
            "--out",
            "one",
            "--collect",
            "--sheet-frame",
            "0",
            "-q",
        ],
    );
    assert_code(&o, 0);
    let sheet = png_pixels(&one.join("contact_sheet.png"));
    let tile = image::imageops::crop_imm(&sheet, 0, 0, 64, 48).to_image();
    assert_eq!(tile, png_pixels(&frame_files(&one.join(&runs[0]))[0]));
}

#[test]
fn a_folder_not_made_by_the_sweep_is_not_written_into() {
    let tmp = tempfile::tempdir().unwrap();
    let taken = tmp.path().join("mine/0001_material.young=200");
    std::fs::create_dir_all(&taken).unwrap();
    std::fs::write(taken.join("notes.txt"), "my notes").unwrap();
    let o = elasto(
        tmp.path(),
        &[
            "sweep",
            "report-drop-2d",
            "--vary",
            "material.young=100,200",
            "--frames",
            "2",
            "--no-render",
            "--out",
            "mine",
        ],
    );
    assert_code(&o, 2);
    assert!(
        stderr(&o).contains("0001_material.young=200 exists and was not made by elasto sweep"),
        "{}",
        stderr(&o)
    );
    assert!(
        !tmp.path().join("mine/0000_material.young=100").exists(),
        "nothing ran"
    );
    assert_eq!(
        std::fs::read_to_string(taken.join("notes.txt")).unwrap(),
        "my notes"
    );
}

/// A 6 x 6 grid: 36 runs, every one on the contact sheet (within its size
/// bound) and in the MP4 comparison, frame by frame.
#[test]
fn thirty_six_runs_fill_the_contact_sheet_and_the_comparison_video() {
    let tmp = tempfile::tempdir().unwrap();
    let o = elasto(
        tmp.path(),
        &[
            "sweep",
            "report-drop-2d",
            "--vary",
            "material.young=linspace(100,3000,6)",
            "--vary",
            "mesh.velocity=[0,0],[1,0],[2,0],[-1,0],[-2,0],[0,2]",
            "--set",
            "time.fps=10",
            "--frames",
            "3",
            "--resolution",
            "32x24",
            "--video",
            "mp4",
            "--out",
            "grid",
            "--jobs",
            "2",
            "-q",
        ],
    );
    assert_code(&o, 0);
    let grid = tmp.path().join("grid");
    let table = sweep_table(&grid);
    assert_eq!(table.len(), 36);
    assert!(table.iter().all(|row| row["status"] == "ok"), "{table:?}");
    // Six columns of tiles no larger than the frames, plus their labels.
    let sheet = png_pixels(&grid.join("contact_sheet.png"));
    let (w, h) = sheet.dimensions();
    assert!(
        (6 * 32..=3840).contains(&w) && (6 * 24..=3840).contains(&h),
        "{w}x{h}"
    );
    // Every run's last frame appears in the sheet, pixel for pixel.
    let runs = folders(&grid);
    assert_eq!(runs.len(), 36);
    let mut found = 0;
    for run in &runs {
        let frame = png_pixels(&grid.join(run).join("frames").join("frame_0002.png"));
        let (fw, fh) = frame.dimensions();
        let here = (0..=h - fh).any(|y| {
            (0..=w - fw).any(|x| {
                (0..fh).all(|dy| {
                    (0..fw).all(|dx| sheet.get_pixel(x + dx, y + dy) == frame.get_pixel(dx, dy))
                })
            })
        });
        found += usize::from(here);
    }
    assert_eq!(found, 36, "tiles found in the contact sheet");
    // The comparison video has one frame per frame of the runs, tiles of
    // at least half the frames' size, and stays within 1920x1080.
    let mp4 = Mp4File::read(&grid.join("comparison.mp4")).unwrap();
    assert_eq!(mp4.samples.len(), 3);
    let (vw, vh) = mp4.track_size;
    assert_eq!(mp4.coded_size, (vw, vh));
    assert!(vw <= 1920 && vh <= 1080 && vw >= 6 * 16, "{vw}x{vh}");
    assert_eq!(mp4.decode_rgb().unwrap().len(), 3);
}
