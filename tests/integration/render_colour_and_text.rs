//! What the renderer draws with on the CPU, through its public functions:
//! the viridis map against matplotlib's samples, the sRGB transfer
//! functions, and text in the embedded font (the legend, the sweep's contact
//! sheet and the study's plot use it).

use elasto::render::{
    draw_text, linear_to_srgb, linear_to_srgb8, srgb_to_linear, text_width, viridis,
};
use image::{Rgba, RgbaImage};

#[test]
fn viridis_ends_and_middle_match_matplotlib() {
    assert_eq!(viridis(0.0), [0.267004, 0.004874, 0.329415]);
    assert_eq!(viridis(1.0), [0.993248, 0.906157, 0.143936]);
    assert_eq!(viridis(2.0), viridis(1.0));
    assert_eq!(viridis(-1.0), viridis(0.0));
    // t = 128/255 lands exactly on sample 128.
    let mid = viridis(128.0 / 255.0);
    for (got, want) in mid.iter().zip([0.127568, 0.566949, 0.550556]) {
        assert!((got - want).abs() < 1e-5, "{mid:?}");
    }
}

#[test]
fn viridis_lightness_increases() {
    // Perceptual uniformity implies monotone luminance.
    let luminance = |c: [f32; 3]| {
        let l = c.map(srgb_to_linear);
        0.2126 * l[0] + 0.7152 * l[1] + 0.0722 * l[2]
    };
    let mut previous = -1.0;
    for i in 0..=100 {
        let y = luminance(viridis(i as f32 / 100.0));
        assert!(y > previous, "luminance drops at t = {}", i as f32 / 100.0);
        previous = y;
    }
}

#[test]
fn srgb_round_trip() {
    for i in 0..=255u8 {
        let c = i as f32 / 255.0;
        let back = linear_to_srgb(srgb_to_linear(c));
        assert!((back - c).abs() < 1e-5, "{i}: {back}");
    }
    assert_eq!(
        linear_to_srgb8([0.0, 1.0, srgb_to_linear(0.5)]),
        [0, 255, 128]
    );
}

#[test]
fn text_darkens_pixels_and_has_a_width() {
    let mut image = RgbaImage::from_pixel(120, 20, Rgba([255, 255, 255, 255]));
    draw_text(&mut image, "young=300", 2.0, 15.0, 14.0, [0, 0, 0]);
    let dark: Vec<u32> = image
        .enumerate_pixels()
        .filter(|(_, _, p)| p.0[0] < 128)
        .map(|(x, _, _)| x)
        .collect();
    assert!(dark.len() > 30, "{} dark pixels", dark.len());
    // The ink lies within the advance width the layout gives, from the caret.
    let width = text_width("young=300", 14.0);
    let (left, right) = (dark.iter().min().unwrap(), dark.iter().max().unwrap());
    assert!(
        *left >= 2 && (*right as f32) < 2.0 + width,
        "{left}..{right} vs {width}"
    );
    assert!(*right as f32 > 2.0 + 0.8 * width, "{right} vs {width}");
    let wide = text_width("material.young=300", 12.0);
    assert!(wide > 60.0 && wide < 160.0, "{wide}");
    assert!(text_width("ab", 12.0) < text_width("abc", 12.0));
    assert_eq!(text_width("", 12.0), 0.0);
}
