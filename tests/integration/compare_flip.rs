//! FLIP comparison: the default thresholds on render-like frames, and
//! `compare_directories` on real PNG files.

use std::path::Path;

use elasto::compare::{
    CompareError, CompareThresholds, FrameOutcome, compare_directories, compare_images, read_rgba,
};
use image::{ImageFormat, Rgba, RgbaImage};

/// A body drawn like the renderer draws one: a rotated rectangle of flat
/// coloured cells with dark edges over a light background and a grey ground.
#[derive(Clone, Copy)]
struct Body {
    /// Centre, in pixels.
    center: [f32; 2],
    /// Half width and half height, in pixels.
    half: [f32; 2],
    /// Rotation, in radians.
    angle: f32,
}

impl Body {
    fn new(half_width: f32, half_height: f32) -> Self {
        Self {
            center: [160.0, 110.0],
            half: [half_width, half_height],
            angle: 0.3,
        }
    }

    fn shifted(self, dx: f32, dy: f32) -> Self {
        Self {
            center: [self.center[0] + dx, self.center[1] + dy],
            ..self
        }
    }
}

/// The colour at a point: background, ground, cell or edge.
fn shade(body: &Body, height: u32, x: f32, y: f32) -> [f32; 3] {
    let (s, c) = body.angle.sin_cos();
    let (dx, dy) = (x - body.center[0], y - body.center[1]);
    let (u, v) = (c * dx + s * dy, -s * dx + c * dy);
    let [hw, hh] = body.half;
    if u.abs() < hw && v.abs() < hh {
        let cell = 10.0;
        let (cu, cv) = ((u + hw) / cell, (v + hh) / cell);
        let on_edge = |t: f32| t.fract() < 0.08 || t.fract() > 0.92;
        if hw - u.abs() < 0.8 || hh - v.abs() < 0.8 || on_edge(cu) || on_edge(cv) {
            return [30.0, 32.0, 40.0];
        }
        let k = (cu.floor() + 2.0 * cv.floor()) % 5.0;
        return [60.0 + 30.0 * k, 120.0 + 20.0 * k, 140.0 - 15.0 * k];
    }
    if y > height as f32 * 0.85 {
        [90.0, 90.0, 95.0]
    } else {
        [235.0, 238.0, 242.0]
    }
}

/// Renders `body` at `width`×`height` with 4×4 supersampling; `rotated_grid`
/// picks another sample pattern, as another rasteriser's MSAA would.
fn draw(body: Body, width: u32, height: u32, rotated_grid: bool) -> RgbaImage {
    let scale_x = width as f32 / 320.0;
    let scale_y = height as f32 / 240.0;
    let body = Body {
        center: [body.center[0] * scale_x, body.center[1] * scale_y],
        half: [body.half[0] * scale_x, body.half[1] * scale_y],
        ..body
    };
    RgbaImage::from_fn(width, height, |x, y| {
        let mut sum = [0.0f32; 3];
        for sy in 0..4u32 {
            for sx in 0..4u32 {
                let (ox, oy) = if rotated_grid {
                    ((sx + 2 * sy) % 4, (sy + 2 * sx + 1) % 4)
                } else {
                    (sx, sy)
                };
                let px = x as f32 + (ox as f32 + 0.5) / 4.0;
                let py = y as f32 + (oy as f32 + 0.5) / 4.0;
                let c = shade(&body, height, px, py);
                for (acc, v) in sum.iter_mut().zip(c) {
                    *acc += v;
                }
            }
        }
        let [r, g, b] = sum.map(|v| (v / 16.0).round() as u8);
        Rgba([r, g, b, 255])
    })
}

fn frame(body: Body) -> RgbaImage {
    draw(body, 320, 240, false)
}

