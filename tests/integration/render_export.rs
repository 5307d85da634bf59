//! `render_sequence` on real renders: numbered frames, APNG / GIF / MP4
//! videos with the right frame counts, in-order progress, and no complete
//! looking video after a failed run.

use crate::mp4_file::Mp4File;
use crate::render_support::{no_adapter_allowed, plain_settings, square};
use elasto::encode::{RenderOutputs, VideoFormat, render_sequence};
use elasto::render::{RenderFrame, RenderSettings};
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
fn mp4_is_written_with_even_dimensions_and_one_sample_per_frame() {
    if no_adapter_allowed() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (mesh, frames) = sliding_square(6);
    // Odd sizes: YUV 4:2:0 pads to 66x50.
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
    let mp4 = Mp4File::read(&path).unwrap();
    assert_eq!(mp4.major_brand, "isom");
    assert_eq!(mp4.track_size, (66, 50));
    assert_eq!(mp4.coded_size, (66, 50));
    assert_eq!(mp4.samples.len(), 6);
    // 25 frames per second, exactly.
    assert!(
        mp4.durations.len() == 6
            && mp4
                .durations
                .iter()
                .all(|&d| u64::from(d) * 25 == u64::from(mp4.timescale)),
        "{} ticks per second, durations {:?}",
        mp4.timescale,
        mp4.durations
    );
    // The first frame is a key frame; the SPS is constrained baseline (66).
    assert!(
        mp4.sync_samples
            .as_ref()
            .is_none_or(|s| s.first() == Some(&1)),
        "{:?}",
        mp4.sync_samples
    );
    assert_eq!(mp4.sps[0] & 0x1f, 7, "an SPS");
    assert_eq!(mp4.sps[1], 66, "baseline profile");
    assert_mp4_shows_the_frames(&mp4, &dir.path().join("frames"), (65, 49), 6);

    // The same frames give the same bytes.
    let again = tempfile::tempdir().unwrap();
    render_sequence(
        &settings,
        &mesh,
        &frames,
        &outputs(again.path(), vec![VideoFormat::Mp4]),
        &mut |_| {},
    )
    .unwrap();
    assert!(
        std::fs::read(&path).unwrap()
            == std::fs::read(again.path().join("video/video.mp4")).unwrap(),
        "two runs wrote different MP4s"
    );
}

#[test]
fn mp4_frames_over_the_encoders_limit_are_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, frames) = sliding_square(2);
    let settings = RenderSettings {
        width: 4000,
        height: 100,
        ..settings()
    };
    let error = render_sequence(
        &settings,
        &mesh,
        &frames,
        &outputs(dir.path(), vec![VideoFormat::Apng, VideoFormat::Mp4]),
        &mut |_| {},
    )
    .unwrap_err()
    .to_string();
    assert!(
        error.contains("video.mp4") && error.contains("4000x100") && error.contains("3840x2160"),
        "{error}"
    );
    assert!(!dir.path().join("frames").exists(), "frames were written");
}

/// Decodes the MP4 as a player does (OpenH264's decoder, then BT.709 in
/// limited range back to RGB, as its SPS says) and compares each frame with
/// its PNG file. H.264 and 4:2:0 chroma blur edges (a red pixel next to grey
/// ones loses some red), but keep flat regions' colours; a wrong colour
/// matrix or range shifts those (BT.601 for BT.709 moves the body's red and
/// green by 11 levels, full range for limited puts the mean error at 9
/// levels). Rounding moves them by a level or two: the conversion rounds
/// each code value (the body's red, sRGB (231, 89, 63), is Y, Cb, Cr = 117,
/// 102, 191 for 116.75, 102.29, 191.42), and so does the decoder. A pixel is
/// in a flat region when every pixel within two of it has its colour, within
/// two levels.
fn assert_mp4_shows_the_frames(mp4: &Mp4File, frames: &Path, size: (u32, u32), count: usize) {
    let decoded = mp4.decode_rgb().unwrap();
    let padded = (size.0.next_multiple_of(2), size.1.next_multiple_of(2));
    let frame_bytes = (padded.0 * padded.1 * 3) as usize;
    assert_eq!(decoded.len(), count);
    for (index, pixels) in decoded.iter().enumerate() {
        assert_eq!(pixels.len(), frame_bytes, "frame {index}");
        let png = image::open(frames.join(format!("frame_{index:04}.png")))
            .unwrap()
            .to_rgb8();
        // Per region (body, background): the sum of signed errors per
        // channel, and the pixel count.
        let mut regions = [([0i64; 3], 0i64); 2];
        let mut absolute = 0u64;
        let flat = |x: u32, y: u32| {
            let centre = png.get_pixel(x, y).0;
            let near = |a: u32, d: i32, end: u32| a.checked_add_signed(d).filter(|&a| a < end);
            (-2..=2).all(|dy| {
                (-2..=2).all(|dx| match (near(x, dx, size.0), near(y, dy, size.1)) {
                    (Some(nx), Some(ny)) => {
                        let other = png.get_pixel(nx, ny).0;
                        (0..3).all(|c| other[c].abs_diff(centre[c]) <= 2)
                    }
                    _ => true,
                })
            })
        };
        for (x, y, expected) in png.enumerate_pixels() {
            let at = ((y * padded.0 + x) * 3) as usize;
            let red = expected.0[0] > expected.0[1].saturating_add(60);
            let (sums, pixel_count) = &mut regions[usize::from(!red)];
            let is_flat = flat(x, y);
            for (c, sum) in sums.iter_mut().enumerate() {
                let error = i64::from(pixels[at + c]) - i64::from(expected.0[c]);
                if is_flat {
                    *sum += error;
                }
                absolute += error.unsigned_abs();
            }
            *pixel_count += i64::from(is_flat);
        }
        let mean = absolute as f64 / (3 * size.0 * size.1) as f64;
        assert!(mean < 4.0, "frame {index}: mean error {mean:.2} levels");
        for ((sums, pixel_count), region) in regions.iter().zip(["body", "background"]) {
            assert!(
                *pixel_count > 50,
                "frame {index}: {pixel_count} flat {region} pixels"
            );
            let shift = sums.map(|sum| sum as f64 / *pixel_count as f64);
            assert!(
                shift.iter().all(|s| s.abs() < 4.0),
                "frame {index}: the {region}'s colour is off by {shift:?} levels"
            );
        }
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
