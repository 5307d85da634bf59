//! Helpers shared by the command-line tests.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// Runs the real binary with `args` in `cwd`.
pub fn elasto(cwd: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_elasto"))
        .args(args)
        .current_dir(cwd)
        .env_remove("RUST_BACKTRACE")
        .output()
        .expect("the elasto binary runs")
}

/// Stdout as text.
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Stderr as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts the exit code, showing the output when it differs.
pub fn assert_code(o: &Output, code: i32) {
    assert_eq!(
        o.status.code(),
        Some(code),
        "stdout:\n{}\nstderr:\n{}",
        stdout(o),
        stderr(o)
    );
}

/// The CSV header and rows of a stats file.
pub fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_owned)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    (header, rows)
}

/// The column names stats.csv must start with, in order.
pub const REQUIRED_COLUMNS: &[&str] = &[
    "frame",
    "time",
    "newton_iters",
    "linear_solves",
    "backtracks",
    "kinetic",
    "elastic",
    "gravity",
    "barrier",
    "total_energy",
    "com_x",
    "com_y",
    "com_z",
    "min_height",
    "min_volume_ratio",
    "sim_ms",
    "unconverged_steps",
    "stalled_steps",
    "assembly_ms",
    "factorisation_ms",
    "solve_ms",
    "line_search_ms",
    "min_distance",
    "contact_pairs",
    "broad_phase_ms",
    "ccd_ms",
    "ccd_budget_exhausted",
    "reanalyses",
    "subdivided_steps",
    "damped_steps",
    "boundary_error",
    "friction_dissipated",
    "projected_iterations",
];

/// A small valid 2D scene file text (falls onto a ground).
pub const SMALL_SCENE: &str = r#"dimension = 2

[mesh]
size = [1.0, 1.0]
cells = [2, 2]
offset = [0.0, 1.0]

[material]
model = "stvk"
young = 300.0
poisson = 0.3

[time]
frames = 4

[effects.gravity]
acceleration = [0.0, -1.0]

[effects.ground]
height = 0.0
"#;

/// Runs the real binary with `args` in `cwd` like [`elasto`], but kills it
/// and fails the test when it has not ended after `limit`: for inputs that
/// once made it hang.
pub fn elasto_within(cwd: &Path, args: &[&str], limit: std::time::Duration) -> Output {
    use std::io::Read;
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_elasto"))
        .args(args)
        .current_dir(cwd)
        .env_remove("RUST_BACKTRACE")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the elasto binary runs");
    // Drain both pipes while waiting, so a chatty child cannot block on them.
    let mut out_pipe = child.stdout.take().unwrap();
    let mut err_pipe = child.stderr.take().unwrap();
    let out_reader = std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let _ = out_pipe.read_to_end(&mut bytes);
        bytes
    });
    let err_reader = std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let _ = err_pipe.read_to_end(&mut bytes);
        bytes
    });
    let start = std::time::Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("elasto {args:?} still ran after {limit:?}: it hangs");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    Output {
        status,
        stdout: out_reader.join().unwrap(),
        stderr: err_reader.join().unwrap(),
    }
}
