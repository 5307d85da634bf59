//! Issue 32, item 1 (with item 4's analytic tests): lagged IPC friction
//! through the binary.
//!
//! A stiff block resting on the ground under gravity tilted by θ (gravity
//! `[g sin θ, −g cos θ]`) slides with the acceleration `g (sin θ − μ cos θ)`
//! when `μ < tan θ` and stays put (creeping at most at the velocity
//! threshold `ε_v`) when `μ > tan θ`. The block starts a hair above the
//! ground's barrier and lands within the first frames, so the acceleration
//! is fitted to the centre of mass over the frames after 0.2 s. The same
//! law holds for a block on a slab (contact friction between bodies) and in
//! 3D. The work friction takes out, `friction_dissipated` in `stats.csv`,
//! accounts for the energy lost, and the keys are validated.

use crate::cli_common::{assert_code, elasto, read_csv, stderr, stdout};
use crate::support::fitted_parabola;
use std::path::Path;

const G: f64 = 9.81;
/// The tilt θ = 30°.
const SIN: f64 = 0.5;
const COS: f64 = 0.866_025_403_784_438_6;

/// A 1 × 0.25 stiff block (2D) or 0.5 × 0.2 × 0.5 (3D) 1e-4 above the
/// ground's barrier (`a = 0.01`), under the tilted gravity, with ground
/// friction `mu` (none when `None`) and `extra` keys appended.
fn tilted_block(dimension: usize, mu: Option<f64>, extra: &str) -> String {
    let (size, cells, gravity) = if dimension == 2 {
        (
            "[1.0, 0.25]",
            "[8, 2]",
            format!("[{}, {}]", G * SIN, -G * COS),
        )
    } else {
        (
            "[0.5, 0.2, 0.5]",
            "[3, 1, 3]",
            format!("[{}, {}, 0.0]", G * SIN, -G * COS),
        )
    };
    let offset = if dimension == 2 {
        "[0.0, 0.0101]"
    } else {
        "[0.0, 0.0101, 0.0]"
    };
    let friction = mu.map_or(String::new(), |mu| format!("friction = {mu}\n"));
    format!(
        r#"dimension = {dimension}

[mesh]
generator = "box"
size = {size}
offset = {offset}
cells = {cells}

[material]
model = "neo-hookean"
young = 1e6
poisson = 0.3
density = 100.0

[time]
fps = 30.0
substeps = 10
frames = 30

[effects.gravity]
acceleration = {gravity}

[effects.ground]
height = 0.0
a = 0.01
{friction}{extra}"#
    )
}

/// A run's frames: time, centre of mass x, total energy, friction's work.
struct Frames {
    time: Vec<f64>,
    com_x: Vec<f64>,
    total: Vec<f64>,
    dissipated: Vec<Option<f64>>,
}

fn run(dir: &Path, name: &str, scene: &str) -> Frames {
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
    assert!(
        !stderr(&o).contains("warning"),
        "{name}: the run is healthy: {}",
        stderr(&o)
    );
    let (header, rows) = read_csv(&dir.join(name).join("stats.csv"));
    let column = |c: &str| header.iter().position(|h| h == c).unwrap();
    let values =
        |c: &str| -> Vec<f64> { rows.iter().map(|r| r[column(c)].parse().unwrap()).collect() };
    Frames {
        time: values("time"),
        com_x: values("com_x"),
        total: values("total_energy"),
        dissipated: rows
            .iter()
            .map(|r| r[column("friction_dissipated")].parse().ok())
            .collect(),
    }
}

/// The least-squares parabola `x = c0 + c1 t + c2 t^2` through the frames
/// at or after `from`: `(c1, 2 c2)` (velocity at t = 0 and acceleration).
fn fitted_motion(frames: &Frames, from: f64) -> (f64, f64) {
    let [_, c1, c2] = fitted_parabola(&frames.time, &frames.com_x, from);
    (c1, 2.0 * c2)
}

fn assert_acceleration(frames: &Frames, expected: f64, what: &str) {
    let (_, acceleration) = fitted_motion(frames, 0.2);
    assert!(
        (acceleration - expected).abs() <= 0.02 * expected.abs(),
        "{what}: acceleration {acceleration} against g (sin θ − μ cos θ) = {expected}"
    );
}

