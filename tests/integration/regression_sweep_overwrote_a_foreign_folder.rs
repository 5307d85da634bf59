//! Issue 33, item 11: `sweep -o DIR` into an existing folder holding the
//! user's own `sweep.csv` overwrote it without `--force` (`run` and `study`
//! refuse such a folder). Now a non-empty folder that is not a sweep's
//! (neither `sweep.json` nor a run folder with its run record) is exit 2,
//! the user's files untouched, unless `--force` is given.

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
