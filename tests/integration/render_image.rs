//! Real renders on the machine's adapter (llvmpipe on CI): pixels land where
//! the positions say, colours follow the fixed viridis range, the readback
//! strips row padding, and rendering is deterministic.

use crate::render_support::{assert_pixel, plain_settings, renderer_or_skip, square, srgb8};
use elasto::render::{
    Camera, Colouring, RenderError, RenderFrame, RenderMesh, RenderSettings, Renderer, viridis,
};

/// 40 pixels per scene unit, origin at the image centre (80, 60).
fn pixel_camera() -> Camera {
    Camera::Orthographic {
        center: [0.0, 0.0],
        height: 3.0,
    }
}

#[test]
fn flat_square_covers_the_pixels_its_positions_say_and_moves_with_them() {
    let settings = RenderSettings {
        camera: pixel_camera(),
        ..plain_settings(160, 120)
    };
    let body = srgb8([0.8, 0.1, 0.05]);
    let background = srgb8(settings.background);
    let (mesh, centred) = square(-0.5, -0.5, 1.0);
    let (_, shifted) = square(0.5, 0.25, 1.0);
    let Some(mut renderer) =
        renderer_or_skip(&settings, &mesh, &[centred.clone(), shifted.clone()])
    else {
        return;
    };

    let image = renderer.render(&centred).unwrap();
    assert_eq!(image.dimensions(), (160, 120));
    assert_pixel(&image, 80, 60, body, 1);
    // The square spans pixels 60..100 across and 40..80 down.
    assert_pixel(&image, 61, 41, body, 1);
    assert_pixel(&image, 98, 78, body, 1);
    assert_pixel(&image, 58, 60, background, 1);
    assert_pixel(&image, 101, 60, background, 1);
    assert_pixel(&image, 80, 38, background, 1);
    assert_pixel(&image, 10, 10, background, 1);

    // Moved by (+1, +0.75): 40 pixels right and 30 pixels up (y points up).
    let image = renderer.render(&shifted).unwrap();
    assert_pixel(&image, 80, 60, background, 1);
    assert_pixel(&image, 120, 30, body, 1);
    assert_pixel(&image, 101, 11, body, 1);
    assert_pixel(&image, 138, 48, body, 1);
    assert_pixel(&image, 120, 52, background, 1);
}

/// A 2D body is drawn with one sample per pixel and anti-aliased by the
/// share of each pixel it covers (a box filter): an edge pixel of an
/// axis-aligned body is the body's colour over exactly the covered
/// fraction, blended in linear light. Four samples would round each share
/// to a quarter (0.7 to 0.75, 0.6 to 0.5), many levels away.
#[test]
fn a_2d_edge_pixel_shows_the_share_of_it_the_body_covers() {
    let settings = RenderSettings {
        camera: pixel_camera(),
        ..plain_settings(160, 120)
    };
    // Pixel x = 80 + 40 x, y = 60 - 40 y: edges at x = 60.3 and 100.7,
    // y = 39.2 (top) and 79.6 (bottom).
    let (mesh, frame) = square(-19.7 / 40.0, -19.6 / 40.0, 40.4 / 40.0);
    let Some(mut renderer) = renderer_or_skip(&settings, &mesh, std::slice::from_ref(&frame))
    else {
        return;
    };
    let image = renderer.render(&frame).unwrap();
    let body = [0.8f32, 0.1, 0.05];
    let background = settings.background;
    let covered = |share: f32| {
        srgb8(std::array::from_fn(|c| {
            share * body[c] + (1.0 - share) * background[c]
        }))
    };
    let (x_left, x_right, y_top, y_bottom) = (60, 100, 39, 79);
    for (x, y, share) in [
        (x_left, 60, 0.7),
        (x_right, 60, 0.7),
        (80, y_top, 0.8),
        (80, y_bottom, 0.6),
        (x_left, y_top, 0.7 * 0.8),
        (x_right, y_bottom, 0.7 * 0.6),
        (x_left - 1, 60, 0.0),
        (80, y_bottom + 1, 0.0),
        (x_left + 1, 60, 1.0),
    ] {
        assert_pixel(&image, x, y, covered(share), 1);
    }
}

