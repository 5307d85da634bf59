//! 3D crossings: an edge through or touching a triangle (in its plane too),
//! interpenetrating cubes, and near misses within the tolerance.

use super::*;

#[test]
fn interpenetrating_cubes_are_found() {
    let mut s = SavedSurface::default();
    cube(&mut s, [0.0; 3], 1.0, 1);
    cube(&mut s, [0.5, 0.3, 0.2], 1.0, 1);
    let s = saved(&s, "cross3");
    let found = find_intersections(&s);
    // B's edge along x from its lowest corner leaves A through A's face
    // x = 1 at (1, 0.3, 0.2), in that face's triangle below the diagonal z = y.
    let edge = [
        vertex_at(&s, [0.5, 0.3, 0.2]),
        vertex_at(&s, [1.5, 0.3, 0.2]),
    ];
    let corners = [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [1.0, 1.0, 1.0]].map(|p| vertex_at(&s, p));
    let triangle = s.triangles.iter().position(|&t| t == corners).unwrap();
    assert!(
        found.contains(&Intersection::EdgeThroughTriangle { edge, triangle }),
        "{found:?}"
    );
    assert!(found.contains(&Intersection::Contained {
        inner: 1,
        outer: 0,
        vertex: edge[0]
    }));
    let lowest_of_a = |i: &Intersection| matches!(i, Intersection::EdgeThroughTriangle { edge, .. } if edge.contains(&0));
    assert!(
        !found.iter().any(lowest_of_a),
        "A's corner at the origin is outside B"
    );
}

#[test]
fn edges_meet_triangles_they_reach_or_overlap_in_their_plane() {
    let triangle = [[0.0, 0.0, 1.0], [2.0, 0.0, 1.0], [0.0, 2.0, 1.0]];
    let meets = |p, q| edge_meets_triangle(p, q, triangle);
    assert!(meets([-1.0, 0.5, 1.0], [3.0, 0.5, 1.0]), "across");
    assert!(meets([0.2, 0.2, 1.0], [0.5, 0.3, 1.0]), "inside");
    assert!(
        meets([1.0, 1.0, 1.0], [3.0, 3.0, 1.0]),
        "from the hypotenuse"
    );
    assert!(!meets([1.5, 1.5, 1.0], [3.0, 1.0, 1.0]), "beside");
    assert!(!meets([0.5, 0.5, 2.0], [0.5, 0.5, 1.5]), "short of it");
    assert!(meets([0.5, 0.5, 2.0], [0.5, 0.5, 1.0]), "ending on it");
    assert!(meets([0.5, 0.5, 2.0], [0.5, 0.5, 0.5]), "through it");
    assert!(
        !meets([1.5, 1.5, 2.0], [1.5, 1.5, 0.5]),
        "past its hypotenuse"
    );
    assert!(
        !meets([-1.0, 0.5, 1.0 + 1e-9], [3.0, 0.5, 1.0 + 1e-9]),
        "above"
    );
    // Cubes touching face to face: B's edge in the plane x = 1 lies on A's face.
    let mut s = SavedSurface::default();
    cube(&mut s, [0.0; 3], 1.0, 1);
    cube(&mut s, [1.0, 0.2, 0.3], 1.0, 1);
    let edge = [
        vertex_at(&s, [1.0, 0.2, 0.3]),
        vertex_at(&s, [1.0, 1.2, 0.3]),
    ];
    let on_face = |t: usize| {
        s.triangles[t]
            .iter()
            .all(|&i| s.vertices[i][0] == 1.0 && i < 8)
    };
    let found = find_intersections(&s);
    assert!(
        found.iter().any(
            |i| matches!(i, Intersection::EdgeThroughTriangle { edge: e, triangle }
        if *e == edge && on_face(*triangle))
        ),
        "{found:?}"
    );
}

#[test]
fn a_tetrahedron_poking_a_vertex_through_a_triangle_is_found() {
    for (apex_z, poking) in [(0.2, true), (-0.1, false)] {
        let mut s = SavedSurface::default();
        add(
            &mut s,
            &[[-2.0, -2.0, 0.0], [3.0, -1.0, 0.0], [-1.0, 3.0, 0.0]],
            &[],
            &[[0, 1, 2]],
        );
        let tetrahedron = [
            [0.0, 0.0, -1.0],
            [1.0, 0.0, -1.0],
            [0.0, 1.0, -1.0],
            [0.25, 0.25, apex_z],
        ];
        add(
            &mut s,
            &tetrahedron,
            &[],
            &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]],
        );
        let expected: Vec<Intersection> = if poking {
            (3..6)
                .map(|b| Intersection::EdgeThroughTriangle {
                    edge: [b, 6],
                    triangle: 0,
                })
                .collect()
        } else {
            Vec::new()
        };
        assert_eq!(find_intersections(&s), expected, "apex at z = {apex_z}");
    }
}

#[test]
fn near_misses_within_the_tolerance_are_found_by_their_distance() {
    // Skew segments 0.5 apart, closest at their middles.
    let (d, at) =
        segment_segment_closest([0.0; 3], [2.0, 0.0, 0.0], [1.0, -1.0, 0.5], [1.0, 1.0, 0.5]);
    assert_eq!((d, at), (0.5, [1.0, 0.0, 0.25]));
    // The foot of the apex falls inside the sheet, 1e-3 below it.
    let mut s = SavedSurface::default();
    add(
        &mut s,
        &[[-2.0, -2.0, 0.0], [3.0, -1.0, 0.0], [-1.0, 3.0, 0.0]],
        &[],
        &[[0, 1, 2]],
    );
    let tetrahedron = [
        [0.0, 0.0, -1.0],
        [1.0, 0.0, -1.0],
        [0.0, 1.0, -1.0],
        [0.25, 0.25, -1e-3],
    ];
    add(
        &mut s,
        &tetrahedron,
        &[],
        &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]],
    );
    assert_eq!(find_intersections_within(&s, 9e-4), []);
    let near: Vec<Intersection> = (3..6)
        .map(|b| Intersection::EdgeThroughTriangle {
            edge: [b, 6],
            triangle: 0,
        })
        .collect();
    assert_eq!(find_intersections_within(&s, 2e-3), near);
}
