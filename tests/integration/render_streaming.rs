//! Frames written while the run is still being produced: a [`SequenceWriter`]
//! with a fixed camera and range writes each frame to disk before the run
//! ends, draws exactly what the whole-run path draws, refuses to start an
//! automatic framing without the whole run, and leaves no video that looks
//! complete when the run stops early.
//!
//! Each `mod regression_*` here guards one fixed bug and is named after it
//! (`cargo test --test integration regression_` selects them all).

use crate::render_support::{no_adapter_allowed, plain_settings, square};
use elasto::encode::{RenderOutputs, SequenceWriter, VideoFormat, render_sequence};
use elasto::math::Vector;
use elasto::mesh::Mesh;
use elasto::render::{Camera, Colouring, RenderError, RenderFrame, RenderMesh, RenderSettings};
use std::path::Path;
use std::time::Duration;

fn outputs(dir: &Path, videos: Vec<VideoFormat>) -> RenderOutputs {
    RenderOutputs {
        frames_dir: dir.join("frames"),
        video_dir: dir.to_owned(),
        videos,
        fps: 20.0,
    }
}

/// A scalar-coloured 2D run seen by a fixed camera over a fixed range.
fn fixed_2d(count: usize) -> (RenderSettings, RenderMesh, Vec<RenderFrame>) {
    let settings = RenderSettings {
        width: 96,
        height: 64,
        camera: Camera::Orthographic {
            center: [1.5, 0.5],
            height: 3.0,
        },
        colouring: Colouring::Scalar {
            range: Some([0.0, 2.0]),
            label: "value",
        },
        ground_height: Some(-0.5),
        ..RenderSettings::default()
    };
    let (mesh, _) = square(0.0, 0.0, 1.0);
    let frames = (0..count)
        .map(|i| {
            let mut frame = square(0.25 * i as f32, 0.0, 1.0).1;
            frame.element_values = vec![0.2 * i as f32, 2.0 - 0.2 * i as f32];
            frame
        })
        .collect();
    (settings, mesh, frames)
}

/// A 3D cube falling towards the ground, seen by a fixed perspective camera.
/// The run reaches far beyond the first frame's bounds, which is what the
/// whole-run path could otherwise have framed differently.
fn fixed_3d(count: usize) -> (RenderSettings, RenderMesh, Vec<RenderFrame>) {
    let cube = Mesh::<3>::axis_aligned_box(Vector::<3>::zeros(), Vector::<3>::repeat(1.0), [2; 3])
        .unwrap();
    let settings = RenderSettings {
        width: 96,
        height: 64,
        camera: Camera::Perspective {
            eye: [4.0, 4.0, 7.0],
            target: [0.5, 1.5, 0.5],
            fov_degrees: 40.0,
        },
        colouring: Colouring::Flat([0.2, 0.4, 0.8]),
        ground_height: Some(0.0),
        ..RenderSettings::default()
    };
    let frames = (0..count)
        .map(|i| {
            let lift = 3.0 - 0.6 * i as f64;
            let positions: Vec<_> = cube
                .rest_positions()
                .iter()
                .map(|p| p + Vector::<3>::new(0.0, lift.max(0.0), 0.0))
                .collect();
            RenderFrame::from_positions(&positions, &vec![0.0; cube.element_count()])
        })
        .collect();
    (settings, RenderMesh::from_mesh(&cube), frames)
}

/// Streams `frames` into a writer that knows only the first one up front.
fn stream(
    settings: &RenderSettings,
    mesh: &RenderMesh,
    frames: &[RenderFrame],
    outputs: &RenderOutputs,
) -> Result<(), RenderError> {
    let mut writer = SequenceWriter::create(settings, mesh, frames.len(), &frames[..1], outputs)?;
    for frame in frames {
        writer.push(frame)?;
    }
    writer.finish()
}

fn assert_same_frames(a: &Path, b: &Path, count: usize) {
    for i in 0..count {
        let name = format!("frame_{i:04}.png");
        let image_a = image::open(a.join(&name)).unwrap().to_rgb8();
        let image_b = image::open(b.join(&name)).unwrap().to_rgb8();
        assert!(image_a == image_b, "{name} differs between the two paths");
    }
}