#[test]
fn element_with_the_maximum_gets_the_top_of_viridis() {
    let settings = RenderSettings {
        camera: pixel_camera(),
        colouring: Colouring::Scalar {
            range: None,
            label: "value",
        },
        ..plain_settings(160, 120)
    };
    // Element 0 is the lower-right triangle, element 1 the upper-left one.
    let (mesh, mut frame) = square(-0.5, -0.5, 1.0);
    frame.element_values = vec![-2.0, 6.0];
    let Some(mut renderer) = renderer_or_skip(&settings, &mesh, std::slice::from_ref(&frame))
    else {
        return;
    };
    assert_eq!(renderer.colour_range(), [-2.0, 6.0]);
    let image = renderer.render(&frame).unwrap();
    let to8 = |c: [f32; 3]| c.map(|v| (v * 255.0).round() as u8);
    assert_pixel(&image, 70, 50, to8(viridis(1.0)), 1);
    assert_pixel(&image, 90, 70, to8(viridis(0.0)), 1);
}

#[test]
fn automatic_range_spans_the_whole_run() {
    let settings = RenderSettings {
        camera: pixel_camera(),
        colouring: Colouring::Scalar {
            range: None,
            label: "value",
        },
        ..plain_settings(160, 120)
    };
    let (mesh, mut early) = square(-0.5, -0.5, 1.0);
    early.element_values = vec![0.0, 1.0];
    let mut late = early.clone();
    late.element_values = vec![0.0, 4.0];
    let Some(mut renderer) = renderer_or_skip(&settings, &mesh, &[early.clone(), late]) else {
        return;
    };
    let image = renderer.render(&early).unwrap();
    // 1 on a run-wide range [0, 4] is a quarter up the map, not its top.
    let to8 = |c: [f32; 3]| c.map(|v| (v * 255.0).round() as u8);
    assert_pixel(&image, 70, 50, to8(viridis(0.25)), 1);
}

#[test]
fn readback_strips_row_padding_at_an_odd_width() {
    // 100 * 4 = 400 bytes a row, padded to 512 by the copy.
    let settings = RenderSettings {
        camera: Camera::Orthographic {
            center: [0.0, 0.0],
            height: 2.0,
        },
        ..plain_settings(100, 60)
    };
    let body = srgb8([0.8, 0.1, 0.05]);
    let background = srgb8(settings.background);
    // The left half of the view, top to bottom: x in [-10, 0].
    let (mesh, mut frame) = square(-10.0, -10.0, 20.0);
    for p in &mut frame.positions {
        p[0] = p[0].min(0.0);
    }
    let Some(mut renderer) = renderer_or_skip(&settings, &mesh, std::slice::from_ref(&frame))
    else {
        return;
    };
    let image = renderer.render(&frame).unwrap();
    assert_eq!(image.dimensions(), (100, 60));
    assert_eq!(image.as_raw().len(), 100 * 60 * 4);
    for y in 0..60 {
        // A wrong row stride would shear the edge from row to row.
        assert_pixel(&image, 0, y, body, 1);
        assert_pixel(&image, 49, y, body, 1);
        assert_pixel(&image, 50, y, background, 1);
        assert_pixel(&image, 99, y, background, 1);
    }
}

#[test]
fn the_same_frame_renders_to_the_same_bytes() {
    let settings = RenderSettings {
        colouring: Colouring::Scalar {
            range: None,
            label: "energy",
        },
        ground_height: Some(-0.7),
        draw_edges: true,
        draw_legend: true,
        ..plain_settings(320, 240)
    };
    let (mesh, frame) = square(-0.5, -0.5, 1.0);
    let Some(mut renderer) = renderer_or_skip(&settings, &mesh, std::slice::from_ref(&frame))
    else {
        return;
    };
    let first = renderer.render(&frame).unwrap();
    let second = renderer.render(&frame).unwrap();
    assert!(first == second, "two renders of one frame differ");
}

