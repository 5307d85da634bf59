//! `elasto run` with rendering: PNG frames and the videos.

use crate::cli_common as common;
use crate::mp4_file::Mp4File;
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

/// `auto` writes APNG and MP4 with nothing on `PATH`: the MP4 is encoded
/// in the process, one sample per frame, at the run's size.
#[test]
fn auto_video_writes_apng_and_mp4_with_nothing_on_path() {
    let tmp = tempfile::tempdir().unwrap();
    let empty = tmp.path().join("empty-path");
    std::fs::create_dir(&empty).unwrap();
    let o = crate::cli_common::elasto_command()
        .args([
            "run",
            "--frames",
            "4",
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
    let mp4 = Mp4File::read(&tmp.path().join("a/video.mp4")).unwrap();
    assert_eq!(mp4.samples.len(), 4);
    assert_eq!((mp4.track_size, mp4.coded_size), ((64, 48), (64, 48)));
    assert_eq!(mp4.decode_rgb().unwrap().len(), 4);
}

#[test]
fn mp4_larger_than_the_encoder_takes_is_refused_before_any_work() {
    let tmp = tempfile::tempdir().unwrap();
    let o = elasto(
        tmp.path(),
        &[
            "run",
            "--frames",
            "2",
            "--resolution",
            "4096x2160",
            "--video",
            "mp4",
            "--out",
            "v",
        ],
    );
    assert_code(&o, 2);
    let log = stderr(&o);
    assert!(
        log.contains("--video mp4")
            && log.contains("video.mp4")
            && log.contains("4096x2160")
            && log.contains("3840x2160"),
        "{log}"
    );
    assert!(!tmp.path().join("v").exists());
}

/// With a fixed camera and colour range, `run` renders while it simulates
/// (one "simulate+render" phase); with the automatic ones it renders after
/// (a separate "render" phase). Both write every frame and the video.
#[test]
fn a_fixed_camera_and_range_render_while_simulating() {
    let tmp = tempfile::tempdir().unwrap();
    let common = [
        "run",
        "--frames",
        "3",
        "--resolution",
        "96x64",
        "--video",
        "apng",
    ];
    let fixed = [
        "--set",
        "render.camera.center=[0.5, 9.0]",
        "--set",
        "render.camera.height=6.0",
        "--set",
        "render.range=[0.0, 0.5]",
    ];
    let streamed = elasto(
        tmp.path(),
        &[&common[..], &fixed[..], &["--out", "streamed"]].concat(),
    );
    assert_code(&streamed, 0);
    let log = stderr(&streamed);
    assert!(log.contains("simulate+render: 3/3 frames"), "{log}");
    assert!(
        !log.contains("\nrender:") && !log.starts_with("render:"),
        "{log}"
    );

    let deferred = elasto(tmp.path(), &[&common[..], &["--out", "deferred"]].concat());
    assert_code(&deferred, 0);
    let log = stderr(&deferred);
    assert!(log.contains("simulate: 3/3 frames"), "{log}");
    assert!(log.contains("render: 3/3 frames"), "{log}");

    for run in ["streamed", "deferred"] {
        for i in 0..3 {
            let frame = tmp.path().join(format!("{run}/frames/frame_{i:04}.png"));
            assert!(image::open(&frame).is_ok(), "{}", frame.display());
        }
        assert!(tmp.path().join(run).join("video.png").exists(), "{run}");
    }
}

/// `--force` over an earlier, longer run: the earlier frames are removed,
/// so the folder holds exactly the new frames, the same bytes as a fresh
/// run, with no hidden partial file left; a frame with a second hard link
/// keeps the earlier bytes under the other name.
#[test]
fn a_forced_rerun_leaves_only_its_own_frames() {
    let tmp = tempfile::tempdir().unwrap();
    let run = |out: &str, frames: &str, force: bool| {
        let mut args = vec![
            "run",
            "--frames",
            frames,
            "--resolution",
            "160x120",
            "--video",
            "none",
            "--out",
            out,
            "-q",
        ];
        if force {
            args.push("--force");
        }
        assert_code(&elasto(tmp.path(), &args), 0);
    };
    let names = |dir: &str| {
        let mut names: Vec<String> = std::fs::read_dir(tmp.path().join(dir))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    };
    run("fresh", "3", false);
    run("o", "5", false);
    let old_frame = std::fs::read(tmp.path().join("o/frames/frame_0000.png")).unwrap();
    std::fs::hard_link(
        tmp.path().join("o/frames/frame_0000.png"),
        tmp.path().join("kept.png"),
    )
    .unwrap();

    run("o", "3", true);
    assert_eq!(names("o/frames"), names("fresh/frames"));
    assert_eq!(
        names("o/frames"),
        ["frame_0000.png", "frame_0001.png", "frame_0002.png"]
    );
    for name in names("o/frames") {
        let path = |dir: &str| tmp.path().join(dir).join("frames").join(&name);
        assert_eq!(
            std::fs::read(path("o")).unwrap(),
            std::fs::read(path("fresh")).unwrap(),
            "{name}"
        );
    }
    assert_eq!(
        std::fs::read(tmp.path().join("kept.png")).unwrap(),
        old_frame
    );
}
