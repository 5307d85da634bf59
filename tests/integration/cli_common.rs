//! Helpers shared by the command-line tests.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// The real binary as a [`Command`], for the tests that spawn it themselves
/// (signals, pipes, its environment): the one place that names it. A
/// backtrace setting of the caller's does not leak into its messages.
pub fn elasto_command() -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_elasto"));
    command.env_remove("RUST_BACKTRACE");
    command
}

/// Runs the real binary with `args` in `cwd`.
pub fn elasto(cwd: &Path, args: &[&str]) -> Output {
    elasto_command()
        .args(args)
        .current_dir(cwd)
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

/// The header and rows of a CSV file elasto wrote (`stats.csv`,
/// `sweep.csv`, `study.csv`), read by the `csv` crate (RFC 4180: a value
/// such as `[8, 1]` is quoted). Rows keep their own lengths, so a test can
/// see a cut row.
pub fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_path(path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let mut records = reader.records().map(|record| {
        let record = record.unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        record.iter().map(str::to_owned).collect::<Vec<String>>()
    });
    let header = records
        .next()
        .unwrap_or_else(|| panic!("{} is empty", path.display()));
    (header, records.collect())
}

/// The position of column `name` in `header`.
pub fn column_index(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
}

/// Column `name` of `rows`, as numbers.
pub fn column_f64(header: &[String], rows: &[Vec<String>], name: &str) -> Vec<f64> {
    let c = column_index(header, name);
    rows.iter()
        .map(|r| {
            r[c].parse()
                .unwrap_or_else(|e| panic!("{name} = {:?}: {e}", r[c]))
        })
        .collect()
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

/// Waits for `child` to exit and returns its status, but kills it and fails
/// the test when it has not ended after `limit` (`what` names it then): for
/// runs that once hung.
pub fn wait_for_exit(
    child: &mut std::process::Child,
    limit: std::time::Duration,
    what: &str,
) -> std::process::ExitStatus {
    let start = std::time::Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what} still ran after {limit:?}: it hangs");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// Runs the real binary with `args` in `cwd` like [`elasto`], but kills it
/// and fails the test when it has not ended after `limit`: for inputs that
/// once made it hang.
pub fn elasto_within(cwd: &Path, args: &[&str], limit: std::time::Duration) -> Output {
    use std::io::Read;
    use std::process::Stdio;
    let mut child = elasto_command()
        .args(args)
        .current_dir(cwd)
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
    let status = wait_for_exit(&mut child, limit, &format!("elasto {args:?}"));
    Output {
        status,
        stdout: out_reader.join().unwrap(),
        stderr: err_reader.join().unwrap(),
    }
}

/// Waits for an event the test is about to assert on (a file appearing, rows
/// written, a process gone): checks `happened` every 10 ms and fails the test
/// naming `what` when it has not happened after `limit`. Tests wait for
/// what they look at, never for a fixed time.
pub fn wait_until(what: &str, limit: std::time::Duration, mut happened: impl FnMut() -> bool) {
    let start = std::time::Instant::now();
    while !happened() {
        assert!(start.elapsed() < limit, "{what}: not after {limit:?}");
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
}

/// Every file under `dir`, recursively (following links to folders), as
/// paths relative to it, sorted; folders themselves are not listed.
pub fn files_under(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut files = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(folder) = pending.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                pending.push(path);
            } else {
                files.push(path.strip_prefix(dir).unwrap().to_path_buf());
            }
        }
    }
    files.sort();
    files
}