/// A frame is drawn in a tile around its body, not over the whole image:
/// the backdrop (drawn in strips) lets its target go, a small body's frame
/// makes a small one, and only a whole-image reference grows it.
#[test]
fn a_frame_draws_a_tile_around_its_body_not_the_whole_image() {
    use elasto::math::Vector3;
    use elasto::mesh::Mesh;
    let (square_mesh, square_frame) = square(-0.2, -0.2, 0.4);
    let box_mesh = Mesh::<3>::axis_aligned_box(
        Vector3::new(-0.1, 0.0, -0.1),
        Vector3::new(0.1, 0.2, 0.1),
        [1, 1, 1],
    )
    .unwrap();
    let box_frame = RenderFrame::from_positions(
        box_mesh.rest_positions(),
        &vec![0.0; box_mesh.element_count()],
    );
    let (width, height) = (320, 240);
    for (mesh, frame, camera) in [
        (square_mesh, square_frame, pixel_camera()),
        (
            RenderMesh::from_mesh(&box_mesh),
            box_frame,
            Camera::Perspective {
                eye: [0.0, 1.0, 3.0],
                target: [0.0, 0.1, 0.0],
                fov_degrees: 40.0,
            },
        ),
    ] {
        let settings = RenderSettings {
            camera,
            ground_height: Some(0.0),
            ..plain_settings(width, height)
        };
        let d = mesh.dimension;
        let Some(mut renderer) = renderer_or_skip(&settings, &mesh, std::slice::from_ref(&frame))
        else {
            return;
        };
        assert_eq!(
            renderer.tile_capacity(),
            None,
            "{d}D: the backdrop's target is let go"
        );
        let tile = renderer.render(&frame).unwrap();
        let (w, h) = renderer.tile_capacity().unwrap();
        assert!(
            w < width && h < height,
            "{d}D: a {w}x{h} tile for a small body"
        );
        assert!(renderer.render(&frame).unwrap() == tile, "{d}D");
        // (A larger target moves positions by rounding errors: compared last.)
        let whole = renderer.render_whole_image(&frame).unwrap();
        assert_eq!(renderer.tile_capacity(), Some((width, height)), "{d}D");
        assert_eq!(tile.dimensions(), whole.dimensions());
        let centre = |image: &image::RgbaImage| image.get_pixel(width / 2, height / 2).0;
        assert_eq!(centre(&tile), centre(&whole), "{d}D");
    }
}

#[test]
fn three_d_box_is_framed_lit_and_standing_on_the_ground() {
    use elasto::math::Vector3;
    use elasto::mesh::Mesh;
    let mesh = Mesh::<3>::axis_aligned_box(
        Vector3::new(-0.5, 0.0, -0.5),
        Vector3::new(0.5, 1.0, 0.5),
        [2, 2, 2],
    )
    .unwrap();
    let view = RenderMesh::from_mesh(&mesh);
    let frame =
        RenderFrame::from_positions(mesh.rest_positions(), &vec![0.0; mesh.element_count()]);
    let settings = RenderSettings {
        colouring: Colouring::Flat([0.7, 0.05, 0.02]),
        ground_height: Some(0.0),
        ..plain_settings(320, 240)
    };
    let Some(mut renderer) = renderer_or_skip(&settings, &view, std::slice::from_ref(&frame))
    else {
        return;
    };
    let image = renderer.render(&frame).unwrap();
    let red = |x: u32, y: u32| {
        let p = image.get_pixel(x, y).0;
        p[0] as i32 > p[1] as i32 + 60 && p[0] as i32 > p[2] as i32 + 60
    };
    // The body fills the middle; the corners show ground or background.
    assert!(
        red(160, 120),
        "centre pixel {:?}",
        image.get_pixel(160, 120)
    );
    for (x, y) in [(2, 2), (317, 2), (2, 237), (317, 237)] {
        assert!(!red(x, y), "corner ({x}, {y}) is red");
    }
    // Flat shading: the top face (facing the key light) is brighter than the
    // front face below it.
    let column: Vec<u8> = (0..240)
        .filter(|&y| red(160, y))
        .map(|y| image.get_pixel(160, y).0[0])
        .collect();
    assert!(column.len() > 60, "body spans {} rows", column.len());
    assert!(
        column[3] > column[column.len() - 4],
        "top {} vs front {}",
        column[3],
        column[column.len() - 4]
    );
    // Contact shadow: the ground just below the box is darker than far away.
    let below = (0..240).rev().find(|&y| red(160, y)).unwrap() + 4;
    let near = image.get_pixel(160, below).0[1];
    let far = image.get_pixel(160, 236).0[1];
    assert!(near + 10 < far, "shadow {near} vs open ground {far}");
}

