//! Golden-image tests: the real binary renders built-in scenes at 320×240 and
//! selected frames are compared by FLIP with `golden/<scene>/frame_NNNN.png`.
//!
//! Every run writes the rendered frames and the magma-coloured FLIP error maps
//! to `target/golden-actual/<scene>/` (`frame_NNNN.actual.png` and
//! `frame_NNNN.png`). References change only with `ELASTO_UPDATE_GOLDEN=1`; a
//! missing reference fails. Without a graphics adapter the tests fail unless
//! `ELASTO_ALLOW_NO_GPU=1`, which makes them skip. See `golden/README.md`.

use std::path::{Path, PathBuf};

use elasto::compare::{
    CompareThresholds, FrameOutcome, compare_directories, compare_images, read_rgba,
};
use image::RgbaImage;

/// Image size of every golden frame.
const RESOLUTION: &str = "320x240";

/// A built-in scene, how long it runs, and which of its frames are checked.
struct GoldenScene {
    /// Built-in scene name, also the folder under `golden/`.
    name: &'static str,
    /// `--frames`: the automatic camera frames the whole motion, so the run
    /// length is part of the picture.
    frames: u64,
    /// The frames compared, with why each was chosen.
    checked: &'static [(usize, &'static str)],
}

/// Falls from 10 units under gravity 1: touches the ground at t ≈ 4.47 s
/// (frame 134), squashed most at frame 136, bouncing up afterwards.
const REPORT_DROP_2D: GoldenScene = GoldenScene {
    name: "report-drop-2d",
    frames: 160,
    checked: &[
        (100, "before impact: falling, undeformed"),
        (136, "at impact: most squashed (volume ratio 0.66)"),
        (155, "after impact: bouncing up, wobbling"),
    ],
};

/// Falls from 3 units while drifting sideways: lands at frame 73, most
/// strained at frame 74.
const DROP_3D: GoldenScene = GoldenScene {
    name: "drop-3d",
    frames: 90,
    checked: &[
        (40, "in flight: undeformed, drifting"),
        (74, "at impact: most strained"),
    ],
};

/// The hanging bar 1.5 s after release, stretched and swinging.
const HANGING_BAR: GoldenScene = GoldenScene {
    name: "hanging-bar-2d",
    frames: 46,
    checked: &[(45, "sagging: bent, stress largest at the pinned end")],
};

fn env_flag(name: &str) -> bool {
    std::env::var(name).is_ok_and(|v| v == "1")
}

fn golden_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("golden")
}

/// `target/golden-actual/<scene>`, emptied.
fn actual_dir(scene: &str) -> PathBuf {
    let target = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .expect("CARGO_TARGET_TMPDIR is target/tmp")
        .to_path_buf();
    let dir = target.join("golden-actual").join(scene);
    if dir.exists() {
        std::fs::remove_dir_all(&dir).unwrap();
    }
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The adapter the renderer will use, or `None` when there is none and
/// `ELASTO_ALLOW_NO_GPU=1` allows skipping.
fn adapter() -> Option<String> {
    match elasto::render::adapter_description() {
        Ok(description) => Some(description),
        Err(e) if env_flag("ELASTO_ALLOW_NO_GPU") => {
            eprintln!("skipping the golden-image test: {e} (ELASTO_ALLOW_NO_GPU=1)");
            None
        }
        Err(e) => panic!(
            "no graphics adapter for the golden-image test: {e}\n\
             set ELASTO_ALLOW_NO_GPU=1 to skip it on a machine without one"
        ),
    }
}

/// Runs `elasto run SCENE` into `out` with `extra` arguments and returns the
/// frames folder.
fn run_scene(scene: &str, frames: u64, out: &Path, extra: &[&str]) -> PathBuf {
    let output = crate::cli_common::elasto_command()
        .args([
            "run",
            scene,
            "--quiet",
            "--video",
            "none",
            "--resolution",
            RESOLUTION,
        ])
        .args(["--frames", &frames.to_string()])
        .arg("--out")
        .arg(out)
        .args(extra)
        .output()
        .expect("the elasto binary runs");
    assert!(
        output.status.success(),
        "elasto run {scene} failed ({}):\n{}",
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
    out.join("frames")
}

fn frame_name(frame: usize) -> String {
    format!("frame_{frame:04}.png")
}

/// Renders `scene`, then compares its checked frames with the references (or
/// replaces the references with `ELASTO_UPDATE_GOLDEN=1`). Returns the
/// rendered frames folder, kept alive by the returned temporary folder.
fn check_scene(scene: &GoldenScene) -> Option<(tempfile::TempDir, PathBuf)> {
    let adapter = adapter()?;
    let tmp = tempfile::tempdir().unwrap();
    let frames = run_scene(scene.name, scene.frames, &tmp.path().join("run"), &[]);
    let golden = golden_root().join(scene.name);
    let actual = actual_dir(scene.name);

    if env_flag("ELASTO_UPDATE_GOLDEN") {
        update_references(scene, &frames, &golden, &adapter);
    }

    let missing: Vec<String> = scene
        .checked
        .iter()
        .map(|&(frame, _)| golden.join(frame_name(frame)))
        .filter(|path| !path.is_file())
        .map(|path| path.display().to_string())
        .collect();
    assert!(
        missing.is_empty(),
        "missing golden references (they are never created silently):\n  {}\n\
         render them with ELASTO_UPDATE_GOLDEN=1 cargo test --test integration golden_scenes, \
         then look at them before committing",
        missing.join("\n  ")
    );

    let report = compare_directories(&golden, &frames, &actual, &CompareThresholds::default())
        .unwrap_or_else(|e| panic!("comparing {}: {e}", scene.name));
    let recorded = std::fs::read_to_string(golden.join("adapter.txt")).unwrap_or_default();
    let recorded = recorded.lines().next().unwrap_or("(not recorded)");
    assert!(
        report.all_passed(),
        "{} differs from its golden frames:\n{}\nrendered on: {adapter}\nreferences made on: {}\n\
         actual frames and difference images: {}",
        scene.name,
        report.table(),
        recorded,
        actual.display()
    );
    let compared: Vec<&str> = report.frames.iter().map(|f| f.name.as_str()).collect();
    let expected: Vec<String> = scene.checked.iter().map(|&(f, _)| frame_name(f)).collect();
    assert_eq!(
        compared, expected,
        "golden/{} holds other frames",
        scene.name
    );
    Some((tmp, frames))
}

/// Copies the checked frames into `golden`, removes other PNGs there, and
/// records the adapter.
fn update_references(scene: &GoldenScene, frames: &Path, golden: &Path, adapter: &str) {
    std::fs::create_dir_all(golden).unwrap();
    for entry in std::fs::read_dir(golden).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "png") {
            std::fs::remove_file(path).unwrap();
        }
    }
    for &(frame, _) in scene.checked {
        let name = frame_name(frame);
        std::fs::copy(frames.join(&name), golden.join(&name))
            .unwrap_or_else(|e| panic!("copying {name} of {}: {e}", scene.name));
    }
    let why: String = scene
        .checked
        .iter()
        .map(|&(frame, why)| format!("{}: {why}\n", frame_name(frame)))
        .collect();
    std::fs::write(
        golden.join("adapter.txt"),
        format!(
            "{adapter}\nelasto run {} --frames {} --resolution {RESOLUTION} --video none\n{why}",
            scene.name, scene.frames
        ),
    )
    .unwrap();
    eprintln!("updated golden/{} on {adapter}", scene.name);
}

