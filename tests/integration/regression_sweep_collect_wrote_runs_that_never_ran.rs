//! Issue 33, items 21 and 25: `sweep --collect` on a missing folder said
//! "cannot write sw/sweep.csv", on an empty folder "2 of 2 runs failed" for
//! runs that never ran, and with other `--vary` values than the sweep's it
//! rewrote the real sweep's `sweep.csv` with "skipped" rows (also when the
//! values overlapped the sweep's only partly); a sweep file
//! without `scene` was read as a scene file and told about unknown scene
//! keys. Now each is exit 2 with what is wrong, and nothing is written.

use crate::cli_common as common;
use common::*;

#[test]
fn collect_refuses_a_folder_without_this_sweeps_runs_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("s.toml"), SMALL_SCENE).unwrap();
    let sweep = |vary: &str, extra: &[&str]| {
        let mut args = vec![
            "sweep",
            "s.toml",
            "--vary",
            vary,
            "--frames",
            "3",
            "-o",
            "sw",
            "--no-render",
            "--quiet",
        ];
        args.extend(extra);
        elasto(dir, &args)
    };
    // No folder: said so, none made.
    let o = sweep("material.young=100,200", &["--collect"]);
    assert_code(&o, 2);
    assert!(
        stderr(&o).contains("there is no sweep folder here"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.join("sw").exists());
    // An empty folder: said so, left empty.
    std::fs::create_dir(dir.join("sw")).unwrap();
    let o = sweep("material.young=100,200", &["--collect"]);
    assert_code(&o, 2);
    assert!(stderr(&o).contains("the folder is empty"), "{}", stderr(&o));
    assert_eq!(std::fs::read_dir(dir.join("sw")).unwrap().count(), 0);
    // A real sweep, then a collect with other values: its table is untouched.
    assert_code(&sweep("material.young=100,200", &[]), 0);
    let table = std::fs::read(dir.join("sw/sweep.csv")).unwrap();
    let o = sweep("material.young=300,400", &["--collect"]);
    assert_code(&o, 2);
    assert!(
        stderr(&o).contains("it holds none of this sweep's runs")
            && stderr(&o).contains("nothing was written"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read(dir.join("sw/sweep.csv")).unwrap(), table);
    // The sweep's own values collect as before.
    assert_code(&sweep("material.young=100,200", &["--collect"]), 0);
}

#[test]
fn collect_with_values_overlapping_the_sweeps_partly_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("s.toml"), SMALL_SCENE).unwrap();
    let sweep = |vary: &str, extra: &[&str]| {
        let mut args = vec![
            "sweep",
            "s.toml",
            "--vary",
            vary,
            "--frames",
            "3",
            "-o",
            "sw",
            "--no-render",
            "--quiet",
        ];
        args.extend(extra);
        elasto(dir, &args)
    };
    assert_code(&sweep("material.young=100,200,300", &[]), 0);
    let table = std::fs::read(dir.join("sw/sweep.csv")).unwrap();
    let json = std::fs::read(dir.join("sw/sweep.json")).unwrap();
    // Run 0 (100) is the sweep's; runs 1 and 2 (400, 500) never ran, and
    // the folder holds the sweep's 200 and 300 instead.
    let o = sweep("material.young=100,400,500", &["--collect"]);
    assert_code(&o, 2);
    let err = stderr(&o);
    assert!(
        err.contains(
            "it holds runs of other values than these arguments describe \
             (0001_material.young=200, 0002_material.young=300) while 2 of theirs never ran \
             there (0001_material.young=400, 0002_material.young=500)"
        ) && err.contains("nothing was written"),
        "{err}"
    );
    assert_eq!(std::fs::read(dir.join("sw/sweep.csv")).unwrap(), table);
    assert_eq!(std::fs::read(dir.join("sw/sweep.json")).unwrap(), json);
    // A subset of the sweep's runs, all there, collects (exit 0).
    assert_code(&sweep("material.young=100,200", &["--collect"]), 0);

    // A shard still to run is not a mistake: its runs are `skipped` (exit 1).
    let o = elasto(
        dir,
        &[
            "sweep",
            "s.toml",
            "--vary",
            "material.young=100,200",
            "--frames",
            "3",
            "-o",
            "sharded",
            "--no-render",
            "--quiet",
            "--shard",
            "0/2",
        ],
    );
    assert_code(&o, 0);
    let o = elasto(
        dir,
        &[
            "sweep",
            "s.toml",
            "--vary",
            "material.young=100,200",
            "--frames",
            "3",
            "-o",
            "sharded",
            "--no-render",
            "--quiet",
            "--collect",
        ],
    );
    assert_code(&o, 1);
    let text = std::fs::read_to_string(dir.join("sharded/sweep.csv")).unwrap();
    assert!(text.contains("skipped"), "{text}");
}

#[test]
fn a_sweep_file_without_its_scene_is_told_so() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(
        tmp.path().join("study.toml"),
        "name = \"stiffness\"\n[vary]\n\"material.young\" = [100, 300]\n",
    )
    .unwrap();
    let o = elasto(tmp.path(), &["sweep", "study.toml", "--no-render"]);
    assert_code(&o, 2);
    assert!(
        stderr(&o).contains("`scene` is missing (a scene file or built-in name)"),
        "{}",
        stderr(&o)
    );
    std::fs::write(tmp.path().join("study.toml"), "scene = 3\n").unwrap();
    let o = elasto(tmp.path(), &["sweep", "study.toml", "--no-render"]);
    assert_code(&o, 2);
    assert!(
        stderr(&o).contains("`scene` must be a string"),
        "{}",
        stderr(&o)
    );
}