#[test]
fn legend_shows_the_colour_bar_on_the_right() {
    let settings = RenderSettings {
        colouring: Colouring::Scalar {
            range: Some([0.0, 1.0]),
            label: "value",
        },
        draw_legend: true,
        ..plain_settings(640, 360)
    };
    let (mesh, frame) = square(-0.5, -0.5, 1.0);
    let Some(mut renderer) = renderer_or_skip(&settings, &mesh, std::slice::from_ref(&frame))
    else {
        return;
    };
    let image = renderer.render(&frame).unwrap();
    // The bar: the top of viridis above its bottom, right of the picture.
    let find = |t: f32| {
        let target = viridis(t).map(|v| (v * 255.0).round() as i32);
        (0..360).find(|&y| {
            (480..640).any(|x| {
                let p = image.get_pixel(x, y).0;
                (0..3).all(|c| (p[c] as i32 - target[c]).abs() <= 2)
            })
        })
    };
    let (top, middle, bottom) = (find(1.0), find(0.5), find(0.02));
    assert!(
        top.is_some() && middle.is_some() && bottom.is_some(),
        "{top:?} {middle:?} {bottom:?}"
    );
    assert!(
        top < middle && middle < bottom,
        "{top:?} {middle:?} {bottom:?}"
    );
    // The body is framed left of the legend.
    let body_columns: Vec<u32> = (0..640)
        .filter(|&x| image.get_pixel(x, 180).0[..3] != image.get_pixel(2, 180).0[..3])
        .collect();
    assert!(body_columns[0] < 320, "{body_columns:?}");
}

#[test]
fn mismatched_frames_are_typed_errors() {
    let settings = RenderSettings {
        colouring: Colouring::Scalar {
            range: None,
            label: "",
        },
        ..plain_settings(64, 48)
    };
    let (mesh, frame) = square(0.0, 0.0, 1.0);
    let mut short = frame.clone();
    short.element_values.pop();
    let error = Renderer::new(&settings, &mesh, &[frame.clone(), short])
        .err()
        .unwrap();
    assert!(matches!(error, RenderError::InvalidInput(_)), "{error}");
    assert!(
        error.to_string().contains("frame 1 has 1 element values"),
        "{error}"
    );

    let error = Renderer::new(&settings, &mesh, &[]).err().unwrap();
    assert!(error.to_string().contains("no frames"), "{error}");

    let zero = RenderSettings {
        width: 0,
        ..settings.clone()
    };
    assert!(matches!(
        Renderer::new(&zero, &mesh, std::slice::from_ref(&frame)),
        Err(RenderError::InvalidInput(_))
    ));

    let bad_range = RenderSettings {
        colouring: Colouring::Scalar {
            range: Some([1.0, 1.0]),
            label: "",
        },
        ..settings.clone()
    };
    assert!(matches!(
        Renderer::new(&bad_range, &mesh, std::slice::from_ref(&frame)),
        Err(RenderError::InvalidInput(_))
    ));

    let mut bad_mesh = mesh.clone();
    bad_mesh.triangles[0][2] = 9;
    let error = Renderer::new(&settings, &bad_mesh, std::slice::from_ref(&frame))
        .err()
        .unwrap();
    assert!(error.to_string().contains("vertex 9"), "{error}");
}

/// A deferred run warms its renderer up with its first frame before the
/// run is known to be drawable. A first frame the renderer cannot draw (here
/// with a vertex missing) is left for the run to report: the warm-up hands
/// the renderer back unharmed, and it then draws the run's frames as a
/// fresh one does.
#[test]
fn a_warm_up_with_a_frame_it_cannot_draw_leaves_the_renderer_as_it_was() {
    let (mesh, frame) = square(-0.5, -0.5, 1.0);
    let settings = RenderSettings {
        camera: pixel_camera(),
        ..plain_settings(160, 120)
    };
    let frames = [frame];
    let Some(mut fresh) = renderer_or_skip(&settings, &mesh, &frames) else {
        return;
    };
    let mut missing_a_vertex = frames[0].clone();
    missing_a_vertex.positions.pop();
    let prepared = Renderer::prepare(&settings, &mesh)
        .unwrap()
        .warmed_up(&missing_a_vertex)
        .expect("a frame it cannot draw is no warm-up error");
    let mut warmed = prepared.with_frames(&frames).unwrap();
    assert!(warmed.render(&frames[0]).unwrap() == fresh.render(&frames[0]).unwrap());
    // The run's own check still says what is wrong with such a frame.
    let Err(RenderError::InvalidInput(message)) = warmed.render(&missing_a_vertex) else {
        panic!("a frame with a vertex missing must be refused");
    };
    assert!(message.contains("3 vertex positions"), "{message}");
}