/// Every channel moved by up to `amplitude` levels in a fixed pattern, like
/// rounding differences between drivers.
fn rounding_noise(image: &RgbaImage, amplitude: u32) -> RgbaImage {
    RgbaImage::from_fn(image.width(), image.height(), |x, y| {
        let p = image.get_pixel(x, y).0;
        let d = ((x * 7 + y * 13) % (2 * amplitude + 1)) as i16 - amplitude as i16;
        let nudge = |c: u8, d: i16| (i16::from(c) + d).clamp(0, 255) as u8;
        Rgba([nudge(p[0], d), nudge(p[1], -d), nudge(p[2], d), 255])
    })
}

mod thresholds {
    use super::*;

    #[test]
    fn identical_frames_have_zero_error() {
        let golden = frame(Body::new(40.0, 10.0));
        let c = compare_images(&golden, &golden.clone(), &CompareThresholds::default()).unwrap();
        assert_eq!((c.mean, c.percentile_value, c.max), (0.0, 0.0, 0.0));
        assert!(c.passed);
        assert_eq!(c.error_map.dimensions(), (320, 240));
    }

    #[test]
    fn rasteriser_noise_passes_the_defaults() {
        let t = CompareThresholds::default();
        for body in [
            Body::new(10.0, 5.0),
            Body::new(40.0, 10.0),
            Body::new(100.0, 50.0),
        ] {
            let golden = frame(body);
            let noisy = compare_images(&golden, &rounding_noise(&golden, 1), &t).unwrap();
            assert!(noisy.passed, "rounding noise failed: {noisy:?}");
            assert!(noisy.mean > 0.0 && noisy.mean < 0.003, "{noisy:?}");
            assert!(noisy.percentile_value < 0.015, "{noisy:?}");

            let noisier = compare_images(&golden, &rounding_noise(&golden, 2), &t).unwrap();
            assert!(noisier.passed, "rounding noise ±2 failed: {noisier:?}");
            assert!(
                noisier.mean < 0.015 && noisier.percentile_value < 0.04,
                "{noisier:?}"
            );

            let msaa = compare_images(&golden, &draw(body, 320, 240, true), &t).unwrap();
            assert!(msaa.passed, "sample pattern failed: {msaa:?}");
            assert!(msaa.mean < 1e-4 && msaa.percentile_value < 0.01, "{msaa:?}");
        }
    }

    #[test]
    fn a_body_shifted_by_a_few_pixels_fails_the_defaults() {
        let t = CompareThresholds::default();
        for body in [
            Body::new(10.0, 5.0),
            Body::new(40.0, 10.0),
            Body::new(100.0, 50.0),
        ] {
            let golden = frame(body);
            for (dx, dy) in [
                (1.0, 0.0),
                (0.0, -1.0),
                (2.0, 0.0),
                (4.0, 0.0),
                (0.0, 4.0),
                (-4.0, 3.0),
            ] {
                let c = compare_images(&golden, &frame(body.shifted(dx, dy)), &t).unwrap();
                assert!(
                    !c.passed,
                    "shift ({dx}, {dy}) of {:?} passed: {c:?}",
                    body.half
                );
                assert!(c.percentile_value > 2.0 * t.percentile_value, "{c:?}");
            }
        }
    }

    #[test]
    fn the_mean_fails_a_large_body_shifted() {
        let t = CompareThresholds::default();
        let body = Body::new(100.0, 50.0);
        let c = compare_images(&frame(body), &frame(body.shifted(4.0, 0.0)), &t).unwrap();
        assert!(c.mean > 5.0 * t.mean, "mean {}", c.mean);
    }

    /// Why the 99.9th and not the 99th percentile: under 1% of the pixels
    /// change when a small body moves.
    #[test]
    fn the_99th_percentile_would_miss_a_small_body() {
        let body = Body::new(10.0, 5.0);
        let (golden, moved) = (frame(body), frame(body.shifted(4.0, 0.0)));
        let p99 = CompareThresholds {
            percentile: 0.99,
            ..CompareThresholds::default()
        };
        let c99 = compare_images(&golden, &moved, &p99).unwrap();
        assert!(c99.passed, "{c99:?}");
        let c = compare_images(&golden, &moved, &CompareThresholds::default()).unwrap();
        assert!(!c.passed);
        assert!(c.percentile_value > c99.percentile_value);
    }

