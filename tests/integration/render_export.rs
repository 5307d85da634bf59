//! `render_sequence` on real renders: numbered frames, APNG / GIF / MP4
//! videos with the right frame counts, in-order progress, and no complete
//! looking video after a failed run.

use crate::render_support::{no_adapter_allowed, plain_settings, square};
use elasto::render::{RenderFrame, RenderOutputs, RenderSettings, VideoFormat, render_sequence};
use image::AnimationDecoder;
use std::path::Path;

/// `count` frames of a square sliding right.
fn sliding_square(count: usize) -> (elasto::render::RenderMesh, Vec<RenderFrame>) {
    let (mesh, _) = square(0.0, 0.0, 1.0);
    let frames = (0..count)
        .map(|i| square(0.2 * i as f32, 0.0, 1.0).1)
        .collect();
    (mesh, frames)
}

fn outputs(dir: &Path, videos: Vec<VideoFormat>) -> RenderOutputs {
    RenderOutputs {
        frames_dir: dir.join("frames"),
        video_dir: dir.join("video"),
        videos,
        fps: 25.0,
    }
}

fn file_names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn settings() -> RenderSettings {
    RenderSettings {
        draw_edges: true,
        ground_height: Some(-0.2),
        ..plain_settings(64, 48)
    }
}

#[test]
fn frames_are_numbered_from_zero_and_progress_comes_in_order() {
    if no_adapter_allowed() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (mesh, frames) = sliding_square(12);
    let mut seen = Vec::new();
    render_sequence(
        &settings(),
        &mesh,
        &frames,
        &outputs(dir.path(), vec![]),
        &mut |i| seen.push(i),
    )
    .unwrap();
    assert_eq!(seen, (0..12).collect::<Vec<_>>());
    let expected: Vec<String> = (0..12).map(|i| format!("frame_{i:04}.png")).collect();
    assert_eq!(file_names(&dir.path().join("frames")), expected);
    assert!(
        !dir.path().join("video").exists(),
        "no video asked for, no video folder"
    );
    for name in &expected {
        let image = image::open(dir.path().join("frames").join(name)).unwrap();
        assert_eq!((image.width(), image.height()), (64, 48), "{name}");
    }
    // Frames differ: the square moves.
    let first = image::open(dir.path().join("frames/frame_0000.png"))
        .unwrap()
        .to_rgb8();
    let last = image::open(dir.path().join("frames/frame_0011.png"))
        .unwrap()
        .to_rgb8();
    assert!(first != last);
}

#[test]
fn apng_holds_every_frame_with_the_frame_rate_as_delay() {
    if no_adapter_allowed() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (mesh, frames) = sliding_square(7);
    render_sequence(
        &settings(),
        &mesh,
        &frames,
        &outputs(dir.path(), vec![VideoFormat::Apng]),
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(file_names(&dir.path().join("video")), ["video.png"]);

    let file = std::fs::File::open(dir.path().join("video/video.png")).unwrap();
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap();
    let control = reader.info().animation_control.unwrap();
    assert_eq!(control.num_frames, 7);
    assert_eq!(control.num_plays, 0, "loops forever");
    let mut buffer = vec![0; reader.output_buffer_size().unwrap()];
    let mut decoded = 0;
    let mut first_frame = None;
    while let Ok(info) = reader.next_frame(&mut buffer) {
        let fc = reader.info().frame_control.unwrap();
        assert_eq!((fc.delay_num, fc.delay_den), (1, 25));
        // The first frame is whole; later ones may be the rectangle where
        // they differ from the frame before, inside the image.
        assert!(
            fc.x_offset + fc.width <= 64 && fc.y_offset + fc.height <= 48,
            "{fc:?}"
        );
        if decoded == 0 {
            assert_eq!((info.width, info.height), (64, 48));
            first_frame = Some(buffer[..info.buffer_size()].to_vec());
        } else {
            // The square covers a part of the image: so does what changed.
            assert!(
                fc.width * fc.height < 64 * 48 / 2,
                "frame {decoded}: {fc:?}"
            );
        }
        decoded += 1;
    }
    assert_eq!(decoded, 7);
    // The first video frame is the first PNG frame.
    let png_frame = image::open(dir.path().join("frames/frame_0000.png"))
        .unwrap()
        .to_rgb8();
    assert_eq!(first_frame.unwrap(), png_frame.into_raw());
    // Every frame as a player shows it (the rectangles drawn over the frame
    // before) is the whole image of its PNG frame.
    let file = std::fs::File::open(dir.path().join("video/video.png")).unwrap();
    let shown: Vec<image::RgbaImage> =
        image::codecs::png::PngDecoder::new(std::io::BufReader::new(file))
            .unwrap()
            .apng()
            .unwrap()
            .into_frames()
            .map(|frame| frame.unwrap().into_buffer())
            .collect();
    assert_eq!(shown.len(), 7);
    for (i, frame) in shown.iter().enumerate() {
        assert_eq!(frame.dimensions(), (64, 48), "frame {i}");
        let png_frame = image::open(dir.path().join(format!("frames/frame_{i:04}.png")))
            .unwrap()
            .to_rgba8();
        assert!(*frame == png_frame, "APNG frame {i} is not frame {i}");
    }
}

#[test]
fn gif_holds_every_frame() {
    if no_adapter_allowed() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (mesh, frames) = sliding_square(5);
    render_sequence(
        &settings(),
        &mesh,
        &frames,
        &outputs(dir.path(), vec![VideoFormat::Gif]),
        &mut |_| {},
    )
    .unwrap();
    let file = std::fs::File::open(dir.path().join("video/video.gif")).unwrap();
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::RGBA);
    let mut decoder = options.read_info(file).unwrap();
    assert_eq!((decoder.width(), decoder.height()), (64, 48));
    let mut delays = Vec::new();
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        delays.push(frame.delay);
    }
    // 25 frames per second: 4/100 s each.
    assert_eq!(delays, [4, 4, 4, 4, 4]);
}