/// The settings of the tile tests: 480x270, a scalar field on a fixed
/// range, edges, the legend, and a ground at `ground_height`.
fn tile_test_settings(camera: Camera, ground_height: f32) -> RenderSettings {
    RenderSettings {
        width: 480,
        height: 270,
        camera,
        colouring: Colouring::Scalar {
            range: Some([-0.6, 0.8]),
            label: "value",
        },
        draw_edges: true,
        draw_legend: true,
        ground_height: Some(ground_height),
        ..RenderSettings::default()
    }
}

/// The renderers a tile test compares (`None` when it may skip for lack of
/// an adapter): one drawing the frames' tiles; one for whole images, which
/// grow a renderer's tile target to the image, where a tile may round a
/// coverage differently; and one prepared on its own and warmed up with
/// the run's first frame (framed on its own, as a deferred run's warm-up
/// draws it) before it was given the run, which must draw the same bytes as
/// the first.
fn tile_test_renderers(
    settings: &RenderSettings,
    mesh: &RenderMesh,
    frames: &[RenderFrame],
) -> Option<[Renderer; 3]> {
    let renderer = renderer_or_skip(settings, mesh, frames)?;
    let whole_renderer = Renderer::new(settings, mesh, frames).unwrap();
    let prepared = Renderer::prepare(settings, mesh)
        .and_then(|prepared| prepared.warmed_up(&frames[0]))
        .and_then(|prepared| prepared.with_frames(frames))
        .unwrap();
    Some([renderer, whole_renderer, prepared])
}

/// A 2D frame is drawn as a tile around the body pasted into the run's fixed
/// backdrop: it must show what drawing the whole image shows, wherever the
/// body is — resting on the ground line, partly outside the image, entirely
/// outside, with edges and the legend.
#[test]
fn a_2d_body_tile_shows_what_the_whole_image_shows() {
    use elasto::math::Vector2;
    use elasto::mesh::Mesh;
    let mesh = Mesh::<2>::axis_aligned_box(Vector2::zeros(), Vector2::new(1.0, 0.5), [8, 4])
        .expect("a valid box");
    let render_mesh = RenderMesh::from_mesh(&mesh);
    // Moved by (dx, dy), sheared, with a field varying across the body.
    let frame = |dx: f64, dy: f64, shear: f64| {
        let positions: Vec<_> = mesh
            .rest_positions()
            .iter()
            .map(|p| Vector2::new(p[0] + dx + shear * p[1], p[1] + dy))
            .collect();
        let values: Vec<f64> = (0..mesh.element_count())
            .map(|e| mesh.rest_positions()[mesh.simplex(e)[0]][0] + shear)
            .collect();
        RenderFrame::from_positions(&positions, &values)
    };
    let frames = [
        frame(0.0, 0.6, 0.0),   // in the air
        frame(-0.3, 0.0, 0.2),  // resting on the ground line (y = -0.25)
        frame(-2.2, 0.3, -0.1), // partly outside on the left
        frame(0.4, -0.1, 0.3),  // overlapping the ground
        frame(9.0, 9.0, 0.0),   // entirely outside
        frame(1.2, 0.2, 0.1),   // reaching under the legend
    ];
    let camera = Camera::Orthographic {
        center: [0.0, 0.3],
        height: 2.0,
    };
    let settings = tile_test_settings(camera, -0.25);
    let Some([mut renderer, mut whole_renderer, mut prepared]) =
        tile_test_renderers(&settings, &render_mesh, &frames)
    else {
        return;
    };
    for (k, frame) in frames.iter().enumerate() {
        let tiled = renderer.render(frame).unwrap();
        assert!(
            tiled == prepared.render(frame).unwrap(),
            "frame {k}: the warmed-up renderer draws differently"
        );
        let whole = whole_renderer.render_whole_image(frame).unwrap();
        assert_eq!(tiled.dimensions(), whole.dimensions());
        // The tile's vertices go through one more multiply-add, so a sample
        // lying exactly on an edge may fall the other way: allow a few
        // single pixels, nothing more.
        let differing: Vec<(u32, u32, u8)> = tiled
            .enumerate_pixels()
            .zip(whole.pixels())
            .filter_map(|((x, y, a), b)| {
                let d =
                    a.0.iter()
                        .zip(&b.0)
                        .map(|(p, q)| p.abs_diff(*q))
                        .max()
                        .unwrap();
                (d > 1).then_some((x, y, d))
            })
            .collect();
        assert!(
            differing.len() <= 3,
            "frame {k}: {} pixels differ between the tile and the whole image: {:?}",
            differing.len(),
            &differing[..differing.len().min(20)]
        );
    }
}

