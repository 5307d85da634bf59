//! Obstacles in frames (issue 32 item 2's rendering): an obstacle beside a
//! body is drawn where its positions say, in the flat obstacle colour
//! whatever the body's colour map — in 2D a translucent fill over the
//! background with a darker outline, in 3D lit on either side of an open
//! surface — and the automatic camera frames it with the body.

use crate::render_support::{assert_pixel, plain_settings, renderer_or_skip, square, srgb8};
use elasto::math::Vector3;
use elasto::mesh::Mesh;
use elasto::render::{
    Camera, Colouring, OBSTACLE_FILL_OPACITY, OBSTACLE_SRGB, RenderFrame, RenderMesh,
    RenderSettings, srgb_to_linear, viridis,
};

/// `mesh` and `frame` with a quad obstacle at `corners` appended: its four
/// vertices after the body's, two triangles, its four sides as edges.
fn with_quad_obstacle(
    mut mesh: RenderMesh,
    mut frame: RenderFrame,
    corners: [[f32; 3]; 4],
) -> (RenderMesh, RenderFrame) {
    let first = frame.positions.len() as u32;
    frame.positions.extend(corners);
    let [a, b, c, d] = [0, 1, 2, 3].map(|k| first + k);
    mesh.obstacle_triangles = vec![[a, b, c], [a, c, d]];
    mesh.obstacle_edges = vec![[a, b], [b, c], [c, d], [d, a]];
    (mesh, frame)
}

/// 40 pixels per scene unit, origin at the image centre (80, 60) of a
/// 160 x 120 image: scene (x, y) is pixel (80 + 40 x, 60 − 40 y).
fn pixel_camera() -> Camera {
    Camera::Orthographic {
        center: [0.0, 0.0],
        height: 3.0,
    }
}

#[test]
fn a_2d_obstacle_is_a_translucent_fill_with_an_outline_beside_the_body() {
    // The body: pixels 20..60 across, 40..80 down; the obstacle: 100..140.
    let (body_mesh, body_frame) = square(-1.5, -0.5, 1.0);
    let (mesh, frame) = with_quad_obstacle(
        body_mesh,
        body_frame,
        [
            [0.5, -0.5, 0.0],
            [1.5, -0.5, 0.0],
            [1.5, 0.5, 0.0],
            [0.5, 0.5, 0.0],
        ],
    );
    // A colour map on the body: the obstacle has no value and keeps its colour.
    let settings = RenderSettings {
        camera: pixel_camera(),
        colouring: Colouring::Scalar {
            range: Some([0.0, 1.0]),
            label: "value",
        },
        draw_legend: false,
        ..plain_settings(160, 120)
    };
    let Some(mut renderer) = renderer_or_skip(&settings, &mesh, std::slice::from_ref(&frame))
    else {
        return;
    };
    let image = renderer.render(&frame).unwrap();
    let background = settings.background;
    // The fill is the obstacle colour over the background, blended in linear light.
    let obstacle = OBSTACLE_SRGB.map(srgb_to_linear);
    let fill = srgb8(std::array::from_fn(|c| {
        OBSTACLE_FILL_OPACITY * obstacle[c] + (1.0 - OBSTACLE_FILL_OPACITY) * background[c]
    }));
    assert_pixel(&image, 120, 60, fill, 1);
    assert_pixel(&image, 104, 44, fill, 1);
    assert_pixel(&image, 136, 76, fill, 1);
    // Outside it, the background; between it and the body too.
    assert_pixel(&image, 145, 60, srgb8(background), 1);
    assert_pixel(&image, 80, 60, srgb8(background), 1);
    assert_pixel(&image, 120, 35, srgb8(background), 1);
    // Its outline, on the obstacle's sides, is darker than the fill.
    for (x, y) in [(100, 60), (139, 60), (120, 40), (120, 79)] {
        let pixel = image.get_pixel(x, y).0;
        assert!(
            (0..3).all(|c| i32::from(pixel[c]) + 40 < i32::from(fill[c])),
            "({x}, {y}) is {pixel:?}, not an outline darker than the fill {fill:?}"
        );
    }
    // The body keeps its colour map: element 0 (value 0) below the diagonal.
    let to8 = |c: [f32; 3]| c.map(|v| (v * 255.0).round() as u8);
    assert_pixel(&image, 50, 70, to8(viridis(0.0)), 1);
    assert_pixel(&image, 30, 50, to8(viridis(1.0)), 1);

    // The same body without the obstacle: the obstacle's pixels are background.
    let (mesh, frame) = square(-1.5, -0.5, 1.0);
    let mut renderer = renderer_or_skip(&settings, &mesh, std::slice::from_ref(&frame)).unwrap();
    let alone = renderer.render(&frame).unwrap();
    assert_pixel(&alone, 120, 60, srgb8(background), 1);
    assert_pixel(&alone, 50, 70, to8(viridis(0.0)), 1);
}

/// A unit box on the ground (y = 0) at x in [-1.5, -0.5], and an upright
/// plate obstacle beside it at x in [0.5, 1.5], facing away from the camera
/// (an open surface, seen from its back).
fn box_and_plate() -> (RenderMesh, RenderFrame) {
    let body = Mesh::<3>::axis_aligned_box(
        Vector3::new(-1.5, 0.0, -0.5),
        Vector3::new(-0.5, 1.0, 0.5),
        [1, 1, 1],
    )
    .unwrap();
    let frame =
        RenderFrame::from_positions(body.rest_positions(), &vec![0.0; body.element_count()]);
    // Counter-clockwise seen from -z: its normal points away from the eye.
    let plate = [
        [0.5, 0.0, 0.0],
        [0.5, 1.0, 0.0],
        [1.5, 1.0, 0.0],
        [1.5, 0.0, 0.0],
    ];
    with_quad_obstacle(RenderMesh::from_mesh(&body), frame, plate)
}

