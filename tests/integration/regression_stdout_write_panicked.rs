//! Issue 33, item 4: a failed write to standard output (`> /dev/full`)
//! panicked with exit 101 and a backtrace (`print!` panics on ENOSPC). Now
//! every command that prints says "cannot write to standard output: ..." and
//! exits 1, and the files it wrote stay complete.
#![cfg(target_os = "linux")]

use crate::cli_common as common;
use common::*;
use std::path::Path;
use std::process::{Command, Output, Stdio};

/// Runs the real binary in `cwd` with its standard output on `/dev/full`.
fn elasto_to_full_disk(cwd: &Path, args: &[&str]) -> Output {
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full opens");
    Command::new(env!("CARGO_BIN_EXE_elasto"))
        .args(args)
        .current_dir(cwd)
        .env_remove("RUST_BACKTRACE")
        .stdout(Stdio::from(full))
        .stderr(Stdio::piped())
        .output()
        .expect("the elasto binary runs")
}

/// Exit 1 with the message, and no panic.
fn assert_says_it_cannot_write(o: &Output, args: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    assert!(
        err.contains("error: cannot write to standard output: No space left on device"),
        "{args:?}: {err}"
    );
}

#[test]
fn the_commands_that_print_say_they_cannot_write_and_exit_1() {
    let tmp = tempfile::tempdir().unwrap();
    for args in [
        &["scenes"][..],
        &["scenes", "show", "drop-3d"],
        &["check", "drop-3d"],
        &[
            "sweep",
            "drop-3d",
            "--vary",
            "material.young=100,200",
            "--list",
        ],
        &["--help"],
        &["--version"],
    ] {
        let o = elasto_to_full_disk(tmp.path(), args);
        assert_says_it_cannot_write(&o, args);
    }
}

#[test]
fn a_run_with_profile_keeps_its_files_when_the_table_cannot_be_written() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("s.toml"), SMALL_SCENE).unwrap();
    let args = ["run", "s.toml", "--no-render", "--profile", "-o", "out"];
    let o = elasto_to_full_disk(tmp.path(), &args);
    assert_says_it_cannot_write(&o, &args);
    let (_, rows) = read_csv(&tmp.path().join("out/stats.csv"));
    assert_eq!(rows.len(), 4, "frames 0 to 3: {rows:?}");
}

#[test]
fn a_study_keeps_its_files_when_the_report_cannot_be_written() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("s.toml"), SMALL_SCENE).unwrap();
    let args = [
        "study",
        "s.toml",
        "--vary",
        "time.substeps=1,2",
        "-o",
        "st",
        "--quiet",
    ];
    let o = elasto_to_full_disk(tmp.path(), &args);
    assert_says_it_cannot_write(&o, &args);
    for file in ["study.csv", "study.md", "study.png"] {
        let size = std::fs::metadata(tmp.path().join("st").join(file))
            .map(|m| m.len())
            .unwrap_or(0);
        assert!(size > 0, "{file} is missing or empty");
    }
}