#[test]
fn only_an_automatic_camera_or_range_needs_the_whole_run() {
    let (fixed, _, _) = fixed_2d(1);
    assert!(!fixed.needs_whole_run());
    let auto_camera = RenderSettings {
        camera: Camera::Auto,
        ..fixed.clone()
    };
    assert!(auto_camera.needs_whole_run());
    let auto_range = RenderSettings {
        colouring: Colouring::Scalar {
            range: None,
            label: "value",
        },
        ..fixed.clone()
    };
    assert!(auto_range.needs_whole_run());
    let flat = RenderSettings {
        colouring: Colouring::Flat([1.0, 0.0, 0.0]),
        ..fixed
    };
    assert!(!flat.needs_whole_run(), "a flat colour has no range");
}

#[test]
fn an_automatic_framing_refuses_to_start_without_the_whole_run() {
    // Checked before any device or file is touched.
    let dir = tempfile::tempdir().unwrap();
    let (mesh, frame) = square(0.0, 0.0, 1.0);
    let auto = RenderSettings {
        colouring: Colouring::Scalar {
            range: None,
            label: "value",
        },
        ..plain_settings(32, 32)
    };
    let error = SequenceWriter::create(
        &auto,
        &mesh,
        5,
        std::slice::from_ref(&frame),
        &outputs(dir.path(), vec![]),
    )
    .err()
    .expect("a partial run with an automatic framing must be refused");
    assert!(
        error.to_string().contains("all 5 frames up front"),
        "{error}"
    );
    assert!(!dir.path().join("frames").exists(), "nothing written");
}

#[test]
fn streamed_frames_reach_the_disk_before_the_run_ends() {
    if no_adapter_allowed() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (settings, mesh, frames) = fixed_2d(8);
    let out = outputs(dir.path(), vec![VideoFormat::Apng]);
    let mut writer = SequenceWriter::create(&settings, &mesh, 8, &frames[..1], &out).unwrap();
    for frame in &frames[..3] {
        writer.push(frame).unwrap();
    }
    // The run is not over (5 frames to go), yet its first frames are files.
    let first = dir.path().join("frames/frame_0000.png");
    crate::cli_common::wait_until(
        "frame 0 is written while the run goes on",
        Duration::from_secs(60),
        || first.exists(),
    );
    assert!(image::open(&first).is_ok(), "frame 0 is a complete PNG");
    assert!(
        !dir.path().join("video.png").exists(),
        "the video appears only once the run is complete"
    );
    for frame in &frames[3..] {
        writer.push(frame).unwrap();
    }
    writer.finish().unwrap();
    assert!(dir.path().join("video.png").exists());
    assert!(dir.path().join("frames/frame_0007.png").exists());
}

#[test]
fn streamed_and_whole_run_frames_are_identical_in_2d_and_3d() {
    if no_adapter_allowed() {
        return;
    }
    for (dimension, (settings, mesh, frames)) in [(2, fixed_2d(6)), (3, fixed_3d(6))] {
        let dir = tempfile::tempdir().unwrap();
        let (whole, streamed) = (dir.path().join("whole"), dir.path().join("streamed"));
        render_sequence(
            &settings,
            &mesh,
            &frames,
            &outputs(&whole, vec![]),
            &mut |_| {},
        )
        .unwrap();
        stream(&settings, &mesh, &frames, &outputs(&streamed, vec![])).unwrap();
        assert_same_frames(
            &whole.join("frames"),
            &streamed.join("frames"),
            frames.len(),
        );
        // The frames are not all alike: the body moves in view.
        let first = image::open(whole.join("frames/frame_0000.png")).unwrap();
        let last = image::open(whole.join(format!("frames/frame_{:04}.png", frames.len() - 1)));
        assert!(
            first != last.unwrap(),
            "{dimension}D: the body did not move"
        );
    }
}