#[test]
fn a_block_on_a_slope_slides_or_sticks_by_coulombs_law() {
    let dir = tempfile::tempdir().unwrap();
    // μ = 0: g sin θ (no friction term, no column values).
    let free = run(dir.path(), "free", &tilted_block(2, None, ""));
    assert_acceleration(&free, G * SIN, "μ = 0");
    assert!(free.dissipated.iter().all(Option::is_none));
    // μ = 0.3 < tan 30° = 0.577: slides with g (sin θ − μ cos θ).
    let mu = 0.3;
    let sliding = run(dir.path(), "sliding", &tilted_block(2, Some(mu), ""));
    assert_acceleration(&sliding, G * (SIN - mu * COS), "μ = 0.3");
    // μ = 0.8 > tan θ: after landing it moves by less than ε_v t (the
    // default ε_v: 1e-3 of the block's diagonal per second).
    let stuck = run(dir.path(), "stuck", &tilted_block(2, Some(0.8), ""));
    let landed = stuck.time.iter().position(|t| *t >= 0.2).unwrap();
    let creep = (stuck.com_x.last().unwrap() - stuck.com_x[landed]).abs();
    let threshold = 1e-3 * (1.0f64 + 0.25 * 0.25).sqrt();
    let elapsed = stuck.time.last().unwrap() - stuck.time[landed];
    assert!(
        creep <= threshold * elapsed,
        "μ = 0.8: crept {creep} in {elapsed} s, more than ε_v t = {}",
        threshold * elapsed
    );
    // ... while without friction it would have slid by ½ g sin θ t².
    assert!(free.com_x.last().unwrap() - free.com_x[landed] > 1.0);
}

#[test]
fn friction_accounts_for_the_energy_lost() {
    let dir = tempfile::tempdir().unwrap();
    let frames = run(dir.path(), "sliding", &tilted_block(2, Some(0.3), ""));
    let work: Vec<f64> = frames.dissipated.iter().map(|w| w.unwrap()).collect();
    assert_eq!(work[0], 0.0);
    assert!(work.windows(2).all(|w| w[1] >= w[0]), "work only grows");
    let start = frames.total[0];
    let (last, taken) = (*frames.total.last().unwrap(), *work.last().unwrap());
    // Sliding 1.1 units against mu m g cos θ = 0.3 x 25 x 8.5: about 70.
    let block_mass = 100.0 * 0.25;
    let travel = frames.com_x.last().unwrap() - frames.com_x[0];
    let coulomb = 0.3 * block_mass * G * COS * travel;
    assert!(
        (taken - coulomb).abs() <= 0.02 * coulomb,
        "friction took {taken}, Coulomb's force times the travel is {coulomb}"
    );
    // The energy lost is friction's work, up to backward Euler's own
    // (small) numerical dissipation; never more energy than at the start.
    let lost = start - last;
    assert!(last + taken <= start, "{last} + {taken} > {start}");
    assert!(
        taken >= 0.99 * lost,
        "friction took {taken} of the {lost} lost"
    );
}

#[test]
fn friction_between_bodies_and_in_3d_follows_the_same_law() {
    let dir = tempfile::tempdir().unwrap();
    // A 0.5 x 0.2 block on a 4 x 0.2 slab: the slab held by the ground
    // (μ = 1 > tan θ), the block sliding on it with contact friction 0.3.
    // The centre of mass accelerates by the block's share (1/9 of the mass).
    let mu = 0.3;
    let slab_and_block = format!(
        r#"dimension = 2

[[bodies]]
[bodies.mesh]
generator = "box"
size = [4.0, 0.2]
offset = [0.0, 0.0101]
cells = [20, 2]
[bodies.material]
model = "neo-hookean"
young = 1e6
poisson = 0.3
density = 100.0

[[bodies]]
[bodies.mesh]
generator = "box"
size = [0.5, 0.2]
offset = [0.5, 0.2161]
cells = [5, 2]
[bodies.material]
model = "neo-hookean"
young = 1e6
poisson = 0.3
density = 100.0

[time]
fps = 30.0
substeps = 10
frames = 30

[effects.gravity]
acceleration = [{}, {}]

[effects.ground]
height = 0.0
a = 0.01
friction = 1.0

[effects.contact]
distance = 0.005
friction = {mu}
"#,
        G * SIN,
        -G * COS
    );
    let stacked = run(dir.path(), "stacked", &slab_and_block);
    assert_acceleration(&stacked, G * (SIN - mu * COS) / 9.0, "block on a slab");
    // 3D, with two friction passes per step.
    let block = run(
        dir.path(),
        "block-3d",
        &tilted_block(3, Some(mu), "\n[solver]\nfriction_iterations = 2\n"),
    );
    assert_acceleration(&block, G * (SIN - mu * COS), "3D block");
}

