//! `elasto compare` run as a binary on real PNG files: exit 0 when frames
//! match, 1 when one differs or is missing, 2 on bad input; the printed
//! table and the difference images.

use crate::cli_common::*;
use std::path::{Path, PathBuf};
use std::process::Output;

use image::{ImageFormat, Rgba, RgbaImage};

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

/// A light frame with a dark-edged coloured box whose left edge is at `left`.
fn box_frame(width: u32, height: u32, left: u32) -> RgbaImage {
    RgbaImage::from_fn(width, height, |x, y| {
        let inside =
            (left..left + width / 3).contains(&x) && (height / 3..2 * height / 3).contains(&y);
        let border = inside
            && (x == left
                || x == left + width / 3 - 1
                || y == height / 3
                || y == 2 * height / 3 - 1);
        match (inside, border) {
            (true, true) => Rgba([30, 30, 40, 255]),
            (true, false) => Rgba([60, 170, 120, 255]),
            _ => Rgba([240, 240, 240, 255]),
        }
    })
}

fn save(dir: &Path, name: &str, image: &RgbaImage) {
    std::fs::create_dir_all(dir).unwrap();
    image
        .save_with_format(dir.join(name), ImageFormat::Png)
        .unwrap();
}

/// `golden/` and `run/frames/` with three identical 160×120 frames.
fn folders() -> (tempfile::TempDir, PathBuf, PathBuf) {
    let tmp = tempfile::tempdir().unwrap();
    let golden = tmp.path().join("golden");
    let frames = tmp.path().join("run/frames");
    for i in 0..3 {
        let image = box_frame(160, 120, 20 + 30 * i);
        save(&golden, &format!("frame_{i:04}.png"), &image);
        save(&frames, &format!("frame_{i:04}.png"), &image);
    }
    (tmp, golden, frames)
}

fn compare(golden: &Path, frames: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "compare",
        "--golden",
        golden.to_str().unwrap(),
        "--frames",
        frames.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    elasto(golden.parent().unwrap(), &args)
}

/// Stdout and stderr, after checking the exit code (both shown if it is wrong).
fn expect_exit(output: &Output, code: i32) -> (String, String) {
    assert_code(output, code);
    (stdout(output), stderr(output))
}

/// The table row of `name`.
fn row<'a>(stdout: &'a str, name: &str) -> &'a str {
    stdout
        .lines()
        .find(|l| l.starts_with(name))
        .unwrap_or_else(|| panic!("no row for {name} in\n{stdout}"))
}

#[test]
fn identical_frames_pass_with_exit_0() {
    let (tmp, golden, frames) = folders();
    let out = compare(&golden, &frames, &[]);
    let (stdout, _) = expect_exit(&out, 0);
    for i in 0..3 {
        let r = row(&stdout, &format!("frame_{i:04}.png"));
        assert!(r.ends_with("pass") && r.contains("0.000000"), "{r}");
    }
    // Difference images go beside the frames folder by default.
    let diff = tmp.path().join("run/diff");
    assert!(
        diff.join("frame_0001.png").is_file(),
        "no diff in {}",
        diff.display()
    );
    assert!(diff.join("frame_0001.actual.png").is_file());
}

#[test]
fn a_shifted_frame_fails_with_exit_1_and_is_named() {
    let (tmp, golden, frames) = folders();
    save(&frames, "frame_0001.png", &box_frame(160, 120, 54)); // 4 px to the right
    let diff = tmp.path().join("diffs");
    let out = compare(&golden, &frames, &["--diff", diff.to_str().unwrap()]);
    let (stdout, _) = expect_exit(&out, 1);
    assert!(row(&stdout, "frame_0001.png").contains("FAIL"), "{stdout}");
    assert!(row(&stdout, "frame_0000.png").ends_with("pass"), "{stdout}");
    assert!(row(&stdout, "frame_0002.png").ends_with("pass"), "{stdout}");
    // The magma difference image shows where the box moved.
    let d = image::open(diff.join("frame_0001.png"))
        .unwrap()
        .into_rgb8();
    let dark = d.get_pixel(5, 5).0;
    assert!(d.pixels().any(|p| p.0 != dark));
}

