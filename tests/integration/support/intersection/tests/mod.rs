//! The checker's own tests, by subject, and the surfaces they build.

mod containment;
mod crossings_2d;
mod crossings_3d;
mod obstacles;
mod saved_files;

use super::containment::{is_closed, signed_measure, winding_number_3d};
use super::geometry::edge_meets_triangle;
use super::*;
use std::collections::HashMap;
use std::path::PathBuf;

/// Appends a piece (indices local to it) to `s`.
pub(super) fn add(
    s: &mut SavedSurface,
    vertices: &[[f64; 3]],
    segments: &[[usize; 2]],
    triangles: &[[usize; 3]],
) {
    let o = s.vertices.len();
    s.vertices.extend_from_slice(vertices);
    s.segments.extend(segments.iter().map(|e| e.map(|i| i + o)));
    s.triangles
        .extend(triangles.iter().map(|t| t.map(|i| i + o)));
}

/// A closed loop through `points` in order.
pub(super) fn polygon(s: &mut SavedSurface, points: &[[f64; 2]]) {
    let n = points.len();
    let vertices: Vec<[f64; 3]> = points.iter().map(|p| [p[0], p[1], 0.0]).collect();
    let segments: Vec<[usize; 2]> = (0..n).map(|i| [i, (i + 1) % n]).collect();
    add(s, &vertices, &segments, &[]);
}

/// A counter-clockwise square with its lower-left corner first.
pub(super) fn square(s: &mut SavedSurface, x: f64, y: f64, size: f64) {
    polygon(
        s,
        &[[x, y], [x + size, y], [x + size, y + size], [x, y + size]],
    );
}

/// The outward boundary of the cube `min + [0, size]³`, each face split
/// into n × n squares of two triangles, vertices shared.
pub(super) fn cube(s: &mut SavedSurface, min: [f64; 3], size: f64, n: usize) {
    let mut index: HashMap<[usize; 3], usize> = HashMap::new();
    let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
    for axis in 0..3 {
        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in [0, n] {
            for i in 0..n {
                for j in 0..n {
                    let mut corner = |di: usize, dj: usize| {
                        let mut l = [0; 3];
                        (l[axis], l[u], l[w]) = (side, i + di, j + dj);
                        *index.entry(l).or_insert_with(|| {
                            vertices.push(std::array::from_fn(|k| {
                                min[k] + size * l[k] as f64 / n as f64
                            }));
                            vertices.len() - 1
                        })
                    };
                    let (c00, c10, c11, c01) =
                        (corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1));
                    // (c00, c10, c11) has normal e_u × e_w = +e_axis.
                    if side == n {
                        triangles.extend([[c00, c10, c11], [c00, c11, c01]]);
                    } else {
                        triangles.extend([[c00, c11, c10], [c00, c01, c11]]);
                    }
                }
            }
        }
    }
    add(s, &vertices, &[], &triangles);
}

/// The OBJ text elasto writes: coordinates printed from `f32`.
pub(super) fn to_obj(s: &SavedSurface) -> String {
    let mut text = String::from("# test surface\n");
    for p in &s.vertices {
        let [x, y, z] = p.map(|c| c as f32);
        text.push_str(&format!("v {x} {y} {z}\n"));
    }
    for [a, b] in &s.segments {
        text.push_str(&format!("l {} {}\n", a + 1, b + 1));
    }
    for [a, b, c] in &s.triangles {
        text.push_str(&format!("f {} {} {}\n", a + 1, b + 1, c + 1));
    }
    text
}

pub(super) fn temp_file(name: &str, text: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("elasto_intersection_{}_{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("surface.obj");
    std::fs::write(&path, text).unwrap();
    path
}

/// Saved by elasto's rules and read back.
pub(super) fn saved(s: &SavedSurface, name: &str) -> SavedSurface {
    let path = temp_file(name, &to_obj(s));
    let read = SavedSurface::read_obj(&path).unwrap();
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
    read
}

pub(super) fn vertex_at(s: &SavedSurface, p: [f64; 3]) -> usize {
    s.vertices.iter().position(|&v| v == p).unwrap()
}
