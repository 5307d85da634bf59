//! What `sweep` refuses or leaves alone: `--collect` on folders that hold
//! no sweep, shortcut flags that would replace a varied key, and folders
//! holding the user's own files.
//!
//! Each `mod regression_*` here guards one fixed bug and is named after it
//! (`cargo test --test integration regression_` selects them all).

/// Issue 33, items 21 and 25: `sweep --collect` on a missing folder said
/// "cannot write sw/sweep.csv", on an empty folder "2 of 2 runs failed" for
/// runs that never ran, and with other `--vary` values than the sweep's it
/// rewrote the real sweep's `sweep.csv` with "skipped" rows (also when the
/// values overlapped the sweep's only partly); a sweep file
/// without `scene` was read as a scene file and told about unknown scene
/// keys. Now each is exit 2 with what is wrong, and nothing is written.
mod regression_sweep_collect_wrote_runs_that_never_ran {
    use crate::cli_common as common;
    use common::*;
    use std::path::Path;
    use std::process::Output;

    /// `elasto sweep s.toml --vary VARY --frames 3 -o sw --no-render --quiet`
    /// and `extra`, in `dir`.
    fn sweep_into_sw(dir: &Path, vary: &str, extra: &[&str]) -> Output {
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
    }

    #[test]
    fn collect_refuses_a_folder_without_this_sweeps_runs_and_writes_nothing() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        std::fs::write(dir.join("s.toml"), SMALL_SCENE).unwrap();
        let sweep = |vary: &str, extra: &[&str]| sweep_into_sw(dir, vary, extra);
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
        let sweep = |vary: &str, extra: &[&str]| sweep_into_sw(dir, vary, extra);
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
}

/// Issue 33, item 19: `sweep --frames N` silently replaced a varied
/// `time.frames` in every run, and `sweep.csv` reported the varied values
/// that never ran. Now a shortcut flag that would replace a varied key
/// (`--frames` against `time.frames` or `time.duration`, `--resolution`
/// against `render.resolution`) is exit 2 naming both, before any work.
mod regression_sweep_flag_replaced_a_varied_key {
    use crate::cli_common as common;
    use common::*;

    #[test]
    fn a_shortcut_flag_that_would_replace_a_varied_key_is_refused() {
        let tmp = tempfile::tempdir().unwrap();
        std::fs::write(tmp.path().join("s.toml"), SMALL_SCENE).unwrap();
        for (vary, flag, value, key) in [
            ("time.frames=3,4", "--frames", "5", "time.frames"),
            ("time.duration=0.1,0.2", "--frames", "5", "time.duration"),
            (
                "render.resolution=[64,48],[32,24]",
                "--resolution",
                "80x60",
                "render.resolution",
            ),
        ] {
            let o = elasto(
                tmp.path(),
                &[
                    "sweep",
                    "s.toml",
                    "--vary",
                    vary,
                    flag,
                    value,
                    "-o",
                    "sw",
                    "--no-render",
                ],
            );
            assert_code(&o, 2);
            let err = stderr(&o);
            assert!(
                err.contains(&format!("`{flag} {value}`"))
                    && err.contains(&format!("would replace the varied {key} in every run")),
                "{vary}: {err}"
            );
            assert!(!tmp.path().join("sw").exists(), "{vary}: wrote a folder");
        }
        // A flag that replaces no varied key still works.
        let o = elasto(
            tmp.path(),
            &[
                "sweep",
                "s.toml",
                "--vary",
                "material.young=100,200",
                "--frames",
                "3",
                "-o",
                "sw",
                "--no-render",
                "--quiet",
            ],
        );
        assert_code(&o, 0);
    }
}

/// Issue 33, item 11: `sweep -o DIR` into an existing folder holding the
/// user's own `sweep.csv` overwrote it without `--force` (`run` and `study`
/// refuse such a folder). Now a non-empty folder that is not a sweep's
/// (neither `sweep.json` nor a run folder with its run record) is exit 2,
/// the user's files untouched, unless `--force` is given.
mod regression_sweep_overwrote_a_foreign_folder {
    use crate::cli_common as common;
    use common::*;

    #[test]
    fn a_folder_that_is_not_a_sweeps_is_refused_without_force() {
        let tmp = tempfile::tempdir().unwrap();
        std::fs::write(tmp.path().join("s.toml"), SMALL_SCENE).unwrap();
        let mine = tmp.path().join("mine");
        std::fs::create_dir(&mine).unwrap();
        std::fs::write(mine.join("sweep.csv"), "my,own\n1,2\n").unwrap();
        let sweep = |out: &str, extra: &[&str]| {
            let mut args = vec![
                "sweep",
                "s.toml",
                "--vary",
                "material.young=100,200",
                "--no-render",
                "--frames",
                "1",
                "--quiet",
                "-o",
                out,
            ];
            args.extend_from_slice(extra);
            elasto(tmp.path(), &args)
        };
        for extra in [&[][..], &["--collect"]] {
            let o = sweep("mine", extra);
            assert_code(&o, 2);
            let err = stderr(&o);
            assert!(
                err.contains("the sweep folder mine is not empty and was not made by elasto sweep")
                    && err.contains("--force"),
                "{extra:?}: {err}"
            );
            assert_eq!(
                std::fs::read_to_string(mine.join("sweep.csv")).unwrap(),
                "my,own\n1,2\n",
                "{extra:?}"
            );
            assert_eq!(std::fs::read_dir(&mine).unwrap().count(), 1, "{extra:?}");
        }

        // A sweep's own folder is taken again (its runs are skipped), and an
        // empty folder is fine.
        std::fs::create_dir(tmp.path().join("empty")).unwrap();
        assert_code(&sweep("empty", &[]), 0);
        assert_code(&sweep("empty", &[]), 0);

        // With --force the folder is the user's choice.
        assert_code(&sweep("mine", &["--force"]), 0);
        assert!(mine.join("sweep.json").is_file());
    }
}
