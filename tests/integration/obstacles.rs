//! Issue 32, items 2 and 4: obstacles (`[[obstacles]]`) through the binary.
//!
//! A stiff block resting on a ramp obstacle tilted by θ = 30° under
//! ordinary gravity slides along it with `g (sin θ − μ cos θ)` for
//! `μ < tan θ` and stays put for `μ > tan θ`, the ramp's own `friction`
//! overriding the contact's; a plate obstacle moving at constant velocity
//! pushes a block along with it; obstacles are written with the surfaces,
//! once when they hold still and every frame when one moves; an obstacle
//! that starts intersecting or inside a body, or a scene with obstacles but
//! no contact, is refused before any work, naming both.

use crate::cli_common::{assert_code, elasto, read_csv, stderr};
use crate::support::fitted_parabola;
use std::path::Path;

const G: f64 = 9.81;
/// The ramp's tilt θ = 30°.
const SIN: f64 = 0.5;
const COS: f64 = 0.866_025_403_784_438_6;

/// A 0.4 × 0.1 block of 4 × 1 cells as Triangle `.node` + `.ele` files in
/// `dir` (`block.node`), lying on y = `lift` along the x axis, to be turned
/// onto the ramp by the scene's `rotate` and moved 0.6 up along it.
fn write_block(dir: &Path, lift: f64) {
    let (nx, w, h) = (4, 0.4, 0.1);
    let mut node = format!("{} 2 0 0\n", 2 * (nx + 1));
    for row in 0..2 {
        for i in 0..=nx {
            let id = row * (nx + 1) + i + 1;
            node += &format!(
                "{id} {} {}\n",
                w * i as f64 / nx as f64,
                lift + h * row as f64
            );
        }
    }
    let mut ele = format!("{} 3 0\n", 2 * nx);
    for i in 0..nx {
        let (a, b) = (i + 1, i + 2);
        let (c, d) = (a + nx + 1, b + nx + 1);
        ele += &format!("{} {a} {b} {d}\n{} {a} {d} {c}\n", 2 * i + 1, 2 * i + 2);
    }
    std::fs::write(dir.join("block.node"), node).unwrap();
    std::fs::write(dir.join("block.ele"), ele).unwrap();
}

/// The block on a 30° ramp obstacle (a 4 × 0.2 box turned about the
/// origin: its top face through the origin along (cos θ, sin θ)), 2e-3
/// above it (`d_hat` = 1e-3), with the ramp's `friction` (none when
/// `None`).
fn block_on_ramp(mu: Option<f64>) -> String {
    let friction = mu.map_or(String::new(), |mu| format!("friction = {mu}\n"));
    format!(
        r#"dimension = 2

[mesh]
generator = "file"
path = "block.node"
rotate = 30.0
translate = [0.5196152422706632, 0.3]

[material]
model = "neo-hookean"
young = 1e6
poisson = 0.3
density = 100.0

[time]
fps = 30.0
substeps = 10
frames = 24

[effects.gravity]
acceleration = [0.0, -{G}]

[effects.contact]
distance = 1e-3

[[obstacles]]
mesh = {{ size = [4.0, 0.2], offset = [-2.0, -0.2], rotate = 30.0 }}
{friction}"#
    )
}

/// Time, and the centre of mass's travel down the slope, per frame.
fn run_along_slope(dir: &Path, name: &str, scene: &str) -> (Vec<f64>, Vec<f64>) {
    std::fs::write(dir.join(format!("{name}.toml")), scene).unwrap();
    let o = elasto(
        dir,
        &[
            "run",
            &format!("{name}.toml"),
            "--no-render",
            "-o",
            name,
            "-q",
        ],
    );
    assert_code(&o, 0);
    assert!(!stderr(&o).contains("warning"), "{name}: {}", stderr(&o));
    let (header, rows) = read_csv(&dir.join(name).join("stats.csv"));
    let column = |c: &str| header.iter().position(|h| h == c).unwrap();
    let value = |r: &Vec<String>, c: &str| -> f64 { r[column(c)].parse().unwrap() };
    let time = rows.iter().map(|r| value(r, "time")).collect();
    // Down the slope is (-cos θ, -sin θ).
    let travel = rows
        .iter()
        .map(|r| -(value(r, "com_x") * COS + value(r, "com_y") * SIN))
        .collect();
    for r in &rows {
        let gap = &r[column("min_distance")];
        assert!(
            gap.is_empty() || gap.parse::<f64>().unwrap() > 0.0,
            "{name}: contact"
        );
    }
    (time, travel)
}

