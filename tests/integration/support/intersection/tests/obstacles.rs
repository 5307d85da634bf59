//! Obstacles: a body crossing or inside an obstacle is found, obstacles
//! crossing each other or inside each other are not, and an open obstacle
//! has no inside.

use super::*;

/// Two open plates, OBJ text as `obstacles_NNNN.obj` holds them: one
/// across y = `y` over x, z in [-1, 2], one upright across it (x = 0.5,
/// y in [y − 0.5, y + 0.5]); each fanned from its first vertex.
fn crossed_plates_obj(y: f64) -> String {
    let (lo, hi) = (y - 0.5, y + 0.5);
    format!(
        "# elasto boundary surface\n\
         v -1 {y} -1\nv 2 {y} -1\nv 2 {y} 2\nv -1 {y} 2\n\
         v 0.5 {lo} -1\nv 0.5 {hi} -1\nv 0.5 {hi} 2\nv 0.5 {lo} 2\n\
         f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\n"
    )
}

#[test]
fn a_body_through_an_obstacle_is_found_and_obstacles_crossing_each_other_are_not() {
    let mut body = SavedSurface::default();
    cube(&mut body, [0.0; 3], 1.0, 1);
    let body = SavedSurface::parse_obj(&to_obj(&body)).unwrap();
    // Plates above the cube: they cross each other, which is no problem.
    let above = SavedSurface::parse_obj(&crossed_plates_obj(1.6)).unwrap();
    assert_eq!(find_intersections(&body.with_obstacles(&above)), []);
    // The same obstacles as a body would cross it.
    assert!(!find_intersections(&above).is_empty());
    // Plates through the cube's middle: the level one (triangles 12 and
    // 13 of the union) is crossed by the cube's upright edges and side
    // diagonals; the upright one touches the cube's top and bottom.
    let through = SavedSurface::parse_obj(&crossed_plates_obj(0.5)).unwrap();
    let joined = body.with_obstacles(&through);
    assert_eq!(joined.obstacles_from, Some(8));
    let found = find_intersections(&joined);
    assert!(!found.is_empty());
    for problem in &found {
        let Intersection::EdgeThroughTriangle { edge, triangle } = problem else {
            panic!("{problem:?}");
        };
        // Always a body's edge against an obstacle's triangle (or an
        // obstacle's edge against a body's triangle), never two obstacles'.
        let body_edge = edge[1] < 8;
        let body_triangle = *triangle < 12;
        assert!(body_edge != body_triangle, "{problem:?}");
    }
    let upright_edges_through_the_level_plate = found
        .iter()
        .filter(|p| {
            matches!(p, Intersection::EdgeThroughTriangle { edge: [a, b], triangle: 12 | 13 }
                if *b < 8 && joined.vertices[*a][1] != joined.vertices[*b][1])
        })
        .count();
    assert!(upright_edges_through_the_level_plate >= 4, "{found:?}");
}

#[test]
fn a_body_inside_a_closed_obstacle_is_found_but_not_inside_an_open_one() {
    let mut body = SavedSurface::default();
    cube(&mut body, [1.0; 3], 1.0, 1);
    // A closed box obstacle around the body, and a second one around
    // that (an obstacle inside an obstacle is no problem).
    let mut boxes = SavedSurface::default();
    cube(&mut boxes, [0.0; 3], 3.0, 1);
    cube(&mut boxes, [-1.0; 3], 5.0, 1);
    let boxes = SavedSurface::parse_obj(&to_obj(&boxes)).unwrap();
    assert_eq!(
        find_intersections(&body.with_obstacles(&boxes)),
        [
            Intersection::Contained {
                inner: 0,
                outer: 1,
                vertex: 0
            },
            Intersection::Contained {
                inner: 0,
                outer: 2,
                vertex: 0
            },
        ]
    );
    // The same box with its top open (a bowl): it has no inside.
    let mut open = boxes.clone();
    open.triangles.truncate(12);
    open.triangles
        .retain(|t| t.iter().any(|&v| open.vertices[v][1] < 3.0));
    assert_eq!(open.triangles.len(), 10);
    open.vertices.truncate(8);
    assert_eq!(find_intersections(&body.with_obstacles(&open)), []);
    // A closed obstacle inside a body counts too.
    let mut big = SavedSurface::default();
    cube(&mut big, [-1.0; 3], 5.0, 1);
    let mut small = SavedSurface::default();
    cube(&mut small, [1.0; 3], 1.0, 1);
    assert_eq!(
        find_intersections(&big.with_obstacles(&small)),
        [Intersection::Contained {
            inner: 1,
            outer: 0,
            vertex: 8
        }]
    );
}

#[test]
fn in_2d_a_body_crossing_an_obstacle_polyline_is_found() {
    let mut body = SavedSurface::default();
    square(&mut body, 0.0, 0.0, 1.0);
    // Two obstacle polylines crossing each other at (0.5, 2), above the
    // square, as `l` lines of an OBJ file.
    let above =
        SavedSurface::parse_obj("v -1 2 0\nv 2 2 0\nv 0.5 1.5 0\nv 0.5 2.5 0\nl 1 2\nl 3 4\n")
            .unwrap();
    assert_eq!(find_intersections(&body.with_obstacles(&above)), []);
    // One lower, through the square at y = 0.5: its segment (4 of the
    // union) crosses the square's right (1) and left (3) sides.
    let through =
        SavedSurface::parse_obj("v -1 0.5 0\nv 2 0.5 0\nv 0.5 1.5 0\nv 0.5 2.5 0\nl 1 2\nl 3 4\n")
            .unwrap();
    assert_eq!(
        find_intersections(&body.with_obstacles(&through)),
        [
            Intersection::SegmentsCross {
                a: 1,
                b: 4,
                at: [1.0, 0.5]
            },
            Intersection::SegmentsCross {
                a: 3,
                b: 4,
                at: [0.0, 0.5]
            },
        ]
    );
}
