//! `elasto compare`: exit 0 when frames match, 1 when one differs, 2 on bad input.

use crate::cli_common as common;
use common::*;
use std::path::Path;

/// A 64x48 grey image with a dark square at `x`.
fn frame(path: &Path, x: u32) {
    let img = image::RgbImage::from_fn(64, 48, |px, py| {
        if (x..x + 16).contains(&px) && (16..32).contains(&py) {
            image::Rgb([20, 20, 120])
        } else {
            image::Rgb([230; 3])
        }
    });
    img.save(path).unwrap();
}

#[test]
fn compare_passes_fails_and_rejects() {
    let tmp = tempfile::tempdir().unwrap();
    for dir in ["golden", "same", "moved"] {
        std::fs::create_dir(tmp.path().join(dir)).unwrap();
    }
    for name in ["frame_0000.png", "frame_0001.png"] {
        frame(&tmp.path().join("golden").join(name), 10);
        frame(&tmp.path().join("same").join(name), 10);
    }
    frame(&tmp.path().join("moved/frame_0000.png"), 10);
    frame(&tmp.path().join("moved/frame_0001.png"), 30);

    let o = elasto(
        tmp.path(),
        &[
            "compare", "--golden", "golden", "--frames", "same", "--diff", "d1",
        ],
    );
    assert_code(&o, 0);
    assert!(stdout(&o).contains("frame_0001.png"), "{}", stdout(&o));

    let o = elasto(
        tmp.path(),
        &[
            "compare", "--golden", "golden", "--frames", "moved", "--diff", "d2",
        ],
    );
    assert_code(&o, 1);
    assert!(
        stderr(&o).contains("1 of 2 frames differ"),
        "{}",
        stderr(&o)
    );

    let o = elasto(
        tmp.path(),
        &["compare", "--golden", "nowhere", "--frames", "same"],
    );
    assert_code(&o, 2);
    assert!(stderr(&o).contains("nowhere"), "{}", stderr(&o));
    // The cause is printed once, not repeated by the error chain.
    let err = stderr(&o);
    let cause = err.rsplit(": ").next().unwrap().trim();
    assert_eq!(err.matches(cause).count(), 1, "{err}");

    let o = elasto(
        tmp.path(),
        &[
            "compare",
            "--golden",
            "golden",
            "--frames",
            "same",
            "--threshold-mean",
            "2",
        ],
    );
    assert_code(&o, 2);
}
