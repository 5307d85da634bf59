//! SIGINT or SIGTERM during `elasto run` left hidden `.video.*.partial`
//! files behind (issue 9 item 12), and SIGHUP (a closed terminal, a dropped
//! ssh session) killed the run without any clean-up (issue 33 item 18). Now
//! each of them stops the encoders, removes every partial file, keeps the
//! complete frames, and exits with 128 + the signal number. And SIGTERM
//! while a run that renders afterwards (automatic camera) was simulating
//! left a `stats.csv` with only its header, its rows waiting for the images
//! (issue 33 item 17): rows are now written as the frames are simulated.
#![cfg(unix)]

use crate::render_support;

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// Waits for `child`, killing it and failing the test after `limit`;
/// returns its status and its stderr.
fn wait_at_most(child: &mut Child, limit: Duration) -> (ExitStatus, String) {
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("elasto still ran after {limit:?}: it hangs");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut stderr = String::new();
    if let Some(mut pipe) = child.stderr.take() {
        pipe.read_to_string(&mut stderr).unwrap();
    }
    (status, stderr)
}

/// Waits until `path` exists, for at most `limit`.
fn wait_for_file(path: &Path, limit: Duration) -> bool {
    let start = Instant::now();
    while start.elapsed() < limit {
        if path.exists() {
            return true;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    false
}

/// Every file under `dir`, recursively, relative to it.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(folder) = pending.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                pending.push(path);
            } else {
                files.push(path.strip_prefix(dir).unwrap().to_path_buf());
            }
        }
    }
    files.sort();
    files
}

/// Starts a long run that renders while simulating (fixed camera and range)
/// with its APNG and MP4 videos, sends `signal` once the first frame is
/// written, and checks what is left.
fn interrupt_run(signal: i32, name: &str) {
    if render_support::no_adapter_allowed() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let mut child = Command::new(env!("CARGO_BIN_EXE_elasto"))
        .args([
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
        .env_remove("RUST_BACKTRACE")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
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
}

#[test]
fn sigint_removes_partial_files_and_exits_130() {
    interrupt_run(libc::SIGINT, "SIGINT");
}

#[test]
fn sigterm_removes_partial_files_and_exits_143() {
    interrupt_run(libc::SIGTERM, "SIGTERM");
}

#[test]
fn sighup_removes_partial_files_and_exits_129() {
    interrupt_run(libc::SIGHUP, "SIGHUP");
}

#[test]
fn sigterm_while_simulating_keeps_the_rows_of_the_frames_simulated() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    // The automatic camera: the frames are drawn after the simulation.
    let mut child = Command::new(env!("CARGO_BIN_EXE_elasto"))
        .args([
            "run",
            "--frames",
            "20000",
            "--resolution",
            "64x48",
            "--video",
            "none",
        ])
        .args(["--out", out.to_str().unwrap(), "--quiet"])
        .env_remove("RUST_BACKTRACE")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stats = out.join("stats.csv");
    let rows = || {
        let text = std::fs::read_to_string(&stats).unwrap_or_default();
        text.lines().count().saturating_sub(1)
    };
    let start = Instant::now();
    while rows() < 20 {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no 20 rows after 60 s"
        );
        assert!(child.try_wait().unwrap().is_none(), "the run ended early");
        std::thread::sleep(Duration::from_millis(5));
    }
    let seen = rows();
    // SAFETY: kill(2) has no memory-safety preconditions.
    let sent = unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGTERM) };
    assert_eq!(sent, 0);
    let (status, stderr) = wait_at_most(&mut child, Duration::from_secs(30));
    assert_eq!(
        status.code(),
        Some(128 + libc::SIGTERM),
        "{status:?}: {stderr}"
    );

    // Every frame simulated before the signal has its row, complete and in
    // order; the run was stopped long before its end.
    let text = std::fs::read_to_string(&stats).unwrap();
    let mut lines = text.lines();
    let columns = lines.next().unwrap().split(',').count();
    let rows: Vec<&str> = lines.collect();
    assert!(
        rows.len() >= seen && rows.len() < 20_000,
        "{} rows",
        rows.len()
    );
    for (frame, row) in rows.iter().enumerate() {
        let cells: Vec<&str> = row.split(',').collect();
        assert_eq!(cells.len(), columns, "row {frame}: {row}");
        assert_eq!(cells[0], frame.to_string(), "rows in frame order");
    }
    assert!(text.ends_with('\n'), "the last row is whole");
    // No image was drawn: the simulation had not finished.
    let frames = out.join("frames");
    assert!(!frames.exists() || std::fs::read_dir(&frames).unwrap().next().is_none());
}
