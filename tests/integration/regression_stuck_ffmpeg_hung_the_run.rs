//! An ffmpeg that stopped reading its input hung `elasto run` forever
//! (issue 9 item 11): writing frames to it blocked without end. Now a run
//! gives up after `ELASTO_FFMPEG_TIMEOUT_SECS` without progress, kills
//! ffmpeg, exits 1 and leaves no video behind.
#![cfg(unix)]

use crate::render_support;

use crate::fake_ffmpeg::{FakeFfmpeg, files_under, process_ended, wait_at_most};
use std::time::{Duration, Instant};

#[test]
fn a_stuck_ffmpeg_is_stopped_after_the_timeout_and_no_video_is_left() {
    if render_support::no_adapter_allowed() {
        return;
    }
    // Never reads its input; `exec` so that its pid is the encoder's.
    let fake = FakeFfmpeg::new("exec sleep 600");
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let start = Instant::now();
    let mut child = fake
        .elasto(&[
            "run",
            "--frames",
            "60",
            "--resolution",
            "64x48",
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ])
        .env("ELASTO_FFMPEG_TIMEOUT_SECS", "1")
        .spawn()
        .unwrap();
    // 60 s is the default timeout: finishing well before shows the variable works.
    let (status, stderr) = wait_at_most(&mut child, Duration::from_secs(50));
    let took = start.elapsed();

    assert_eq!(status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("ffmpeg read no frame for 1 s")
            && stderr.contains("video.mp4")
            && stderr.contains("ELASTO_FFMPEG_TIMEOUT_SECS"),
        "{stderr}"
    );
    assert!(took >= Duration::from_secs(1), "gave up after {took:?}");
    assert!(took < Duration::from_secs(30), "took {took:?}");

    // `auto` asked for APNG and MP4: neither is left, partial or complete;
    // the frames written before the failure are whole.
    let files = files_under(&out);
    let frames: Vec<_> = files.iter().filter(|f| f.starts_with("frames")).collect();
    assert!(
        files.iter().all(|f| {
            let name = f.file_name().unwrap().to_string_lossy();
            !name.contains("video") && !name.ends_with(".partial")
        }),
        "{files:?}"
    );
    assert!(files.iter().any(|f| f.ends_with("stats.csv")), "{files:?}");
    assert!(!frames.is_empty() && frames.len() < 60, "{files:?}");
    for frame in frames {
        image::open(out.join(frame)).unwrap();
    }

    let pid = fake
        .encoder_pid()
        .expect("the fake ffmpeg ran as the encoder");
    assert!(process_ended(pid), "the stuck ffmpeg {pid} still runs");
}

#[test]
fn an_invalid_timeout_is_refused_before_any_work() {
    let fake = FakeFfmpeg::new("exec sleep 600");
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    for value in ["0", "-3", "soon"] {
        let mut child = fake
            .elasto(&[
                "run",
                "--frames",
                "2",
                "--video",
                "mp4",
                "--out",
                out.to_str().unwrap(),
            ])
            .env("ELASTO_FFMPEG_TIMEOUT_SECS", value)
            .spawn()
            .unwrap();
        let (status, stderr) = wait_at_most(&mut child, Duration::from_secs(30));
        assert_eq!(status.code(), Some(2), "{value}: {stderr}");
        assert!(
            stderr.contains(&format!(
                "ELASTO_FFMPEG_TIMEOUT_SECS must be a positive number of seconds \
                 (how long ffmpeg may go without progress), got `{value}`"
            )),
            "{stderr}"
        );
        assert!(!out.exists(), "{value}: the run wrote files");
    }
}
