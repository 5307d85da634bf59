//! Issue 33, item 13: two runs with `--force` into the same folder at once:
//! one failed with a misleading "No such file or directory" and the folder
//! ended mixed (frames of one, stats of both). Now a run locks its output
//! folder while it writes, and a second writer is refused (exit 2, naming
//! the folder) before it removes or writes anything.

use crate::cli_common as common;
use common::*;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[test]
fn a_second_writer_into_a_folder_in_use_is_refused_before_it_touches_anything() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("s.toml"), SMALL_SCENE).unwrap();
    // A long run, writing into `out`.
    let mut first = Command::new(env!("CARGO_BIN_EXE_elasto"))
        .args([
            "run",
            "s.toml",
            "--no-render",
            "--frames",
            "200000",
            "-q",
            "-o",
            "out",
        ])
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let stats = dir.join("out/stats.csv");
    let start = Instant::now();
    let rows = || {
        std::fs::read_to_string(&stats)
            .map(|t| t.lines().count())
            .unwrap_or(0)
    };
    while rows() < 3 {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "the first run never wrote its rows"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let second = elasto(
        dir,
        &[
            "run",
            "s.toml",
            "--no-render",
            "--frames",
            "3",
            "-q",
            "-o",
            "out",
            "--force",
        ],
    );
    let written_meanwhile = rows();
    let still_running = first.try_wait().unwrap().is_none();
    first.kill().unwrap();
    first.wait().unwrap();
    assert!(still_running, "the first run was still writing");
    assert_code(&second, 2);
    assert!(
        stderr(&second).contains("another elasto is writing into the output folder out now"),
        "{}",
        stderr(&second)
    );
    // The second touched nothing: the first's table kept every row it had.
    assert!(written_meanwhile >= 3 && rows() >= written_meanwhile);
    let header = std::fs::read_to_string(&stats).unwrap();
    assert!(header.starts_with("frame,time,"));
    // Once the first is gone, the folder is free again.
    let third = elasto(
        dir,
        &[
            "run",
            "s.toml",
            "--no-render",
            "--frames",
            "3",
            "-q",
            "-o",
            "out",
            "--force",
        ],
    );
    assert_code(&third, 0);
}
