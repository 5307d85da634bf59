//! Shared helpers of the renderer tests: small meshes, pixel checks, and the
//! rule for machines without a graphics adapter (the tests fail there unless
//! `ELASTO_ALLOW_NO_GPU=1`, in which case they print a note and pass).
#![allow(dead_code)]

use elasto::render::{Colouring, RenderError, RenderFrame, RenderMesh, RenderSettings, Renderer};

/// Builds a renderer, or returns `None` (after a note) when there is no
/// adapter and `ELASTO_ALLOW_NO_GPU=1` allows skipping.
pub fn renderer_or_skip(
    settings: &RenderSettings,
    mesh: &RenderMesh,
    frames: &[RenderFrame],
) -> Option<Renderer> {
    match Renderer::new(settings, mesh, frames) {
        Ok(renderer) => Some(renderer),
        Err(error) if skip_allowed(&error) => None,
        Err(error) => panic!("cannot create the renderer: {error}"),
    }
}

/// True (after printing a note) when `error` is a missing adapter and
/// `ELASTO_ALLOW_NO_GPU=1` allows skipping.
pub fn skip_allowed(error: &RenderError) -> bool {
    let allowed = matches!(error, RenderError::NoAdapter { .. })
        && std::env::var("ELASTO_ALLOW_NO_GPU").as_deref() == Ok("1");
    if allowed {
        eprintln!("note: skipping, no graphics adapter and ELASTO_ALLOW_NO_GPU=1: {error}");
    }
    allowed
}

/// Whether a test should skip for lack of an adapter.
pub fn no_adapter_allowed() -> bool {
    match elasto::render::adapter_description() {
        Ok(_) => false,
        Err(error) if skip_allowed(&error) => true,
        Err(error) => panic!("no usable graphics adapter: {error}"),
    }
}

/// A unit square from (x, y) made of two triangles (one element each).
pub fn square(x: f32, y: f32, size: f32) -> (RenderMesh, RenderFrame) {
    let mesh = RenderMesh {
        dimension: 2,
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        triangle_element: vec![0, 1],
        edges: vec![[0, 1], [1, 2], [2, 3], [0, 3], [0, 2]],
        element_count: 2,
        obstacle_triangles: Vec::new(),
        obstacle_edges: Vec::new(),
    };
    let frame = RenderFrame {
        positions: vec![
            [x, y, 0.0],
            [x + size, y, 0.0],
            [x + size, y + size, 0.0],
            [x, y + size, 0.0],
        ],
        element_values: vec![0.0, 1.0],
    };
    (mesh, frame)
}

/// Small plain settings: flat colour, no edges, no legend, no ground.
pub fn plain_settings(width: u32, height: u32) -> RenderSettings {
    RenderSettings {
        width,
        height,
        colouring: Colouring::Flat([0.8, 0.1, 0.05]),
        draw_edges: false,
        draw_legend: false,
        ground_height: None,
        ..RenderSettings::default()
    }
}

/// A linear colour as 8-bit sRGB.
pub fn srgb8(linear: [f32; 3]) -> [u8; 3] {
    linear.map(|c| (elasto::render::linear_to_srgb(c) * 255.0).round() as u8)
}

/// Asserts that a pixel has the expected sRGB colour within `tolerance`.
#[track_caller]
pub fn assert_pixel(image: &image::RgbaImage, x: u32, y: u32, expected: [u8; 3], tolerance: u8) {
    let p = image.get_pixel(x, y).0;
    let close = (0..3).all(|c| p[c].abs_diff(expected[c]) <= tolerance);
    assert!(
        close,
        "pixel ({x}, {y}) is {:?}, expected {expected:?} ± {tolerance}",
        &p[..3]
    );
    assert_eq!(p[3], 255, "pixel ({x}, {y}) is not opaque");
}
