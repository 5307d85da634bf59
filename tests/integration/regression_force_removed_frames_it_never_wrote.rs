//! Issue 33, item 12 (second half): `--force` deleted any `frame_*.png`
//! (`frame_abc.png`, `frame_0042-notes.png`), not only files named as
//! elasto names its frames. Now only `frame_` + a frame number (4 digits or
//! more) + `.png`/`.vtu`, and `surface_` + a number + `.obj`/`.ply`, are
//! cleared; the user's other files stay.

use crate::cli_common as common;
use common::*;

#[test]
fn force_clears_only_files_named_like_elastos_frames() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("s.toml"), SMALL_SCENE).unwrap();
    for folder in ["out/frames", "out/meshes", "out/surfaces"] {
        std::fs::create_dir_all(dir.join(folder)).unwrap();
    }
    let theirs = [
        "out/frames/frame_abc.png",
        "out/frames/frame_0042-notes.png",
        "out/frames/frame_12.png",
        "out/meshes/frame_final.vtu",
        "out/surfaces/surface_best.obj",
    ];
    for file in theirs {
        std::fs::write(dir.join(file), "mine").unwrap();
    }
    let stale = ["out/frames/frame_0099.png", "out/meshes/frame_00042.vtu"];
    for file in stale {
        std::fs::write(dir.join(file), "old").unwrap();
    }
    let o = elasto(
        dir,
        &[
            "run",
            "s.toml",
            "--no-render",
            "--frames",
            "3",
            "-o",
            "out",
            "--force",
            "-q",
        ],
    );
    assert_code(&o, 0);
    for file in theirs {
        assert_eq!(
            std::fs::read_to_string(dir.join(file)).unwrap(),
            "mine",
            "{file} is the user's"
        );
    }
    for file in stale {
        assert!(!dir.join(file).exists(), "{file}: a stale frame is cleared");
    }
}