    #[test]
    fn the_diff_image_is_bright_where_the_body_moved() {
        let body = Body::new(40.0, 10.0);
        let c = compare_images(
            &frame(body),
            &frame(body.shifted(4.0, 0.0)),
            &CompareThresholds::default(),
        )
        .unwrap();
        let diff = c.diff_image();
        assert_eq!(diff.dimensions(), (320, 240));
        let brightness = |x: u32, y: u32| {
            diff.get_pixel(x, y)
                .0
                .iter()
                .map(|&v| u32::from(v))
                .sum::<u32>()
        };
        // The magma colour of zero error is near black; the body's right end
        // around (198, 122) changed.
        assert!(brightness(5, 5) < 30, "corner {:?}", diff.get_pixel(5, 5));
        let brightest = (190..206)
            .flat_map(|x| (100..140).map(move |y| (x, y)))
            .map(|(x, y)| brightness(x, y))
            .max()
            .unwrap();
        assert!(brightest > 300, "brightest {brightest}");
        let max_at = c
            .error_map
            .enumerate_pixels()
            .max_by(|a, b| a.2.0[0].total_cmp(&b.2.0[0]))
            .unwrap();
        assert!((max_at.2.0[0] - c.max).abs() < 1e-6);
        assert!(c.max > 0.5 && c.max <= 1.0);
    }

    #[test]
    fn images_of_different_sizes_are_an_error() {
        let err = compare_images(
            &RgbaImage::new(32, 24),
            &RgbaImage::new(24, 32),
            &CompareThresholds::default(),
        )
        .unwrap_err();
        assert!(matches!(
            err,
            CompareError::SizeMismatch {
                golden: (32, 24),
                actual: (24, 32)
            }
        ));
        assert!(err.to_string().contains("32x24"), "{err}");
    }

    #[test]
    fn thresholds_out_of_range_are_rejected() {
        let d = CompareThresholds::default();
        d.validate().unwrap();
        let cases = [
            (CompareThresholds { mean: 1.5, ..d }, "mean"),
            (CompareThresholds { mean: -0.1, ..d }, "mean"),
            (
                CompareThresholds {
                    percentile_value: f32::NAN,
                    ..d
                },
                "percentile_value",
            ),
            (
                CompareThresholds {
                    percentile: 1.0,
                    ..d
                },
                "percentile",
            ),
            (
                CompareThresholds {
                    percentile: 0.0,
                    ..d
                },
                "percentile",
            ),
            (
                CompareThresholds {
                    percentile: 99.0,
                    ..d
                },
                "percentile",
            ),
        ];
        for (t, expected) in cases {
            match t.validate() {
                Err(CompareError::InvalidThreshold { key, .. }) => assert_eq!(key, expected),
                other => panic!("{t:?}: {other:?}"),
            }
        }
        let msg = CompareThresholds {
            percentile: 99.0,
            ..d
        }
        .validate()
        .unwrap_err()
        .to_string();
        assert!(msg.contains("percentile = 99"), "{msg}");
    }

    #[test]
    fn percentile_labels() {
        let label = |percentile| {
            CompareThresholds {
                percentile,
                ..Default::default()
            }
            .percentile_label()
        };
        assert_eq!(label(0.99), "p99");
        assert_eq!(label(0.995), "p99.5");
        assert_eq!(label(0.999), "p99.9");
        assert_eq!(label(0.5), "p50");
    }
}

mod directories {
    use super::*;

    const W: u32 = 160;
    const H: u32 = 120;

    fn save(dir: &Path, name: &str, image: &RgbaImage) {
        std::fs::create_dir_all(dir).unwrap();
        image
            .save_with_format(dir.join(name), ImageFormat::Png)
            .unwrap();
    }

    fn small(body: Body) -> RgbaImage {
        draw(body, W, H, false)
    }

