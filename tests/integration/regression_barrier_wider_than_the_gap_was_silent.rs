//! Issue 33, item 6: a ground barrier wider than the gap the body starts at
//! (`--set effects.ground.a=100` with the box 1 above the ground) pushed the
//! body from the first step with only a generic health line at the end (and
//! `a = 11` pushed it upward silently). Now `check` and `run` say so before
//! the run, naming the key and both lengths; a barrier narrower than the
//! gap says nothing.

use crate::cli_common as common;
use common::*;

#[test]
fn a_barrier_wider_than_the_starting_gap_is_warned_before_the_run() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("s.toml"), SMALL_SCENE).unwrap();
    let expected = "effects.ground.a = 100 is more than the gap of 1 the bodies start at above \
                    the ground: the barrier pushes them up from the first step";
    let o = elasto(
        tmp.path(),
        &["check", "s.toml", "--set", "effects.ground.a=100"],
    );
    assert_code(&o, 0);
    assert!(
        stdout(&o).contains(&format!("warning         {expected}")),
        "{}",
        stdout(&o)
    );
    let o = elasto(
        tmp.path(),
        &[
            "run",
            "s.toml",
            "--set",
            "effects.ground.a=100",
            "--frames",
            "2",
            "--no-render",
            "-q",
            "-o",
            "wide",
        ],
    );
    let err = stderr(&o);
    let warned = err
        .find(&format!("elasto: warning: {expected}"))
        .unwrap_or_else(|| panic!("{err}"));
    // Said before anything else the run prints (the health line comes last).
    assert!(err[..warned].trim().is_empty(), "{err}");
    // The scene as it is (a = 0.1 below a gap of 1): no warning.
    let o = elasto(tmp.path(), &["check", "s.toml"]);
    assert_code(&o, 0);
    assert!(!stdout(&o).contains("warning"), "{}", stdout(&o));
}