/// A 3D frame is drawn as a tile around the body and its contact shadow,
/// pasted into the run's fixed backdrop: it must show what one
/// multisampled pass over the whole image shows, wherever the body is —
/// high in the air (a wide, faint shadow), resting on the ground, partly
/// outside the image, above the image with its shadow in view, under the
/// legend, and with a vertex behind the eye.
#[test]
fn a_3d_scene_tile_shows_what_the_whole_image_shows() {
    use elasto::math::Vector3;
    use elasto::mesh::Mesh;
    let mesh =
        Mesh::<3>::axis_aligned_box(Vector3::zeros(), Vector3::new(1.0, 0.5, 0.8), [3, 2, 2])
            .expect("a valid box");
    let render_mesh = RenderMesh::from_mesh(&mesh);
    // Moved by (dx, dy, dz), sheared, with a field varying across the body.
    let frame = |dx: f64, dy: f64, dz: f64, shear: f64| {
        let positions: Vec<_> = mesh
            .rest_positions()
            .iter()
            .map(|p| Vector3::new(p[0] + dx + shear * p[1], p[1] + dy, p[2] + dz))
            .collect();
        let values: Vec<f64> = (0..mesh.element_count())
            .map(|e| mesh.rest_positions()[mesh.simplex(e)[0]][0] + shear)
            .collect();
        RenderFrame::from_positions(&positions, &values)
    };
    let frames = [
        frame(0.0, 1.5, 0.0, 0.0),   // high in the air
        frame(-0.4, 0.0, 0.3, 0.2),  // resting on the ground (y = 0)
        frame(-3.2, 0.4, 0.0, -0.1), // partly outside on the left
        frame(0.2, 4.5, -0.5, 0.0),  // above the image, its shadow in view
        frame(2.4, 0.8, 0.0, 0.1),   // reaching under the legend
        frame(0.0, 0.5, 5.5, 0.0),   // reaching behind the eye
    ];
    let camera = Camera::Perspective {
        eye: [0.0, 2.0, 6.0],
        target: [0.0, 0.5, 0.0],
        fov_degrees: 45.0,
    };
    let settings = tile_test_settings(camera, 0.0);
    let Some([mut renderer, mut whole_renderer, mut prepared]) =
        tile_test_renderers(&settings, &render_mesh, &frames)
    else {
        return;
    };
    let differing = |a: &image::RgbaImage, b: &image::RgbaImage, above: u8| {
        a.pixels()
            .zip(b.pixels())
            .filter(|(p, q)| p.0.iter().zip(&q.0).any(|(x, y)| x.abs_diff(*y) > above))
            .count()
    };
    for (k, frame) in frames.iter().enumerate() {
        let tiled = renderer.render(frame).unwrap();
        assert!(
            tiled == prepared.render(frame).unwrap(),
            "frame {k}: the warmed-up renderer draws differently"
        );
        let whole = whole_renderer.render_whole_image(frame).unwrap();
        assert_eq!(tiled.dimensions(), whole.dimensions());
        // The body moves the image: the backdrop alone would differ a lot.
        let backdrop_only = differing(&whole, &renderer.render(&frames[4]).unwrap(), 8);
        assert!(k == 4 || backdrop_only > 500, "frame {k}: {backdrop_only}");
        // The tile's positions go through one more multiply-add and the
        // ground's shading rounds differently in a few hundred pixels (one
        // level); a sample on an edge may fall the other way.
        let by_more_than_one = differing(&tiled, &whole, 1);
        let at_all = differing(&tiled, &whole, 0);
        assert!(
            by_more_than_one <= 4 && at_all <= 100,
            "frame {k}: {by_more_than_one} pixels differ by more than one level from the \
             whole image, {at_all} at all"
        );
    }
}
