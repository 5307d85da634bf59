//! `elasto run` with rendering: PNG frames and the animated PNG video.

#[path = "cli_common.rs"]
mod common;
use common::*;

#[test]
fn a_render_run_writes_png_frames_and_an_apng() {
    let tmp = tempfile::tempdir().unwrap();
    let o = elasto(
        tmp.path(),
        &[
            "run",
            "--frames",
            "2",
            "--resolution",
            "160x120",
            "--video",
            "apng",
            "--out",
            "r",
        ],
    );
    assert_code(&o, 0);
    for i in 0..2 {
        let png = image::open(tmp.path().join(format!("r/frames/frame_{i:04}.png"))).unwrap();
        assert_eq!((png.width(), png.height()), (160, 120));
    }
    assert!(!tmp.path().join("r/frames/frame_0002.png").exists());
    let apng = std::fs::read(tmp.path().join("r/video.png")).unwrap();
    assert_eq!(&apng[..8], b"\x89PNG\r\n\x1a\n");
    assert!(
        apng.windows(4).any(|w| w == b"acTL"),
        "video.png is animated"
    );
}

#[test]
fn mp4_without_ffmpeg_is_refused_before_any_work() {
    let tmp = tempfile::tempdir().unwrap();
    let empty = tmp.path().join("empty-path");
    std::fs::create_dir(&empty).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_elasto"))
        .args(["run", "--frames", "2", "--video", "mp4", "--out", "v"])
        .current_dir(tmp.path())
        .env("PATH", &empty)
        .output()
        .unwrap();
    assert_code(&o, 2);
    assert!(
        stderr(&o).contains("--video mp4") && stderr(&o).contains("ffmpeg"),
        "{}",
        stderr(&o)
    );
    assert!(!tmp.path().join("v").exists());
    // `auto` falls back to APNG alone.
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_elasto"))
        .args([
            "run",
            "--frames",
            "2",
            "--resolution",
            "64x48",
            "--out",
            "a",
            "-q",
        ])
        .current_dir(tmp.path())
        .env("PATH", &empty)
        .output()
        .unwrap();
    assert_code(&o, 0);
    assert!(tmp.path().join("a/video.png").exists());
    assert!(!tmp.path().join("a/video.mp4").exists());
}