/// The acceleration of the least-squares parabola through the points at
/// or after `from`.
fn fitted_acceleration(time: &[f64], x: &[f64], from: f64) -> f64 {
    2.0 * fitted_parabola(time, x, from)[2]
}

#[test]
fn a_block_on_a_ramp_obstacle_slides_or_sticks_by_coulombs_law() {
    let dir = tempfile::tempdir().unwrap();
    write_block(dir.path(), 2e-3);
    for (name, mu) in [("free", None), ("sliding", Some(0.3))] {
        let (time, travel) = run_along_slope(dir.path(), name, &block_on_ramp(mu));
        let expected = G * (SIN - mu.unwrap_or(0.0) * COS);
        let acceleration = fitted_acceleration(&time, &travel, 0.1);
        assert!(
            (acceleration - expected).abs() <= 0.02 * expected,
            "{name}: acceleration {acceleration} along the ramp against g (sin θ − μ cos θ) = {expected}"
        );
    }
    // μ = 0.8 > tan θ: after landing it creeps at most at ε_v (1e-3 of the
    // block's diagonal per second, the default).
    let (time, travel) = run_along_slope(dir.path(), "stuck", &block_on_ramp(Some(0.8)));
    let landed = time.iter().position(|t| *t >= 0.1).unwrap();
    let creep = (travel.last().unwrap() - travel[landed]).abs();
    let threshold = 1e-3 * (0.4f64.powi(2) + 0.1f64.powi(2)).sqrt();
    let elapsed = time.last().unwrap() - time[landed];
    assert!(
        creep <= threshold * elapsed,
        "μ = 0.8: crept {creep} in {elapsed} s, more than ε_v t = {}",
        threshold * elapsed
    );
    // The ramp's own friction overrides the contact's (here 0.8 in
    // [effects.contact], 0 on the ramp: it slides freely).
    let scene =
        block_on_ramp(Some(0.0)).replace("distance = 1e-3", "distance = 1e-3\nfriction = 0.8");
    let (time, travel) = run_along_slope(dir.path(), "override", &scene);
    let acceleration = fitted_acceleration(&time, &travel, 0.1);
    assert!(
        (acceleration - G * SIN).abs() <= 0.02 * G * SIN,
        "the ramp's friction = 0 overrides the contact's: {acceleration}"
    );
}

/// A block resting on the ground, pushed along x by a plate obstacle moving
/// at 0.5 units/s from 0.1 away, and the stats of the run.
fn pushed_block(extra: &str) -> String {
    format!(
        r#"dimension = 2

[mesh]
size = [0.4, 0.4]
cells = [4, 4]
offset = [0.0, 0.01]

[material]
model = "neo-hookean"
young = 1e5
poisson = 0.3

[time]
fps = 30.0
frames = 30

[effects.gravity]
acceleration = [0.0, -9.81]

[effects.ground]
height = 0.0
a = 0.005
friction = 0.2

[effects.contact]
distance = 0.005

[[obstacles]]
mesh = {{ size = [0.1, 0.5], offset = [-0.2, 0.05] }}
velocity = [0.5, 0.0]
{extra}"#
    )
}

