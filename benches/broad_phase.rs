//! Cost of the contact broad phase on two stacked wavy sheets of triangles.
//!
//! Run with `cargo bench --bench broad_phase`. Two sheets of `n x 5n/8` quads (two
//! triangles each) over `[0, 1] x [0, 0.625]`, the same wave `z0(x, y)`, the
//! upper one lifted by a gap growing from `0.5 d_hat` at `x = 0` to
//! `2.5 d_hat` at `x = 1`, with `d_hat = 1e-3`; `2.5 n^2` triangles in all
//! (25k, 100k, 400k for n = 100, 200, 400). For each size, the median time
//! over several runs of the four queries of a 3D contact step, with the
//! realistic filter (no pair sharing a vertex):
//!
//! - vertices vs triangles and edges vs edges at a state `x` (Newton iterate);
//! - the same with swept boxes over `x -> x + dx`, the upper sheet moving
//!   down by `0.4 d_hat` with a small sideways wobble (line search);
//! - the same swept, with the upper sheet falling fast, by `0.05` (20 mesh
//!   spacings at n = 400): boxes far larger than the median.
//!
//! Set `ELASTO_BENCH_QUICK=1` for the two smaller sizes only.

use elasto::contact::broad_phase::{Aabb, BroadPhase};
use elasto::math::{Vector, Vector3};
use std::time::Instant;

const D_HAT: f64 = 1e-3;
const RUNS: usize = 7;

/// Vertices, triangles and edges of the two sheets.
struct Surface {
    x: Vec<Vector<3>>,
    faces: Vec<[usize; 3]>,
    edges: Vec<[usize; 2]>,
    /// Number of vertices of the lower sheet (the upper ones follow).
    lower: usize,
}

fn sheets(n: usize) -> Surface {
    let (nx, ny) = (n, 5 * n / 8);
    let wave = |x: f64, y: f64| {
        0.02 * (6.0 * std::f64::consts::PI * x).sin() * (4.0 * std::f64::consts::PI * y).sin()
    };
    let (mut x, mut faces, mut edges) = (Vec::new(), Vec::new(), Vec::new());
    for sheet in 0..2 {
        let base = x.len();
        for j in 0..=ny {
            for i in 0..=nx {
                let (u, v) = (i as f64 / nx as f64, j as f64 * 0.625 / ny as f64);
                let lift = if sheet == 0 {
                    0.0
                } else {
                    D_HAT * (0.5 + 2.0 * u)
                };
                x.push(Vector3::new(u, v, wave(u, v) + lift));
            }
        }
        let id = |i: usize, j: usize| base + j * (nx + 1) + i;
        for j in 0..=ny {
            for i in 0..=nx {
                if i < nx {
                    edges.push([id(i, j), id(i + 1, j)]);
                }
                if j < ny {
                    edges.push([id(i, j), id(i, j + 1)]);
                }
                if i < nx && j < ny {
                    edges.push([id(i, j), id(i + 1, j + 1)]);
                    faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                    faces.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
                }
            }
        }
    }
    let lower = x.len() / 2;
    Surface {
        x,
        faces,
        edges,
        lower,
    }
}

fn boxes<const K: usize>(
    prims: &[[usize; K]],
    x: &[Vector<3>],
    dx: Option<&[Vector<3>]>,
    out: &mut Vec<Aabb<3>>,
) {
    out.clear();
    out.extend(prims.iter().map(|p| {
        let start = p.map(|v| x[v]);
        match dx {
            Some(dx) => Aabb::swept(&start, &p.map(|v| x[v] + dx[v])),
            None => Aabb::of_points(&start),
        }
    }));
}

fn median(mut times: Vec<f64>) -> f64 {
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn main() {
    let quick = std::env::var_os("ELASTO_BENCH_QUICK").is_some();
    let sizes: &[usize] = if quick { &[100, 200] } else { &[100, 200, 400] };
    println!(
        "{:>8} {:>8} {:>8} | {:<9} {:>10} {:>9} {:>10} {:>9}",
        "faces", "edges", "verts", "boxes", "vt ms", "vt pairs", "ee ms", "ee pairs"
    );
    for &n in sizes {
        let s = sheets(n);
        let vertices: Vec<[usize; 1]> = (0..s.x.len()).map(|v| [v]).collect();
        let slow: Vec<Vector<3>> = (0..s.x.len())
            .map(|v| {
                if v < s.lower {
                    Vector::zeros()
                } else {
                    Vector3::new(
                        1e-4 * (v as f64).sin(),
                        1e-4 * (v as f64).cos(),
                        -0.4 * D_HAT,
                    )
                }
            })
            .collect();
        let fast: Vec<Vector<3>> = slow
            .iter()
            .map(|d| {
                if d.z == 0.0 {
                    *d
                } else {
                    Vector3::new(d.x, d.y, -0.05)
                }
            })
            .collect();
        let mut phase = BroadPhase::<3>::new();
        let (mut vb, mut fb, mut eb, mut pairs) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (label, dx) in [
            ("at x", None),
            ("swept", Some(&slow[..])),
            ("fast", Some(&fast[..])),
        ] {
            boxes(&vertices, &s.x, dx, &mut vb);
            boxes(&s.faces, &s.x, dx, &mut fb);
            boxes(&s.edges, &s.x, dx, &mut eb);
            let vertex_face = |v: usize, f: usize| !s.faces[f].contains(&v);
            let edge_edge = |a: usize, b: usize| !s.edges[a].iter().any(|v| s.edges[b].contains(v));
            let (mut vt, mut ee) = (Vec::new(), Vec::new());
            let (mut vt_pairs, mut ee_pairs) = (0, 0);
            for _ in 0..RUNS {
                let t = Instant::now();
                phase.pairs_between(&vb, &fb, D_HAT, vertex_face, &mut pairs);
                vt.push(t.elapsed().as_secs_f64() * 1e3);
                vt_pairs = pairs.len();
                let t = Instant::now();
                phase.pairs_within(&eb, D_HAT, edge_edge, &mut pairs);
                ee.push(t.elapsed().as_secs_f64() * 1e3);
                ee_pairs = pairs.len();
            }
            println!(
                "{:>8} {:>8} {:>8} | {:<9} {:>10.2} {:>9} {:>10.2} {:>9}",
                s.faces.len(),
                s.edges.len(),
                s.x.len(),
                label,
                median(vt),
                vt_pairs,
                median(ee),
                ee_pairs
            );
        }
    }
}