#[test]
fn a_run_that_stops_early_leaves_its_frames_but_no_video() {
    if no_adapter_allowed() {
        return;
    }
    let (settings, mesh, frames) = fixed_2d(6);

    // Dropped unfinished, as when the simulation fails at frame 3.
    let dir = tempfile::tempdir().unwrap();
    let out = outputs(dir.path(), vec![VideoFormat::Apng, VideoFormat::Gif]);
    let mut writer = SequenceWriter::create(&settings, &mesh, 6, &frames[..1], &out).unwrap();
    for frame in &frames[..3] {
        writer.push(frame).unwrap();
    }
    drop(writer);
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["frames"], "no video, complete or partial");
    for i in 0..3 {
        let frame = dir.path().join(format!("frames/frame_{i:04}.png"));
        assert!(image::open(&frame).is_ok(), "frame {i} is complete");
    }

    // Finished with frames missing: an error, and no video either.
    let dir = tempfile::tempdir().unwrap();
    let out = outputs(dir.path(), vec![VideoFormat::Apng]);
    let mut writer = SequenceWriter::create(&settings, &mesh, 6, &frames[..1], &out).unwrap();
    writer.push(&frames[0]).unwrap();
    let error = writer.finish().unwrap_err();
    assert!(error.to_string().contains("6 frames but only 1"), "{error}");
    assert!(!dir.path().join("video.png").exists());
    assert!(!dir.path().join(".video.png.partial").exists());
}

/// SIGINT or SIGTERM during `elasto run` left hidden `.video.*.partial`
/// files behind (issue 9 item 12), and SIGHUP (a closed terminal, a dropped
/// ssh session) killed the run without any clean-up (issue 33 item 18). Now
/// each of them stops the encoders, removes every partial file, keeps the
/// complete frames, and exits with 128 + the signal number. And SIGTERM
/// while a run that renders afterwards (automatic camera) was simulating
/// left a `stats.csv` with only its header, its rows waiting for the images
/// (issue 33 item 17): rows are now written as the frames are simulated.
#[cfg(unix)]
mod regression_interrupt_left_partial_video {
    use crate::cli_common::files_under;
    use crate::render_support;

    use std::io::Read;
    use std::process::{Child, ExitStatus, Stdio};
    use std::time::Duration;

    /// Waits for `child` (see [`crate::cli_common::wait_for_exit`]); returns
    /// its status and its stderr.
    fn wait_at_most(child: &mut Child, limit: Duration) -> (ExitStatus, String) {
        let status = crate::cli_common::wait_for_exit(child, limit, "elasto");
        let mut stderr = String::new();
        if let Some(mut pipe) = child.stderr.take() {
            pipe.read_to_string(&mut stderr).unwrap();
        }
        (status, stderr)
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
        let mut child = crate::cli_common::elasto_command()
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
        crate::cli_common::wait_until("frame 0", Duration::from_secs(60), || first.exists());
        // The videos are being written under their hidden names (waited
        // for: the video threads may open them after frame 0 is a file).
        for partial in [".video.png.partial", ".video.mp4.partial"] {
            crate::cli_common::wait_until(
                &format!("{partial} appears beside frame 0"),
                Duration::from_secs(60),
                || files_under(&out).iter().any(|f| f.ends_with(partial)),
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
        // The frames written before the signal stay, each complete (the exit
        // code says the run was interrupted, however far it had come).
        let frames: Vec<_> = after.iter().filter(|f| f.starts_with("frames")).collect();
        assert!(!frames.is_empty(), "{after:?}");
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
        let mut child = crate::cli_common::elasto_command()
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
        crate::cli_common::wait_until("20 rows of stats.csv", Duration::from_secs(60), || {
            assert!(child.try_wait().unwrap().is_none(), "the run ended early");
            rows() >= 20
        });
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
        // order (the exit code says the run was interrupted).
        let text = std::fs::read_to_string(&stats).unwrap();
        let (header, rows) = crate::cli_common::read_csv(&stats);
        assert!(rows.len() >= seen, "{} rows, {seen} seen", rows.len());
        for (frame, cells) in rows.iter().enumerate() {
            assert_eq!(cells.len(), header.len(), "row {frame}: {cells:?}");
            assert_eq!(cells[0], frame.to_string(), "rows in frame order");
        }
        assert!(text.ends_with('\n'), "the last row is whole");
        // No image was drawn before the simulation had finished (the
        // automatic camera frames the whole run).
        let frames = out.join("frames");
        let no_image = !frames.exists() || std::fs::read_dir(&frames).unwrap().next().is_none();
        assert!(no_image || rows.len() == 20_000, "{} rows", rows.len());
    }
}