#[test]
fn a_3d_obstacle_is_drawn_lit_in_its_colour_from_either_side() {
    let (mesh, frame) = box_and_plate();
    let settings = RenderSettings {
        camera: Camera::Perspective {
            eye: [0.0, 0.5, 6.0],
            target: [0.0, 0.5, 0.0],
            fov_degrees: 30.0,
        },
        colouring: Colouring::Flat([0.8, 0.1, 0.05]),
        ground_height: Some(0.0),
        draw_edges: true,
        ..plain_settings(320, 240)
    };
    let Some(mut renderer) = renderer_or_skip(&settings, &mesh, std::slice::from_ref(&frame))
    else {
        return;
    };
    let image = renderer.render(&frame).unwrap();
    // At z = 0, 6 units from the eye, the image's half height of 120 pixels
    // is 6 tan 15° = 1.61 units: 74.6 pixels a unit, from the image centre
    // (x = 0, y = 0.5). The plate spans pixels 197..272 across, 83..157
    // down; its centre (1, 0.5) is pixel (235, 120).
    let (plate_x, plate_y) = (235, 120);
    let shade = image.get_pixel(plate_x, plate_y).0;
    // Lit from the front-left above: a shade of the obstacle colour, its
    // channels in the same order (blue the strongest), neither the body's
    // red nor the background's grey.
    assert!(
        shade[0] < shade[1] && shade[1] < shade[2],
        "({plate_x}, {plate_y}) is {shade:?}, not the obstacle's cool grey"
    );
    let obstacle = srgb8(OBSTACLE_SRGB.map(srgb_to_linear));
    for c in 0..3 {
        let ratio = shade[c] as f32 / obstacle[c] as f32;
        assert!(
            (0.5..1.2).contains(&ratio),
            "{shade:?} against {obstacle:?}"
        );
    }
    // Above it, the neutral grey background.
    let far = image.get_pixel(plate_x, 20).0;
    assert!(far[0] == far[1] && far[1] == far[2], "{far:?}");
    // The body beside it (its front face spans pixels 38..119) keeps its flat red.
    let [r, g, b, _] = image.get_pixel(80, 120).0.map(u16::from);
    assert!(r > 2 * g && r > 2 * b, "{:?}", [r, g, b]);

    // Without the obstacle, its pixels show what lies behind it.
    let mut bare = mesh.clone();
    bare.obstacle_triangles.clear();
    bare.obstacle_edges.clear();
    let mut renderer = renderer_or_skip(&settings, &bare, std::slice::from_ref(&frame)).unwrap();
    let behind = renderer
        .render(&frame)
        .unwrap()
        .get_pixel(plate_x, plate_y)
        .0;
    assert!(
        (0..3).any(|c| behind[c].abs_diff(shade[c]) > 20),
        "{behind:?} and {shade:?}: the obstacle was not drawn"
    );
}

/// The automatic camera frames the bodies and the obstacles: an obstacle far
/// to the right makes the body smaller in the image and shows at its side.
#[test]
fn an_obstacle_far_away_widens_the_automatic_camera() {
    for dimension in [2, 3] {
        let (mesh, frame) = if dimension == 2 {
            square(-0.5, -0.5, 1.0)
        } else {
            let (mesh, frame) = box_and_plate();
            let mut mesh = mesh;
            mesh.obstacle_triangles.clear();
            mesh.obstacle_edges.clear();
            let mut frame = frame;
            frame.positions.truncate(frame.positions.len() - 4);
            (mesh, frame)
        };
        let far = [
            [8.0, 0.0, 0.0],
            [9.0, 0.0, 0.0],
            [9.0, 1.0, 0.0],
            [8.0, 1.0, 0.0],
        ];
        let (wide_mesh, wide_frame) = with_quad_obstacle(mesh.clone(), frame.clone(), far);
        let settings = RenderSettings {
            camera: Camera::Auto,
            ..plain_settings(320, 240)
        };
        let body_pixels = |mesh: &RenderMesh, frame: &RenderFrame| {
            let mut renderer = renderer_or_skip(&settings, mesh, std::slice::from_ref(frame))?;
            let image = renderer.render(frame).unwrap();
            let red = |p: &image::Rgba<u8>| {
                let [r, g, b, _] = p.0.map(u16::from);
                r > 2 * g && r > 2 * b
            };
            let grey = |p: &image::Rgba<u8>| {
                let [r, g, b, _] = p.0;
                r < g && g < b && b < 235
            };
            let obstacle_columns: Vec<u32> = image
                .enumerate_pixels()
                .filter(|(_, _, p)| grey(p))
                .map(|(x, _, _)| x)
                .collect();
            Some((image.pixels().filter(|p| red(p)).count(), obstacle_columns))
        };
        let Some((alone, no_obstacle)) = body_pixels(&mesh, &frame) else {
            return;
        };
        let (with_far, obstacle) = body_pixels(&wide_mesh, &wide_frame).unwrap();
        assert!(
            no_obstacle.is_empty(),
            "{dimension}D: no obstacle, no obstacle pixels"
        );
        // The view is about ten times wider: the body covers far fewer pixels.
        assert!(
            with_far * 10 < alone,
            "{dimension}D: {with_far} body pixels with the obstacle, {alone} without"
        );
        // The obstacle is in the image, on its right.
        assert!(
            !obstacle.is_empty(),
            "{dimension}D: the obstacle is not in view"
        );
        assert!(
            obstacle.iter().all(|&x| x > 160),
            "{dimension}D: obstacle pixels left of the centre"
        );
    }
}
