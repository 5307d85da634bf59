//! Issue 33, item 3: `RAYON_NUM_THREADS=100000` started 100 000 threads (a
//! 3-frame run took over a minute) and `RAYON_NUM_THREADS=abc` was silently
//! ignored. Now a value that is not a whole number is exit 2 naming the
//! variable, before any work, and one above the cap (4 threads per core, at
//! least 64) is lowered to it with a warning.

use crate::cli_common as common;
use common::*;
use std::path::Path;
use std::process::{Command, Output};

/// Runs the real binary in `cwd` with `RAYON_NUM_THREADS` = `threads`.
fn elasto_with_threads(cwd: &Path, threads: &str, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_elasto"))
        .args(args)
        .current_dir(cwd)
        .env_remove("RUST_BACKTRACE")
        .env("RAYON_NUM_THREADS", threads)
        .output()
        .expect("the elasto binary runs")
}

#[test]
fn a_thread_count_that_is_not_a_whole_number_is_refused_before_any_work() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("s.toml"), SMALL_SCENE).unwrap();
    for value in ["abc", "-4", "2.5", ""] {
        for args in [
            &["check", "s.toml"][..],
            &["run", "s.toml", "--no-render", "-o", "out"],
        ] {
            let o = elasto_with_threads(tmp.path(), value, args);
            assert_code(&o, 2);
            let err = stderr(&o);
            assert!(
                err.contains(&format!("`RAYON_NUM_THREADS={value}`"))
                    && err.contains("must be a whole number of threads"),
                "{value:?} {args:?}: {err}"
            );
            assert!(!tmp.path().join("out").exists(), "{args:?} wrote a folder");
        }
    }
}

#[test]
fn a_thread_count_above_the_cap_is_lowered_with_a_warning() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("s.toml"), SMALL_SCENE).unwrap();
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let cap = (4 * cores).max(64);
    let o = elasto_with_threads(
        tmp.path(),
        "100000",
        &["run", "s.toml", "--no-render", "--quiet", "-o", "out"],
    );
    assert_code(&o, 0);
    let err = stderr(&o);
    assert!(
        err.contains(&format!(
            "warning: RAYON_NUM_THREADS=100000 is more than the {cap} threads elasto starts"
        )) && err.contains(&format!("using {cap}")),
        "{err}"
    );
    let (_, rows) = read_csv(&tmp.path().join("out/stats.csv"));
    assert_eq!(rows.len(), 4, "the run completed");
    // Within the cap, the value is kept without a word.
    let o = elasto_with_threads(tmp.path(), "2", &["check", "s.toml"]);
    assert_code(&o, 0);
    assert!(stderr(&o).is_empty(), "{}", stderr(&o));
}