/// `image` moved right by `dx` and down by `dy` pixels, the uncovered border
/// filled with the image's top-left colour (the background).
fn shifted(image: &RgbaImage, dx: u32, dy: u32) -> RgbaImage {
    let background = *image.get_pixel(0, 0);
    RgbaImage::from_fn(image.width(), image.height(), |x, y| {
        if x < dx || y < dy {
            background
        } else {
            *image.get_pixel(x - dx, y - dy)
        }
    })
}

#[test]
fn report_drop_2d_matches_its_golden_frames() {
    let Some((_tmp, frames)) = check_scene(&REPORT_DROP_2D) else {
        return;
    };
    // A perturbed picture fails: the rendered frame at impact moved by 3 px.
    let (frame, _) = REPORT_DROP_2D.checked[1];
    let name = frame_name(frame);
    let golden = read_rgba(&golden_root().join(REPORT_DROP_2D.name).join(&name)).unwrap();
    let actual = read_rgba(&frames.join(&name)).unwrap();
    let t = CompareThresholds::default();
    for (dx, dy) in [(3, 0), (0, 3)] {
        let c = compare_images(&golden, &shifted(&actual, dx, dy), &t).unwrap();
        assert!(!c.passed, "{name} shifted by ({dx}, {dy}) px passed: {c:?}");
    }
}

#[test]
fn drop_3d_matches_its_golden_frames() {
    check_scene(&DROP_3D);
}

#[test]
fn hanging_bar_matches_its_golden_frame_and_renders_identically_twice() {
    let Some((tmp, first)) = check_scene(&HANGING_BAR) else {
        return;
    };
    let second = run_scene(
        HANGING_BAR.name,
        HANGING_BAR.frames,
        &tmp.path().join("again"),
        &[],
    );
    let report = compare_directories(
        &golden_root().join(HANGING_BAR.name),
        &second,
        &tmp.path().join("diff-again"),
        &CompareThresholds::default(),
    )
    .unwrap();
    // The second run passes against the golden frame like the first; it is
    // not required to be bit-identical to it: faer picks its SIMD kernels at
    // run time (AVX2 or AVX-512), so another CPU may round the last bits of
    // the simulation differently and move a colour by one level. Two runs on
    // one machine, compared below, must be identical.
    for f in &report.frames {
        assert_eq!(f.outcome, FrameOutcome::Pass, "{}", report.table());
    }
    for &(frame, _) in HANGING_BAR.checked {
        let name = frame_name(frame);
        let (a, b) = (
            read_rgba(&first.join(&name)).unwrap(),
            read_rgba(&second.join(&name)).unwrap(),
        );
        let c = compare_images(&a, &b, &CompareThresholds::default()).unwrap();
        assert!(
            c.mean < 1e-6 && c.max < 1e-3,
            "{name} differs between two runs: {c:?}"
        );
    }
}

/// The body placed 0.1 units (4 pixels) further right, seen by the same fixed
/// camera, fails the comparison with the unmoved body.
#[test]
fn an_offset_body_fails_the_comparison() {
    if adapter().is_none() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let camera = [
        "--set",
        "render.camera.center=[0.5, 9.0]",
        "--set",
        "render.camera.height=6.0",
    ];
    let plain = run_scene("report-drop-2d", 2, &tmp.path().join("plain"), &camera);
    let mut moved_args = camera.to_vec();
    moved_args.extend(["--set", "mesh.offset=[0.1, 10.0]"]);
    let moved = run_scene("report-drop-2d", 2, &tmp.path().join("moved"), &moved_args);
    let t = CompareThresholds::default();
    for name in ["frame_0000.png", "frame_0001.png"] {
        let (a, b) = (
            read_rgba(&plain.join(name)).unwrap(),
            read_rgba(&moved.join(name)).unwrap(),
        );
        let c = compare_images(&a, &b, &t).unwrap();
        assert!(!c.passed, "{name}: the offset body passed: {c:?}");
    }
}