#[test]
fn a_moving_plate_obstacle_pushes_a_block_along_with_it() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("push.toml"), pushed_block("")).unwrap();
    let o = elasto(
        dir.path(),
        &[
            "run",
            "push.toml",
            "--no-render",
            "-o",
            "push",
            "-q",
            "--save-surface",
            "obj",
        ],
    );
    assert_code(&o, 0);
    let (header, rows) = read_csv(&dir.path().join("push/stats.csv"));
    let column = |c: &str| header.iter().position(|h| h == c).unwrap();
    let value = |r: &Vec<String>, c: &str| -> f64 { r[column(c)].parse().unwrap() };
    // The plate's right face reaches the block's left face (x = 0) at
    // t = 0.2 s; from then on the block moves with the plate, 0.5 units/s,
    // keeping the gap within d_hat.
    let (first, last) = (&rows[15], rows.last().unwrap());
    let speed = (value(last, "com_x") - value(first, "com_x"))
        / (value(last, "time") - value(first, "time"));
    assert!(
        (speed - 0.5).abs() < 0.01,
        "the block moves at {speed}, not 0.5"
    );
    let plate_face = -0.1 + 0.5 * value(last, "time");
    let block_left = value(last, "com_x") - 0.2;
    let gap = block_left - plate_face;
    assert!(
        gap > 0.0 && gap < 0.01,
        "the plate keeps its gap to the block: {gap}"
    );
    // The moving plate's surface is written with every frame.
    let surfaces = dir.path().join("push/surfaces");
    for frame in [0, 15, 29] {
        let file = surfaces.join(format!("obstacles_{frame:04}.obj"));
        let text = std::fs::read_to_string(&file).unwrap();
        let xs: Vec<f64> = text
            .lines()
            .filter(|l| l.starts_with("v "))
            .map(|l| l.split_whitespace().nth(1).unwrap().parse().unwrap())
            .collect();
        let right = xs.iter().copied().fold(f64::MIN, f64::max);
        let expected = -0.1 + 0.5 * frame as f64 / 30.0;
        assert!(
            (right - expected).abs() < 1e-5,
            "frame {frame}: plate at {right}"
        );
    }
}

#[test]
fn a_still_obstacle_is_written_once_with_the_surfaces() {
    let dir = tempfile::tempdir().unwrap();
    write_block(dir.path(), 2e-3);
    std::fs::write(dir.path().join("ramp.toml"), block_on_ramp(Some(0.8))).unwrap();
    let o = elasto(
        dir.path(),
        &[
            "run",
            "ramp.toml",
            "--no-render",
            "-o",
            "ramp",
            "-q",
            "--frames",
            "3",
            "--save-surface",
            "ply",
        ],
    );
    assert_code(&o, 0);
    let mut names: Vec<String> = std::fs::read_dir(dir.path().join("ramp/surfaces"))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.starts_with("obstacles_"))
        .collect();
    names.sort();
    assert_eq!(names, ["obstacles_0000.ply"]);
}

#[test]
fn obstacles_that_start_in_contact_or_without_contact_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        // The plate through the block.
        (
            pushed_block("").replace("offset = [-0.2, 0.05]", "offset = [-0.05, 0.05]"),
            "`obstacles[0]`: body 0 and obstacle 0 (obstacles[0]) start 0.000e0 apart",
        ),
        // The plate 1e-3 from the block, within d_hat = 5e-3.
        (
            pushed_block("").replace("offset = [-0.2, 0.05]", "offset = [-0.101, 0.05]"),
            "`obstacles[0]`: body 0 and obstacle 0 (obstacles[0]) start 1.000e-3 apart",
        ),
        // The block inside a big box obstacle.
        (
            pushed_block("").replace(
                "mesh = { size = [0.1, 0.5], offset = [-0.2, 0.05] }",
                "mesh = { size = [2.0, 2.0], offset = [-1.0, -0.5] }",
            ),
            "`obstacles[0]`: body 0 starts inside obstacle 0 (obstacles[0])",
        ),
        // No [effects.contact].
        (
            pushed_block("").replace("[effects.contact]\ndistance = 0.005\n", ""),
            "obstacles",
        ),
        // An obstacle cannot be released, nor have a body's velocity.
        (pushed_block("release = 1.0\n"), "release"),
        (
            pushed_block("").replace(
                "offset = [-0.2, 0.05] }",
                "offset = [-0.2, 0.05], velocity = [1.0, 0.0] }",
            ),
            "obstacles[0].mesh.velocity",
        ),
    ];
    for (k, (scene, expected)) in cases.iter().enumerate() {
        let path = dir.path().join(format!("case{k}.toml"));
        std::fs::write(&path, scene).unwrap();
        for args in [
            vec!["check", path.to_str().unwrap()],
            vec!["run", path.to_str().unwrap(), "--no-render"],
        ] {
            let o = elasto(dir.path(), &args);
            assert_code(&o, 2);
            assert!(stderr(&o).contains(expected), "case {k}: {}", stderr(&o));
        }
    }
    assert!(
        !dir.path().join("out").exists(),
        "a refused run wrote its folder"
    );
}