    /// golden/ and frames/ with frame_0000..0002 identical.
    fn identical_dirs() -> (tempfile::TempDir, std::path::PathBuf, std::path::PathBuf) {
        let tmp = tempfile::tempdir().unwrap();
        let golden = tmp.path().join("golden");
        let frames = tmp.path().join("frames");
        for i in 0..3 {
            let img = small(Body::new(40.0, 10.0).shifted(0.0, 10.0 * i as f32));
            save(&golden, &format!("frame_{i:04}.png"), &img);
            save(&frames, &format!("frame_{i:04}.png"), &img);
        }
        (tmp, golden, frames)
    }

    #[test]
    fn identical_frames_pass_and_write_diffs_and_copies() {
        let (tmp, golden, frames) = identical_dirs();
        // Extra frames without a golden image, and other files, are ignored.
        save(&frames, "frame_0099.png", &small(Body::new(5.0, 5.0)));
        std::fs::write(golden.join("notes.txt"), "not an image").unwrap();
        let diff = tmp.path().join("out/diff");

        let t = CompareThresholds::default();
        let report = compare_directories(&golden, &frames, &diff, &t).unwrap();
        assert!(report.all_passed(), "{}", report.table());
        let names: Vec<&str> = report.frames.iter().map(|f| f.name.as_str()).collect();
        assert_eq!(
            names,
            ["frame_0000.png", "frame_0001.png", "frame_0002.png"]
        );
        assert_eq!(report.thresholds, t);
        for f in &report.frames {
            assert_eq!(f.outcome, FrameOutcome::Pass);
            assert_eq!((f.mean, f.percentile_value), (Some(0.0), Some(0.0)));
            let diff_path = f.diff_image.as_ref().unwrap();
            assert_eq!(diff_path, &diff.join(&f.name));
            let diff_image = read_rgba(diff_path).unwrap();
            assert_eq!(diff_image.dimensions(), (W, H));
            let actual = f.actual_image.as_ref().unwrap();
            assert_eq!(actual, &diff.join(f.name.replace(".png", ".actual.png")));
            assert_eq!(
                std::fs::read(actual).unwrap(),
                std::fs::read(frames.join(&f.name)).unwrap()
            );
        }
        // Zero error everywhere: the diff image is one colour (magma at 0).
        let d = read_rgba(&diff.join("frame_0001.png")).unwrap();
        let first = *d.get_pixel(0, 0);
        assert!(d.pixels().all(|p| *p == first));
        assert!(!diff.join("frame_0099.png").exists());

        let table = report.table();
        assert!(table.contains("mean <= 0.02, p99.9 <= 0.1"), "{table}");
        assert!(table.contains("all 3 frames passed"), "{table}");
        let row = table
            .lines()
            .find(|l| l.starts_with("frame_0002.png"))
            .unwrap();
        assert!(row.contains("0.000000") && row.ends_with("pass"), "{row}");
    }

    #[test]
    fn a_shape_shifted_by_4_pixels_fails() {
        let (tmp, golden, frames) = identical_dirs();
        let moved = small(Body::new(40.0, 10.0).shifted(8.0, 10.0)); // 4 px at 160x120
        save(&frames, "frame_0001.png", &moved);
        let diff = tmp.path().join("diff");

        let report =
            compare_directories(&golden, &frames, &diff, &CompareThresholds::default()).unwrap();
        assert!(!report.all_passed());
        let outcomes: Vec<_> = report.frames.iter().map(|f| f.outcome.clone()).collect();
        assert_eq!(
            outcomes,
            [FrameOutcome::Pass, FrameOutcome::Fail, FrameOutcome::Pass]
        );
        let failed = &report.frames[1];
        assert!(failed.percentile_value.unwrap() > 0.3, "{failed:?}");
        assert!(failed.mean.unwrap() > 0.0);
        let failures: Vec<_> = report.failures().map(|f| f.name.as_str()).collect();
        assert_eq!(failures, ["frame_0001.png"]);

        // The diff image shows the error: not one flat colour.
        let d = read_rgba(failed.diff_image.as_ref().unwrap()).unwrap();
        let first = *d.get_pixel(0, 0);
        assert!(d.pixels().any(|p| *p != first));
        assert_eq!(
            read_rgba(&diff.join("frame_0001.actual.png")).unwrap(),
            moved
        );

        let table = report.table();
        let row = table
            .lines()
            .find(|l| l.starts_with("frame_0001.png"))
            .unwrap();
        // The verdict names the figure over its limit.
        assert!(row.contains("FAIL ("), "{row}");
        assert!(row.contains("p99.9 0.") && row.contains(" > 0.1"), "{row}");
        assert!(table.contains("1 of 3 frames failed"), "{table}");
    }

