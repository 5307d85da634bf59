//! Frames drawn by two devices at once (`render::drawers`, `render::egl_gpu`):
//! on Mesa's llvmpipe a second software device, with a rasteriser of its
//! own, draws frames beside the shared one. A frame is the same bytes
//! whichever device draws it, the frames and the video come out in frame
//! order, and a frame that fails stops the run with its own error.

use crate::render_support::no_adapter_allowed;
use elasto::math::Vector;
use elasto::mesh::Mesh;
use elasto::render::{
    Colouring, FrameCost, PreparedRenderers, RenderFrame, RenderMesh, RenderOutputs,
    RenderSettings, SequenceWriter, VideoFormat, adapter_description,
};
use std::collections::BTreeMap;
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

/// A 3D box falling onto the ground and tumbling, automatic camera.
fn falling_3d(count: usize) -> (RenderSettings, RenderMesh, Vec<RenderFrame>) {
    let cube = Mesh::<3>::axis_aligned_box(Vector::<3>::zeros(), Vector::<3>::repeat(1.0), [2; 3])
        .unwrap();
    let settings = RenderSettings {
        width: 160,
        height: 120,
        colouring: Colouring::Scalar {
            range: None,
            label: "volume ratio",
        },
        ground_height: Some(0.0),
        ..RenderSettings::default()
    };
    let frames = (0..count)
        .map(|i| {
            let t = i as f64 / count as f64;
            let (s, c) = (2.0 * t).sin_cos();
            let positions: Vec<_> = cube
                .rest_positions()
                .iter()
                .map(|p| {
                    Vector::<3>::new(c * p.x - s * p.y, s * p.x + c * p.y + 3.0 * (1.0 - t), p.z)
                })
                .collect();
            let values = vec![t; cube.element_count()];
            RenderFrame::from_positions(&positions, &values)
        })
        .collect();
    (settings, RenderMesh::from_mesh(&cube), frames)
}

/// Writes the run with at most `devices` devices into `dir`; the frames'
/// costs, in order.
fn write_run(
    settings: &RenderSettings,
    mesh: &RenderMesh,
    frames: &[RenderFrame],
    devices: usize,
    dir: &Path,
) -> (usize, Vec<FrameCost>) {
    let prepared = PreparedRenderers::prepare_with(settings, mesh, devices).unwrap();
    let used = prepared.devices();
    let mut writer =
        SequenceWriter::create_prepared(prepared, frames.len(), frames, &outputs(dir)).unwrap();
    let mut costs = Vec::new();
    for frame in frames {
        writer.push(frame).unwrap();
        costs.extend(writer.take_costs());
    }
    costs.extend(writer.finish_with_costs().unwrap());
    (used, costs)
}

/// Every file of a run's output folder, by its path in the folder.
fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut files = BTreeMap::new();
    for sub in ["", "frames"] {
        for entry in std::fs::read_dir(dir.join(sub)).unwrap() {
            let path = entry.unwrap().path();
            if path.is_file() {
                let name = path
                    .strip_prefix(dir)
                    .unwrap()
                    .to_string_lossy()
                    .into_owned();
                files.insert(name, std::fs::read(&path).unwrap());
            }
        }
    }
    files
}

/// Where llvmpipe draws, the second device is there: a run that could use
/// it but did not would pass the comparisons below without testing them.
fn expect_second_device() -> bool {
    adapter_description().is_ok_and(|adapter| adapter.contains("llvmpipe"))
}

fn two_devices_draw_what_one_draws(
    (settings, mesh, frames): (RenderSettings, RenderMesh, Vec<RenderFrame>),
) {
    let dir = tempfile::tempdir().unwrap();
    let (one, two) = (dir.path().join("one"), dir.path().join("two"));
    let (used, costs) = write_run(&settings, &mesh, &frames, 1, &one);
    assert_eq!(used, 1);
    assert!(costs.iter().all(|cost| cost.drawer == 0));
    let (used, costs) = write_run(&settings, &mesh, &frames, 2, &two);
    assert_eq!(costs.len(), frames.len(), "every frame's cost, once");
    if expect_second_device() {
        assert_eq!(used, 2, "llvmpipe has a second software device");
        let second = costs.iter().filter(|cost| cost.drawer == 1).count();
        assert!(
            second > 0 && second < frames.len(),
            "both devices drew frames: {second} of {} on the second",
            frames.len()
        );
    }
    let (one, two) = (files(&one), files(&two));
    assert_eq!(
        one.keys().collect::<Vec<_>>(),
        two.keys().collect::<Vec<_>>()
    );
    assert_eq!(one.len(), frames.len() + 1, "the frames and video.png");
    for (name, bytes) in &one {
        assert!(
            bytes == &two[name],
            "{name} differs between one and two devices"
        );
    }
}

#[test]
fn two_devices_draw_the_same_2d_frames_and_video_as_one() {
    if no_adapter_allowed() {
        return;
    }
    two_devices_draw_what_one_draws(moving_2d(40));
}

#[test]
fn two_devices_draw_the_same_3d_frames_and_video_as_one() {
    if no_adapter_allowed() {
        return;
    }
    two_devices_draw_what_one_draws(falling_3d(24));
}

#[test]
fn a_frame_that_fails_on_either_device_stops_the_run_with_its_error() {
    if no_adapter_allowed() {
        return;
    }
    let (settings, mesh, mut frames) = moving_2d(24);
    // Frame 13 has a vertex too few; the frames before it are fine.
    frames[13].positions.pop();
    let dir = tempfile::tempdir().unwrap();
    let prepared = PreparedRenderers::prepare_with(&settings, &mesh, 2).unwrap();
    let known = moving_2d(24).2;
    let mut writer =
        SequenceWriter::create_prepared(prepared, frames.len(), &known, &outputs(dir.path()))
            .unwrap();
    // Frames are drawn while later ones are pushed: the error comes back
    // in frame order, from a push or from finish.
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
fn a_run_dropped_unfinished_writes_every_frame_pushed_on_two_devices() {
    if no_adapter_allowed() {
        return;
    }
    let (settings, mesh, frames) = moving_2d(30);
    let dir = tempfile::tempdir().unwrap();
    let prepared = PreparedRenderers::prepare_with(&settings, &mesh, 2).unwrap();
    let mut writer =
        SequenceWriter::create_prepared(prepared, frames.len(), &frames, &outputs(dir.path()))
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