#[test]
fn obstacle_surface_files_are_read_and_their_errors_named() {
    let dir = tempfile::tempdir().unwrap();
    // A 2D polyline (a V-shaped trough) as OBJ, a 2D PLY edge list, and a
    // broken OBJ.
    std::fs::write(
        dir.path().join("trough.obj"),
        "v -1 0.5 0\nv 0 -0.2 0\nv 1 0.5 0\nl 1 2 3\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("trough.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement edge 2\nproperty int vertex1\nproperty int vertex2\n\
         end_header\n-1 0.5 0\n0 -0.2 0\n1 0.5 0\n0 1\n1 2\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("broken.obj"), "v 0 0 0\nv 1 0 0\nl 1 7\n").unwrap();
    let scene = |path: &str| {
        pushed_block("")
            .replace(
                "mesh = { size = [0.1, 0.5], offset = [-0.2, 0.05] }\nvelocity = [0.5, 0.0]",
                &format!(
                    "mesh = {{ generator = \"file\", path = \"{path}\", translate = [0.2, 0.0] }}"
                ),
            )
            .replace("offset = [0.0, 0.01]", "offset = [0.0, 0.5]")
    };
    for file in ["trough.obj", "trough.ply"] {
        std::fs::write(dir.path().join("s.toml"), scene(file)).unwrap();
        let o = elasto(dir.path(), &["check", "s.toml"]);
        assert_code(&o, 0);
        let out = String::from_utf8_lossy(&o.stdout).to_string();
        assert!(
            out.contains("obstacle 0      2 segments (open), still"),
            "{file}: {out}"
        );
    }
    std::fs::write(dir.path().join("s.toml"), scene("broken.obj")).unwrap();
    let o = elasto(dir.path(), &["check", "s.toml"]);
    assert_code(&o, 2);
    let message = stderr(&o);
    assert!(message.contains("obstacles[0].mesh.path"), "{message}");
    assert!(message.contains("broken.obj:3: point index 7"), "{message}");
    std::fs::write(dir.path().join("s.toml"), scene("missing.obj")).unwrap();
    let o = elasto(dir.path(), &["check", "s.toml"]);
    assert_code(&o, 2);
    assert!(
        stderr(&o).contains("No such file or directory"),
        "{}",
        stderr(&o)
    );
}

/// Regression: an obstacle's surface file (`.obj`, `.ply`) was read apart
/// from the bodies' mesh files and its path went into a run's `scene.toml`
/// as written, relative: checking or re-running that `scene.toml` from the
/// run's folder could not find the file. Read by the one mesh-file reader,
/// its path is made absolute and its size and checksum are recorded, like a
/// body's.
#[test]
fn a_runs_scene_toml_finds_the_obstacles_surface_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("floor.obj"), "v -1 0 0\nv 1 0 0\nl 1 2\n").unwrap();
    let scene = pushed_block("").replace(
        "mesh = { size = [0.1, 0.5], offset = [-0.2, 0.05] }\nvelocity = [0.5, 0.0]",
        "mesh = { generator = \"file\", path = \"floor.obj\" }",
    );
    assert!(scene.contains("floor.obj"), "the scene was changed");
    std::fs::write(dir.path().join("floor.toml"), scene).unwrap();
    let o = elasto(
        dir.path(),
        &[
            "run",
            "floor.toml",
            "--no-render",
            "-q",
            "--frames",
            "2",
            "-o",
            "first",
        ],
    );
    assert_code(&o, 0);
    let resolved = std::fs::read_to_string(dir.path().join("first/scene.toml")).unwrap();
    let absolute = std::path::absolute(dir.path().join("floor.obj")).unwrap();
    assert!(
        resolved.contains(&format!("path = {:?}", absolute.display().to_string())),
        "{resolved}"
    );
    assert!(resolved.contains("file_checksum = \"xxh3:"), "{resolved}");
    // From the run's own folder, the recorded scene finds its file.
    let o = elasto(&dir.path().join("first"), &["check", "scene.toml"]);
    assert_code(&o, 0);
}