    #[test]
    fn a_missing_frame_is_reported() {
        let (tmp, golden, frames) = identical_dirs();
        std::fs::remove_file(frames.join("frame_0002.png")).unwrap();
        let diff = tmp.path().join("diff");
        let report =
            compare_directories(&golden, &frames, &diff, &CompareThresholds::default()).unwrap();
        assert!(!report.all_passed());
        let missing = &report.frames[2];
        assert_eq!(missing.outcome, FrameOutcome::Missing);
        assert_eq!((missing.mean, missing.diff_image.as_ref()), (None, None));
        assert!(!diff.join("frame_0002.png").exists());
        let row = report
            .table()
            .lines()
            .find(|l| l.starts_with("frame_0002.png"))
            .unwrap()
            .to_owned();
        assert!(row.ends_with("MISSING") && row.contains(" - "), "{row}");
    }

    #[test]
    fn a_size_mismatch_is_reported() {
        let (tmp, golden, frames) = identical_dirs();
        save(
            &frames,
            "frame_0000.png",
            &draw(Body::new(40.0, 10.0), 2 * W, 2 * H, false),
        );
        let diff = tmp.path().join("diff");
        let report =
            compare_directories(&golden, &frames, &diff, &CompareThresholds::default()).unwrap();
        assert_eq!(
            report.frames[0].outcome,
            FrameOutcome::SizeMismatch {
                golden: (W, H),
                actual: (2 * W, 2 * H)
            }
        );
        assert_eq!(report.frames[0].diff_image, None);
        assert!(diff.join("frame_0000.actual.png").is_file());
        assert_eq!(report.frames[1].outcome, FrameOutcome::Pass);
        assert!(
            report
                .table()
                .contains("SIZE MISMATCH (golden 160x120, actual 320x240)")
        );
    }

    #[test]
    fn greyscale_and_16_bit_pngs_compare_as_colour() {
        let tmp = tempfile::tempdir().unwrap();
        let (golden, frames) = (tmp.path().join("g"), tmp.path().join("f"));
        let rgba = small(Body::new(30.0, 10.0));
        let grey = image::DynamicImage::ImageRgba8(rgba).to_luma8();
        std::fs::create_dir_all(&golden).unwrap();
        grey.save_with_format(golden.join("a.png"), ImageFormat::Png)
            .unwrap();
        let wide = image::DynamicImage::ImageLuma8(grey.clone()).to_rgba16();
        std::fs::create_dir_all(&frames).unwrap();
        wide.save_with_format(frames.join("a.png"), ImageFormat::Png)
            .unwrap();
        let report = compare_directories(
            &golden,
            &frames,
            &tmp.path().join("d"),
            &CompareThresholds::default(),
        )
        .unwrap();
        assert_eq!(report.frames[0].mean, Some(0.0));
        assert!(report.all_passed());
    }

    #[test]
    fn a_golden_folder_without_pngs_is_an_error() {
        let tmp = tempfile::tempdir().unwrap();
        let golden = tmp.path().join("golden");
        std::fs::create_dir_all(&golden).unwrap();
        std::fs::write(golden.join("README.md"), "no images").unwrap();
        let err = compare_directories(
            &golden,
            tmp.path(),
            &tmp.path().join("d"),
            &CompareThresholds::default(),
        )
        .unwrap_err();
        assert!(matches!(err, CompareError::NoGoldenImages { ref path } if *path == golden));
        assert!(
            err.to_string().contains(&golden.display().to_string()),
            "{err}"
        );
        assert!(err.to_string().contains("no *.png"), "{err}");
    }