#[test]
fn friction_keys_are_validated_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            tilted_block(2, Some(-0.1), ""),
            "effects.ground.friction",
            "must be 0 or more",
        ),
        (
            tilted_block(2, None, "\n[solver]\nfriction_velocity = 0.01\n"),
            "solver.friction_velocity",
            "is only used with friction",
        ),
        (
            tilted_block(2, Some(0.3), "\n[solver]\nfriction_velocity = 0.0\n"),
            "solver.friction_velocity",
            "must be a finite number > 0",
        ),
        (
            tilted_block(2, Some(0.3), "\n[solver]\nfriction_iterations = 0\n"),
            "solver.friction_iterations",
            "at least 1",
        ),
    ];
    for (i, (scene, key, reason)) in cases.iter().enumerate() {
        let file = format!("bad{i}.toml");
        std::fs::write(dir.path().join(&file), scene).unwrap();
        let o = elasto(dir.path(), &["run", &file, "--no-render", "-o", "out"]);
        assert_code(&o, 2);
        let message = stderr(&o);
        assert!(
            message.contains(key) && message.contains(reason),
            "case {i}: {message}"
        );
        assert!(!dir.path().join("out").exists(), "case {i}: no work done");
    }
    // `elasto check` says what friction the scene has (ε_v: 1e-3 of the
    // block's diagonal per second).
    std::fs::write(dir.path().join("ok.toml"), tilted_block(2, Some(0.3), "")).unwrap();
    let o = elasto(dir.path(), &["check", "ok.toml"]);
    assert_code(&o, 0);
    let expected = format!(
        "friction        mu = 0.3 against the ground, 0 between bodies, velocity threshold \
         eps_v = {} (length/s), 1 solve(s) per step",
        1e-3 * (1.0f64 + 0.25 * 0.25).sqrt()
    );
    assert!(stdout(&o).contains(&expected), "{}", stdout(&o));
}

#[test]
fn a_sweep_over_the_friction_coefficient_shows_the_difference() {
    let dir = tempfile::tempdir().unwrap();
    let scene =
        tilted_block(2, Some(0.3), "") + "\n[render]\nresolution = [160, 120]\nlegend = false\n";
    std::fs::write(dir.path().join("slope.toml"), scene).unwrap();
    let o = elasto(
        dir.path(),
        &[
            "sweep",
            "slope.toml",
            "--vary",
            "effects.ground.friction=0,0.2,0.4,0.8",
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
    let travel: Vec<f64> = rows
        .iter()
        .map(|r| r[column("com_x")].parse::<f64>().unwrap() - 0.5)
        .collect();
    assert_eq!(travel.len(), 4);
    // 0.5 s: ½ g (sin θ − μ cos θ) t² (from the landing on) for the three
    // that slide, 0 for μ = 0.8 > tan θ.
    for (mu, moved) in [0.0, 0.2, 0.4].iter().zip(&travel) {
        let expected = 0.5 * G * (SIN - mu * COS) * 0.25;
        assert!(
            (moved - expected).abs() < 0.05 * expected,
            "μ = {mu}: travelled {moved}, expected about {expected}"
        );
    }
    assert!(travel[3].abs() < 1e-2, "μ = 0.8 holds: {}", travel[3]);
}
