//! Containment: separate bodies are clean, a body inside another is found,
//! and one in a hole of a hollow body is not.

use super::*;

#[test]
fn separate_squares_are_clean_and_nested_ones_contained() {
    let mut s = SavedSurface::default();
    square(&mut s, 0.0, 0.0, 1.0);
    square(&mut s, 1.5, 0.0, 1.0);
    assert_eq!(s.components(), [0, 0, 0, 0, 1, 1, 1, 1]);
    assert_eq!(find_intersections(&s), []);
    let mut nested = SavedSurface::default();
    square(&mut nested, 0.0, 0.0, 3.0);
    square(&mut nested, 1.0, 1.0, 1.0);
    assert_eq!(
        find_intersections(&nested),
        [Intersection::Contained {
            inner: 1,
            outer: 0,
            vertex: 4
        }]
    );
}

#[test]
fn a_body_in_a_hole_is_clean_and_one_in_the_material_is_not() {
    for (x, contained) in [(4.0, false), (1.0, true)] {
        let mut s = SavedSurface::default();
        square(&mut s, 0.0, 0.0, 10.0);
        polygon(&mut s, &[[3.0, 3.0], [3.0, 7.0], [7.0, 7.0], [7.0, 3.0]]); // clockwise hole
        square(&mut s, x, x, 1.0);
        let expected: &[Intersection] = if contained {
            &[Intersection::Contained {
                inner: 2,
                outer: 0,
                vertex: 8,
            }]
        } else {
            &[]
        };
        assert_eq!(find_intersections(&s), expected, "square at {x}");
    }
}

#[test]
fn a_cube_has_its_volume_and_winds_once_around_its_inside() {
    let mut s = SavedSurface::default();
    cube(&mut s, [1.0, 2.0, 3.0], 2.0, 2);
    let facets: Vec<Vec<usize>> = s.triangles.iter().map(|t| t.to_vec()).collect();
    assert_eq!(facets.len(), 48);
    assert!(is_closed(&facets));
    assert!(!is_closed(&facets[1..]));
    assert!((signed_measure(&facets, &s.vertices, [0.0; 3]) - 8.0).abs() < 1e-12);
    let w = |p| winding_number_3d(p, &facets, &s.vertices);
    assert!(
        (w([2.1, 2.9, 4.2]) - 1.0).abs() < 1e-12,
        "{}",
        w([2.1, 2.9, 4.2])
    );
    assert!(w([3.5, 3.0, 4.0]).abs() < 1e-12);
    assert!(w([-5.0, 40.0, 1.0]).abs() < 1e-12);
}

#[test]
fn separate_and_nested_cubes() {
    let mut s = SavedSurface::default();
    cube(&mut s, [0.0; 3], 1.0, 2);
    cube(&mut s, [1.001, 0.2, 0.3], 1.0, 1);
    assert_eq!(find_intersections(&s), []);
    assert_eq!(find_intersections_within(&s, 9e-4), []);
    let near = find_intersections_within(&s, 2e-3);
    assert!(
        !near.is_empty()
            && near
                .iter()
                .all(|i| matches!(i, Intersection::EdgeThroughTriangle { .. }))
    );
    let mut nested = SavedSurface::default();
    cube(&mut nested, [0.0; 3], 3.0, 2);
    let first_of_small = nested.vertices.len();
    cube(&mut nested, [1.0, 1.2, 0.9], 1.0, 1);
    assert_eq!(
        find_intersections(&nested),
        [Intersection::Contained {
            inner: 1,
            outer: 0,
            vertex: first_of_small
        }]
    );
}