    #[test]
    fn absent_folders_are_errors_naming_them() {
        let (tmp, golden, frames) = identical_dirs();
        let nowhere = tmp.path().join("nowhere");
        let t = CompareThresholds::default();

        let err = compare_directories(&nowhere, &frames, &tmp.path().join("d"), &t).unwrap_err();
        assert!(
            matches!(err, CompareError::ReadDir { role: "golden", .. }),
            "{err:?}"
        );
        assert!(
            err.to_string().contains("golden folder") && err.to_string().contains("nowhere"),
            "{err}"
        );

        let err = compare_directories(&golden, &nowhere, &tmp.path().join("d"), &t).unwrap_err();
        assert!(
            matches!(err, CompareError::ReadDir { role: "frames", .. }),
            "{err:?}"
        );
        assert!(err.to_string().contains("frames folder"), "{err}");
    }

    #[test]
    fn an_unreadable_image_is_an_error_naming_it() {
        let (tmp, golden, frames) = identical_dirs();
        std::fs::write(golden.join("frame_0001.png"), b"not a png at all").unwrap();
        let err = compare_directories(
            &golden,
            &frames,
            &tmp.path().join("d"),
            &CompareThresholds::default(),
        )
        .unwrap_err();
        let bad = golden.join("frame_0001.png");
        assert!(
            matches!(err, CompareError::ReadImage { ref path, .. } if *path == bad),
            "{err:?}"
        );
        assert!(
            err.to_string().contains(&bad.display().to_string()),
            "{err}"
        );

        // The same for a broken frame on the actual side.
        let (tmp, golden, frames) = identical_dirs();
        std::fs::write(
            frames.join("frame_0002.png"),
            b"\x89PNG\r\n\x1a\n truncated",
        )
        .unwrap();
        let err = compare_directories(
            &golden,
            &frames,
            &tmp.path().join("d"),
            &CompareThresholds::default(),
        )
        .unwrap_err();
        assert!(err.to_string().contains("frame_0002.png"), "{err}");
    }

    #[test]
    fn the_diff_folder_may_not_be_an_input_folder() {
        let (_tmp, golden, frames) = identical_dirs();
        let t = CompareThresholds::default();
        for (diff, role) in [(&frames, "frames"), (&golden, "golden")] {
            let err = compare_directories(&golden, &frames, diff, &t).unwrap_err();
            assert!(
                matches!(err, CompareError::DiffDirOverlap { role: r, .. } if r == role),
                "{err:?}"
            );
        }
        // Nothing was overwritten.
        let report = compare_directories(&golden, &frames, &frames.join("diff"), &t).unwrap();
        assert!(report.all_passed());
    }

    #[test]
    fn invalid_thresholds_are_rejected_before_reading() {
        let tmp = tempfile::tempdir().unwrap();
        let t = CompareThresholds {
            mean: 2.0,
            ..Default::default()
        };
        let err =
            compare_directories(tmp.path(), tmp.path(), &tmp.path().join("d"), &t).unwrap_err();
        assert!(
            matches!(err, CompareError::InvalidThreshold { key: "mean", .. }),
            "{err:?}"
        );
    }

    #[test]
    fn looser_thresholds_accept_the_shift() {
        let (tmp, golden, frames) = identical_dirs();
        save(
            &frames,
            "frame_0001.png",
            &small(Body::new(40.0, 10.0).shifted(8.0, 10.0)),
        );
        let loose = CompareThresholds {
            mean: 1.0,
            percentile_value: 1.0,
            percentile: 0.99,
        };
        let report = compare_directories(&golden, &frames, &tmp.path().join("d"), &loose).unwrap();
        assert!(report.all_passed(), "{}", report.table());
        assert!(report.table().contains("p99 <= 1"), "{}", report.table());
    }
}
