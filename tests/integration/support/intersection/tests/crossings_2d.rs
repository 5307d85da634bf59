//! 2D crossings: segments that cross or touch are found where they meet,
//! and a gap counts only within the tolerance asked for.

use super::*;

#[test]
fn crossing_squares_are_found_where_they_cross() {
    let mut s = SavedSurface::default();
    square(&mut s, 0.0, 0.0, 1.0);
    square(&mut s, 0.5, 0.25, 1.0);
    let found = find_intersections(&saved(&s, "cross2"));
    // Right edge of A (segment 1) meets bottom of B (4) at (1, 0.25);
    // top of A (2) meets left of B (7) at (0.5, 1); B's corner is in A.
    assert_eq!(
        found,
        [
            Intersection::SegmentsCross {
                a: 1,
                b: 4,
                at: [1.0, 0.25]
            },
            Intersection::SegmentsCross {
                a: 2,
                b: 7,
                at: [0.5, 1.0]
            },
            Intersection::Contained {
                inner: 1,
                outer: 0,
                vertex: 4
            },
        ]
    );
}

#[test]
fn a_gap_of_1e_3_is_clean_unless_within_the_tolerance() {
    let mut s = SavedSurface::default();
    square(&mut s, 0.0, 0.0, 1.0);
    square(&mut s, 1.001, 0.0, 1.0);
    assert_eq!(find_intersections(&s), []);
    assert_eq!(find_intersections_within(&s, 9e-4), []);
    let near = find_intersections_within(&s, 2e-3);
    // A's right edge (1) and B's left edge (7) are 1e-3 apart, midway at x = 1.0005.
    assert!(
        near.iter().any(
            |i| matches!(i, Intersection::SegmentsCross { a: 1, b: 7, at }
        if (at[0] - 1.0005).abs() < 1e-12)
        ),
        "{near:?}"
    );
}

#[test]
fn a_figure_eight_crosses_itself() {
    let mut s = SavedSurface::default();
    polygon(&mut s, &[[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 2.0]]);
    assert_eq!(
        find_intersections(&s),
        [Intersection::SegmentsCross {
            a: 0,
            b: 2,
            at: [1.0, 1.0]
        }]
    );
}