/// Obstacles are in the frames (issue 32 item 2): the plate of
/// `pushed_block` is drawn where it is, not left out, and the background
/// beside it is untouched. 100 pixels per unit, scene (x, y) at pixel
/// (80 + 100 x, 60 − 100 (y − 0.3)).
#[test]
fn an_obstacle_is_drawn_in_the_frames_where_it_is() {
    let dir = tempfile::tempdir().unwrap();
    let view = "\n[render]\nresolution = [160, 120]\nlegend = false\n\
                [render.camera]\ncenter = [0.0, 0.3]\nheight = 1.2\n";
    std::fs::write(dir.path().join("push.toml"), pushed_block(view)).unwrap();
    let o = elasto(
        dir.path(),
        &[
            "run",
            "push.toml",
            "--frames",
            "1",
            "--video",
            "none",
            "-o",
            "out",
        ],
    );
    assert_code(&o, 0);
    let frame = image::open(dir.path().join("out/frames/frame_0000.png"))
        .unwrap()
        .to_rgb8();
    let plate = frame.get_pixel(65, 60).0; // (-0.15, 0.3): the plate's middle
    let background = frame.get_pixel(30, 60).0; // (-0.5, 0.3): nothing there
    let body = frame.get_pixel(100, 60).0; // (0.2, 0.3): the block
    let apart = |a: [u8; 3], b: [u8; 3]| (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap();
    assert!(
        apart(plate, background) >= 12,
        "the plate {plate:?} stands out from the background {background:?}"
    );
    assert!(apart(plate, body) >= 12, "and is not the block {body:?}");
}

/// Issue 32 item 5: a sweep over the contact's friction coefficient on a
/// contact scene (the block on the ramp obstacle, whose own `friction` is
/// left out, so the contact's applies) gives a contact sheet, and the runs
/// differ as Coulomb's law says: after 0.5 s the sliding blocks are
/// `½ g (sin θ − μ cos θ) t²` further down the slope than the block held
/// by μ = 0.8 > tan θ.
#[test]
fn a_sweep_over_the_contact_friction_shows_the_difference() {
    let dir = tempfile::tempdir().unwrap();
    let scene = block_on_ramp(None) + "\n[render]\nresolution = [160, 120]\nlegend = false\n";
    write_block(dir.path(), 2e-3);
    std::fs::write(dir.path().join("ramp.toml"), scene).unwrap();
    let o = elasto(
        dir.path(),
        &[
            "sweep",
            "ramp.toml",
            "--vary",
            "effects.contact.friction=0,0.2,0.4,0.8",
            "--frames",
            "16",
            "-o",
            "sweep",
        ],
    );
    assert_code(&o, 0);
    assert!(dir.path().join("sweep/contact_sheet.png").is_file());
    let (header, rows) = read_csv(&dir.path().join("sweep/sweep.csv"));
    let column = |c: &str| header.iter().position(|h| h == c).unwrap();
    // Down the slope is (-cos θ, -sin θ).
    let down: Vec<f64> = rows
        .iter()
        .map(|r| {
            let (x, y): (f64, f64) = (
                r[column("com_x")].parse().unwrap(),
                r[column("com_y")].parse().unwrap(),
            );
            -(x * COS + y * SIN)
        })
        .collect();
    assert_eq!(down.len(), 4);
    for (mu, d) in [0.0, 0.2, 0.4].iter().zip(&down) {
        let travel = d - down[3];
        let expected = 0.5 * G * (SIN - mu * COS) * 0.25;
        assert!(
            (travel - expected).abs() < 0.05 * expected,
            "μ = {mu}: {travel} further down than μ = 0.8, expected about {expected}"
        );
    }
}
