//! A run's frames and errors through the sequence writer: a frame that
//! fails stops the run with its own error, after the frames before it are
//! written whole; a writer dropped unfinished writes every frame pushed.

use crate::render_support::no_adapter_allowed;
use elasto::encode::{RenderOutputs, SequenceWriter, VideoFormat};
use elasto::math::Vector;
use elasto::mesh::Mesh;
use elasto::render::{Colouring, RenderFrame, RenderMesh, RenderSettings};
use std::path::Path;

fn outputs(dir: &Path) -> RenderOutputs {
    RenderOutputs {
        frames_dir: dir.join("frames"),
        video_dir: dir.to_owned(),
        videos: vec![VideoFormat::Apng],
        fps: 20.0,
    }
}

/// A 2D plate crossing the image and stretching, automatic camera and
/// colour range with the legend, over the ground: the default scene's kind.
fn moving_2d(count: usize) -> (RenderSettings, RenderMesh, Vec<RenderFrame>) {
    let plate =
        Mesh::<2>::axis_aligned_box(Vector::<2>::zeros(), Vector::<2>::new(2.0, 1.0), [6, 3])
            .unwrap();
    let settings = RenderSettings {
        width: 320,
        height: 180,
        colouring: Colouring::Scalar {
            range: None,
            label: "energy density",
        },
        ground_height: Some(-0.5),
        ..RenderSettings::default()
    };
    let frames = (0..count)
        .map(|i| {
            let t = i as f64 / count as f64;
            let positions: Vec<_> = plate
                .rest_positions()
                .iter()
                .map(|p| Vector::<2>::new(p.x * (1.0 + 0.3 * t) + 4.0 * t, p.y + (3.0 * t).sin()))
                .collect();
            let values: Vec<f64> = (0..plate.element_count())
                .map(|e| (e as f64 * 0.37 + 5.0 * t).sin())
                .collect();
            RenderFrame::from_positions(&positions, &values)
        })
        .collect();
    (settings, RenderMesh::from_mesh(&plate), frames)
}

#[test]
fn a_frame_that_fails_stops_the_run_with_its_error() {
    if no_adapter_allowed() {
        return;
    }
    let (settings, mesh, mut frames) = moving_2d(24);
    // Frame 13 has a vertex too few; the frames before it are fine.
    frames[13].positions.pop();
    let dir = tempfile::tempdir().unwrap();
    let known = moving_2d(24).2;
    let mut writer =
        SequenceWriter::create(&settings, &mesh, frames.len(), &known, &outputs(dir.path()))
            .unwrap();
    let error = frames
        .iter()
        .try_for_each(|frame| writer.push(frame))
        .and_then(|()| writer.finish())
        .unwrap_err();
    assert!(error.to_string().contains("positions"), "{error}");
    for i in 0..13 {
        let frame = dir.path().join(format!("frames/frame_{i:04}.png"));
        assert!(image::open(&frame).is_ok(), "frame {i} is complete");
    }
    assert!(!dir.path().join("frames/frame_0013.png").exists());
    assert!(!dir.path().join("video.png").exists(), "no video");
    let leftovers: Vec<_> = std::fs::read_dir(dir.path().join("frames"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.starts_with('.'))
        .collect();
    assert!(leftovers.is_empty(), "partial files left: {leftovers:?}");
}

#[test]
fn a_run_dropped_unfinished_writes_every_frame_pushed() {
    if no_adapter_allowed() {
        return;
    }
    let (settings, mesh, frames) = moving_2d(30);
    let dir = tempfile::tempdir().unwrap();
    let mut writer = SequenceWriter::create(
        &settings,
        &mesh,
        frames.len(),
        &frames,
        &outputs(dir.path()),
    )
    .unwrap();
    // As when the simulation fails after frame 19: the writer is dropped.
    for frame in &frames[..20] {
        writer.push(frame).unwrap();
    }
    drop(writer);
    for i in 0..20 {
        let frame = dir.path().join(format!("frames/frame_{i:04}.png"));
        assert!(image::open(&frame).is_ok(), "frame {i} is complete");
    }
    assert!(!dir.path().join("frames/frame_0020.png").exists());
    assert!(!dir.path().join("video.png").exists(), "no video");
}