#[test]
fn mp4_is_written_with_even_dimensions_when_ffmpeg_exists() {
    if std::process::Command::new("ffmpeg")
        .arg("-version")
        .output()
        .is_err()
    {
        eprintln!("note: skipping the mp4 test, ffmpeg is not on PATH (CI installs it)");
        return;
    }
    if no_adapter_allowed() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (mesh, frames) = sliding_square(6);
    // Odd sizes: ffmpeg pads to 66x50 for yuv420p.
    let settings = RenderSettings {
        width: 65,
        height: 49,
        ..settings()
    };
    render_sequence(
        &settings,
        &mesh,
        &frames,
        &outputs(dir.path(), vec![VideoFormat::Mp4]),
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(file_names(&dir.path().join("video")), ["video.mp4"]);
    let path = dir.path().join("video/video.mp4");
    let probe = std::process::Command::new("ffprobe")
        .args([
            "-v",
            "error",
            "-select_streams",
            "v:0",
            "-count_frames",
            "-show_entries",
        ])
        .arg("stream=codec_name,width,height,pix_fmt,nb_read_frames")
        .args(["-of", "default=noprint_wrappers=1"])
        .arg(&path)
        .output()
        .expect("ffprobe comes with ffmpeg");
    let report = String::from_utf8_lossy(&probe.stdout);
    for line in [
        "codec_name=h264",
        "width=66",
        "height=50",
        "pix_fmt=yuv420p",
        "nb_read_frames=6",
    ] {
        assert!(
            report.lines().any(|l| l == line),
            "missing {line} in:\n{report}"
        );
    }
}

#[test]
fn a_failed_run_leaves_no_video_and_names_the_file() {
    if no_adapter_allowed() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (mesh, frames) = sliding_square(8);
    // A folder where frame 3 should go makes that frame's write fail.
    let blocker = dir.path().join("frames/frame_0003.png");
    std::fs::create_dir_all(blocker.join("occupied")).unwrap();
    let mut seen = Vec::new();
    let error = render_sequence(
        &settings(),
        &mesh,
        &frames,
        &outputs(dir.path(), vec![VideoFormat::Apng, VideoFormat::Gif]),
        &mut |i| seen.push(i),
    )
    .unwrap_err();
    assert!(error.to_string().contains("frame_0003.png"), "{error}");
    assert!(
        file_names(&dir.path().join("video")).is_empty(),
        "{:?}",
        file_names(&dir.path().join("video"))
    );
    assert_eq!(
        &seen[..],
        &[0, 1, 2][..seen.len().min(3)],
        "progress stops before the failed frame"
    );
    assert!(seen.len() <= 3);
    // No half-written frame hides under a final name or a temporary one.
    for name in file_names(&dir.path().join("frames")) {
        assert!(!name.ends_with(".partial"), "{name}");
        if name != "frame_0003.png" {
            image::open(dir.path().join("frames").join(&name)).unwrap();
        }
    }
}