#[test]
fn thresholds_from_the_command_line_are_used() {
    let (_tmp, golden, frames) = folders();
    save(&frames, "frame_0001.png", &box_frame(160, 120, 54));
    let out = compare(
        &golden,
        &frames,
        &["--threshold-mean", "1", "--threshold-percentile", "1"],
    );
    let (stdout, _) = expect_exit(&out, 0);
    assert!(row(&stdout, "frame_0001.png").ends_with("pass"), "{stdout}");

    let out = compare(&golden, &frames, &["--threshold-mean", "1.5"]);
    let (_, stderr) = expect_exit(&out, 2);
    assert!(
        stderr.contains("mean") && stderr.contains("1.5"),
        "{stderr}"
    );
}

#[test]
fn a_missing_frame_fails_with_exit_1() {
    let (_tmp, golden, frames) = folders();
    std::fs::remove_file(frames.join("frame_0002.png")).unwrap();
    let out = compare(&golden, &frames, &[]);
    let (stdout, _) = expect_exit(&out, 1);
    assert!(
        row(&stdout, "frame_0002.png").contains("MISSING"),
        "{stdout}"
    );
}

#[test]
fn a_size_mismatch_fails_with_exit_1() {
    let (_tmp, golden, frames) = folders();
    save(&frames, "frame_0000.png", &box_frame(320, 240, 40));
    let out = compare(&golden, &frames, &[]);
    let (stdout, _) = expect_exit(&out, 1);
    let r = row(&stdout, "frame_0000.png");
    assert!(
        r.contains("SIZE MISMATCH (golden 160x120, actual 320x240)"),
        "{r}"
    );
}

#[test]
fn an_empty_golden_folder_is_an_error_naming_it() {
    let (tmp, _golden, frames) = folders();
    let empty = tmp.path().join("empty-golden");
    std::fs::create_dir_all(&empty).unwrap();
    let out = compare(&empty, &frames, &[]);
    let (_, stderr) = expect_exit(&out, 2);
    assert!(
        stderr.contains("empty-golden") && stderr.contains("no *.png"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// Issue 33, item 20: difference and actual images were written through
/// symbolic links placed in `--diff` (links to a golden frame): the golden
/// image was overwritten, exit 0. Now each image is written to a temporary
/// file and renamed over whatever was there: the links are replaced, their
/// targets untouched.
#[test]
fn links_in_the_diff_folder_are_replaced_not_written_through() {
    let (tmp, golden, frames) = folders();
    // Frame 1 differs, so both its images are written.
    save(&frames, "frame_0001.png", &box_frame(160, 120, 90));
    let diff = tmp.path().join("diff");
    std::fs::create_dir_all(&diff).unwrap();
    let target = golden.join("frame_0001.png");
    let before = std::fs::read(&target).unwrap();
    for name in [
        "frame_0001.png",
        "frame_0001.actual.png",
        ".frame_0001.png.partial",
    ] {
        std::os::unix::fs::symlink(&target, diff.join(name)).unwrap();
    }
    let d = diff.to_str().unwrap();
    expect_exit(&compare(&golden, &frames, &["--diff", d]), 1);
    assert_eq!(
        std::fs::read(&target).unwrap(),
        before,
        "the golden frame is untouched"
    );
    for name in ["frame_0001.png", "frame_0001.actual.png"] {
        let path = diff.join(name);
        assert!(
            !path.is_symlink() && path.is_file(),
            "{name} is a file of its own"
        );
    }
    assert!(
        !diff.join(".frame_0001.png.partial").exists(),
        "no temporary left"
    );
    assert_eq!(
        std::fs::read(diff.join("frame_0001.actual.png")).unwrap(),
        std::fs::read(frames.join("frame_0001.png")).unwrap()
    );
}
