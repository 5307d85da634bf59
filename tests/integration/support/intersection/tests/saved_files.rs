//! The checker on saved files: it judges the `f32` numbers in the file,
//! reads every OBJ index form, and checks a large surface quickly.

use super::*;

#[test]
fn the_checker_judges_the_f32_numbers_in_the_file() {
    // 1 + 1e-7 rounds to the next f32 above 1 (1 + 1.19e-7): still apart.
    // 1 + 4e-8 rounds to 1: in the file the squares touch along x = 1.
    for (gap, touching) in [(1e-7, false), (4e-8, true)] {
        let mut s = SavedSurface::default();
        square(&mut s, 0.0, 0.0, 1.0);
        square(&mut s, 1.0 + gap, 0.0, 1.0);
        assert_eq!(find_intersections(&s), [], "unrounded, gap {gap}");
        let found = find_intersections(&saved(&s, &format!("f32_{touching}")));
        assert_eq!(!found.is_empty(), touching, "gap {gap}: {found:?}");
        assert!(
            found
                .iter()
                .all(|i| matches!(i, Intersection::SegmentsCross { at, .. } if at[0] == 1.0))
        );
    }
}

#[test]
fn obj_files_read_every_index_form() {
    let text = "# comment\nmtllib x.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0.5\nv 0 1 0\nvn 0 0 1\nvt 0 0\n\
                l 1 2 3\nf 1/1/1 2/1/1 3/1/1\nf 1//1 2//1 3//1 4//1\nf -1 -2 -3\nf 2/7 3/7 4/7\n";
    let path = temp_file("read", text);
    let s = SavedSurface::read_obj(&path).unwrap();
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
    assert_eq!(
        s.vertices,
        [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.5],
            [0.0, 1.0, 0.0]
        ]
    );
    assert_eq!(s.segments, [[0, 1], [1, 2]]);
    assert_eq!(
        s.triangles,
        [[0, 1, 2], [0, 1, 2], [0, 2, 3], [3, 2, 1], [1, 2, 3]]
    );
    assert_eq!(s.components(), [0, 0, 0, 0]);
    assert!(
        SavedSurface::parse_obj("v 0 0 0\nf 1 2 3\n")
            .unwrap_err()
            .contains("index 2")
    );
    assert!(
        SavedSurface::parse_obj("v 0 x 0\n")
            .unwrap_err()
            .contains("line 1")
    );
    assert!(SavedSurface::parse_obj("v 0 0 0\nl 1 0\n").is_err());
    assert!(SavedSurface::read_obj(Path::new("/nonexistent/surface.obj")).is_err());
}

#[test]
fn a_surface_of_ten_thousand_triangles_is_checked_quickly() {
    let mut s = SavedSurface::default();
    cube(&mut s, [0.0; 3], 1.0, 20);
    cube(&mut s, [1.01, 0.3, 0.2], 1.0, 20);
    assert_eq!(s.triangles.len(), 9600);
    let start = std::time::Instant::now();
    assert_eq!(find_intersections(&s), []);
    let shifted = SavedSurface {
        vertices: s
            .vertices
            .iter()
            .enumerate()
            .map(|(i, p)| {
                if i < 2402 {
                    *p
                } else {
                    [p[0] - 0.1, p[1], p[2]]
                }
            })
            .collect(),
        ..s.clone()
    };
    let found = find_intersections(&shifted);
    assert!(
        found
            .iter()
            .filter(|i| matches!(i, Intersection::EdgeThroughTriangle { .. }))
            .count()
            > 20
    );
    assert!(
        start.elapsed().as_secs_f64() < 20.0,
        "{:?}",
        start.elapsed()
    );
}
