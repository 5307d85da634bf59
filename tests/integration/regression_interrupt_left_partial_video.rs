//! SIGINT or SIGTERM during `elasto run` left hidden `.video.*.partial`
//! files behind (issue 9 item 12). Now an interrupt stops the encoders,
//! removes every partial file, keeps the complete frames, and exits with
//! 128 + the signal number.
#![cfg(unix)]

use crate::render_support;

use crate::fake_ffmpeg::{FakeFfmpeg, files_under, process_ended, wait_at_most, wait_for_file};
use std::time::Duration;

/// Starts a long run that renders while simulating (fixed camera and range)
/// with APNG and a fake MP4 encoder, sends `signal` once the first frame is
/// written, and checks what is left.
fn interrupt_run(signal: i32, name: &str) {
    if render_support::no_adapter_allowed() {
        return;
    }
    // An encoder that takes every frame: its output grows while the run goes.
    let fake = FakeFfmpeg::new("exec cat > \"$last\"");
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let mut child = fake
        .elasto(&[
            "run",
            "--frames",
            "5000",
            "--resolution",
            "64x48",
            "--set",
            "render.camera.center=[0.5, 5.5]",
            "--set",
            "render.camera.height=12.0",
            "--set",
            "render.range=[0.0, 0.5]",
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ])
        .spawn()
        .unwrap();
    let first = out.join("frames/frame_0000.png");
    assert!(
        wait_for_file(&first, Duration::from_secs(60)),
        "no frame after 60 s"
    );
    // The videos are being written under their hidden names.
    let before = files_under(&out);
    for partial in [".video.png.partial", ".video.mp4.partial"] {
        assert!(
            before.iter().any(|f| f.ends_with(partial)),
            "{partial} missing: {before:?}"
        );
    }

    // SAFETY: kill(2) has no memory-safety preconditions.
    let sent = unsafe { libc::kill(child.id() as libc::pid_t, signal) };
    assert_eq!(sent, 0);
    let (status, stderr) = wait_at_most(&mut child, Duration::from_secs(30));

    assert_eq!(status.code(), Some(128 + signal), "{status:?}: {stderr}");
    assert!(
        stderr.contains(&format!("interrupted by {name}")),
        "{stderr}"
    );
    let after = files_under(&out);
    assert!(
        after.iter().all(|f| {
            let file = f.file_name().unwrap().to_string_lossy();
            !file.ends_with(".partial") && !file.starts_with("video")
        }),
        "{after:?}"
    );
    // The frames written before the signal stay, each complete.
    let frames: Vec<_> = after.iter().filter(|f| f.starts_with("frames")).collect();
    assert!(!frames.is_empty() && frames.len() < 5000, "{after:?}");
    for frame in &frames {
        let image = image::open(out.join(frame)).unwrap();
        assert_eq!((image.width(), image.height()), (64, 48), "{frame:?}");
    }
    let pid = fake
        .encoder_pid()
        .expect("the fake ffmpeg ran as the encoder");
    assert!(process_ended(pid), "the encoder {pid} still runs");
}

#[test]
fn sigint_removes_partial_files_and_exits_130() {
    interrupt_run(libc::SIGINT, "SIGINT");
}

#[test]
fn sigterm_removes_partial_files_and_exits_143() {
    interrupt_run(libc::SIGTERM, "SIGTERM");
}
