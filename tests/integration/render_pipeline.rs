//! The render pipeline (draw on the calling thread, PNG encoding on worker
//! threads, videos on their own threads, bounded queues between them) keeps
//! frame order and loses nothing: with many tiny frames, each different,
//! every numbered PNG is the frame of its number, the APNG holds them all in
//! order, and the per-frame costs come out once per frame, in order.

use crate::render_support::{renderer_or_skip, square};
use elasto::encode::{FrameCost, RenderOutputs, SequenceWriter, VideoFormat};
use elasto::render::{Camera, Colouring, FRAMES_IN_FLIGHT, RenderFrame, RenderSettings};
use image::AnimationDecoder;
use image::codecs::png::PngDecoder;
use std::io::BufReader;
use std::time::Duration;

const FRAMES: usize = 120;

/// A square sliding right and changing colour: no two frames look alike.
fn run() -> (RenderSettings, elasto::render::RenderMesh, Vec<RenderFrame>) {
    let settings = RenderSettings {
        width: 24,
        height: 16,
        camera: Camera::Orthographic {
            center: [1.5, 0.5],
            height: 2.0,
        },
        colouring: Colouring::Scalar {
            range: Some([0.0, 1.0]),
            label: "value",
        },
        draw_legend: false,
        ..RenderSettings::default()
    };
    let (mesh, _) = square(0.0, 0.0, 1.0);
    let frames = (0..FRAMES)
        .map(|i| {
            let t = i as f32 / (FRAMES - 1) as f32;
            let mut frame = square(2.0 * t, 0.0, 1.0).1;
            frame.element_values = vec![t, 1.0 - t];
            frame
        })
        .collect();
    (settings, mesh, frames)
}

#[test]
fn many_tiny_frames_are_written_complete_and_in_order() {
    let (settings, mesh, frames) = run();
    // Each frame drawn alone, the reference for its file.
    let Some(mut renderer) = renderer_or_skip(&settings, &mesh, &frames) else {
        return;
    };
    let expected: Vec<image::RgbImage> = frames
        .iter()
        .map(|f| image::DynamicImage::from(renderer.render(f).unwrap()).to_rgb8())
        .collect();
    let distinct = expected.windows(2).filter(|w| w[0] != w[1]).count();
    assert!(
        distinct > FRAMES / 2,
        "only {distinct} frames differ from the one before"
    );

    let dir = tempfile::tempdir().unwrap();
    let outputs = RenderOutputs {
        frames_dir: dir.path().join("frames"),
        video_dir: dir.path().to_owned(),
        videos: vec![VideoFormat::Apng],
        fps: 30.0,
    };
    let mut writer =
        SequenceWriter::create(&settings, &mesh, FRAMES, &frames[..1], &outputs).unwrap();
    for (i, frame) in frames.iter().enumerate() {
        writer.push(frame).unwrap();
        // A frame is read back while the next is drawn.
        assert_eq!(
            writer.frames_drawn(),
            (i + 2).saturating_sub(FRAMES_IN_FLIGHT)
        );
    }
    let costs: Vec<FrameCost> = writer.finish_with_costs().unwrap();

    assert_eq!(costs.len(), FRAMES, "one cost per frame");
    for (i, cost) in costs.iter().enumerate() {
        assert!(cost.timings.draw > Duration::ZERO, "frame {i}: {cost:?}");
        assert!(cost.png > Duration::ZERO, "frame {i}: {cost:?}");
        assert!(cost.video > Duration::ZERO, "frame {i}: {cost:?}");
        assert_eq!(cost.encode(), cost.png + cost.video);
    }

    for (i, want) in expected.iter().enumerate() {
        let path = outputs.frames_dir.join(format!("frame_{i:04}.png"));
        let got = image::open(&path).unwrap().to_rgb8();
        assert!(&got == want, "{} is not frame {i}", path.display());
    }
    let names = std::fs::read_dir(&outputs.frames_dir).unwrap().count();
    assert_eq!(names, FRAMES, "no stray or temporary files");

    let file = std::fs::File::open(dir.path().join("video.png")).unwrap();
    let decoder = PngDecoder::new(BufReader::new(file)).unwrap();
    let video: Vec<image::RgbImage> = decoder
        .apng()
        .unwrap()
        .into_frames()
        .map(|f| image::DynamicImage::from(f.unwrap().into_buffer()).to_rgb8())
        .collect();
    assert_eq!(video.len(), FRAMES);
    for (i, (got, want)) in video.iter().zip(&expected).enumerate() {
        assert!(got == want, "APNG frame {i} is not frame {i}");
    }
}
