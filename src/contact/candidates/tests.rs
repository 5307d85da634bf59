use super::*;
use crate::mesh::Mesh;

/// Two stacked boxes, `gap` apart, as one collision mesh.
fn stacked<const D: usize>(cells: usize, gap: f64) -> (CollisionMesh, Vec<Vector<D>>) {
    let unit =
        Mesh::axis_aligned_box(Vector::<D>::zeros(), Vector::<D>::repeat(1.0), [cells; D]).unwrap();
    let n = unit.vertex_count();
    let mut lift = Vector::<D>::zeros();
    lift[1] = 1.0 + gap;
    let mut positions = unit.rest_positions().to_vec();
    positions.extend(unit.rest_positions().iter().map(|p| p + lift));
    let mut simplices: Vec<Vec<usize>> = unit.simplices().map(<[usize]>::to_vec).collect();
    simplices.extend(unit.simplices().map(|s| s.iter().map(|v| v + n).collect()));
    let mesh = Mesh::new(positions.clone(), simplices).unwrap();
    let owner: Vec<usize> = (0..2 * n).map(|v| v / n).collect();
    (CollisionMesh::new(&mesh, &owner), positions)
}

/// A deterministic pseudo-random number in [-1, 1).
fn noise(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// Every pair of primitives (not sharing a vertex) whose boxes over the
/// query, grown by `activation / 2`, overlap: the broad phase's answer by
/// brute force, in the finder's order.
fn box_pairs<const D: usize>(
    mesh: &CollisionMesh,
    x: &[Vector<D>],
    dx: Option<&[Vector<D>]>,
    activation: f64,
) -> Vec<ContactStencil> {
    let box_of = |corners: &[usize]| {
        corners.iter().fold(Aabb::<D>::empty(), |b, &v| {
            let b = b.union_point(&x[v]);
            dx.map_or(b, |dx| b.union_point(&(x[v] + dx[v])))
        })
    };
    let near = |a: &[usize], b: &[usize]| {
        !a.iter().any(|v| b.contains(v))
            && box_of(a)
                .inflated(activation / 2.0)
                .overlaps(&box_of(b).inflated(activation / 2.0))
    };
    let mut out = Vec::new();
    let (vertices, edges, faces) = (mesh.vertices(), mesh.edges(), mesh.faces());
    for (s, &vertex) in vertices.iter().enumerate() {
        if D == 2 {
            for (e, edge) in edges.iter().enumerate() {
                if near(&[vertex], edge) {
                    out.push(point_edge(mesh, s as u32, e as u32));
                }
            }
        } else {
            for (f, face) in faces.iter().enumerate() {
                if near(&[vertex], face) {
                    out.push(point_triangle(mesh, s as u32, f as u32));
                }
            }
        }
    }
    if D == 3 {
        for a in 0..edges.len() {
            for b in a + 1..edges.len() {
                if near(&edges[a], &edges[b]) {
                    out.push(edge_edge(mesh, a as u32, b as u32));
                }
            }
        }
    }
    out
}

/// The smallest distance of `stencil` over `x -> x + dx`, sampled at 17
/// points (the end points included).
fn closest_on_segment<const D: usize>(
    stencil: &ContactStencil,
    x: &[Vector<D>],
    dx: Option<&[Vector<D>]>,
) -> f64 {
    let Some(dx) = dx else {
        return stencil.distance_squared(x).sqrt();
    };
    (0..=16)
        .map(|k| {
            let t = k as f64 / 16.0;
            let y: Vec<Vector<D>> = x.iter().zip(dx).map(|(p, d)| p + d * t).collect();
            stencil.distance_squared(&y).sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Over a walk of small and large moves, static and swept, with the two
/// boxes deforming and translating: every answer is a part of the broad
/// phase's answer (brute force), in its order, and holds every pair of it
/// that comes within `d_hat` on the query; small moves are answered from
/// the cache.
fn answers_hold_every_near_pair<const D: usize>() {
    let activation = 0.05;
    let (mesh, mut x) = stacked::<D>(3, 0.03);
    let mut finder = CandidateFinder::<D>::default();
    let mut seed = 7;
    let mut out = Vec::new();
    let (mut queries, mut near_pairs) = (0, 0);
    for step in 0..60 {
        // Mostly moves well below the margin, over a translation of each
        // box of its own; every 10th a jump.
        let size = if step % 10 == 9 { 0.3 } else { 0.004 };
        let drift: [Vector<D>; 2] =
            std::array::from_fn(|_| Vector::<D>::from_fn(|_, _| 0.02 * noise(&mut seed)));
        let half = x.len() / 2;
        let dx: Vec<Vector<D>> = (0..x.len())
            .map(|v| drift[v / half] + Vector::<D>::from_fn(|_, _| size * noise(&mut seed)))
            .collect();
        for motion in [None, Some(dx.as_slice())] {
            finder.find(&mesh, &x, motion, activation, true, &mut out);
            let all = box_pairs(&mesh, &x, motion, activation);
            let mut rest = all.iter();
            for stencil in &out {
                assert!(
                    rest.any(|s| s == stencil),
                    "query {step} ({}): {stencil:?} is not a box pair, or out of order",
                    if motion.is_some() { "swept" } else { "static" }
                );
            }
            for stencil in &all {
                if closest_on_segment(stencil, &x, motion) <= activation {
                    near_pairs += 1;
                    assert!(out.contains(stencil), "query {step}: {stencil:?} missing");
                }
            }
            queries += 1;
        }
        for (p, d) in x.iter_mut().zip(&dx) {
            *p += d * 0.5;
        }
    }
    assert!(near_pairs > 0, "the walk never brought a pair near");
    assert!(
        finder.searches() < queries / 3,
        "{} grid searches for {queries} queries",
        finder.searches()
    );
}

#[test]
fn answers_hold_every_near_pair_in_2d() {
    answers_hold_every_near_pair::<2>();
}

#[test]
fn answers_hold_every_near_pair_in_3d() {
    answers_hold_every_near_pair::<3>();
}

/// Right after a search, a static query answers exactly the box pairs
/// within `d_hat`; and a body that moves as a whole, by far more than
/// `d_hat` per query, keeps its own far pairs out of the answer: only pairs
/// between the two boxes, which come within `d_hat`, remain.
fn a_translated_body_keeps_its_far_pairs_out<const D: usize>() {
    let activation = 0.05;
    let (mesh, x) = stacked::<D>(3, 0.03);
    let mut finder = CandidateFinder::<D>::default();
    let mut out = Vec::new();
    finder.find(&mesh, &x, None, activation, true, &mut out);
    let within: Vec<_> = box_pairs(&mesh, &x, None, activation)
        .into_iter()
        .filter(|s| s.distance_squared(&x).sqrt() <= activation)
        .collect();
    assert!(!within.is_empty());
    assert_eq!(out, within);
    let fall = vec![Vector::<D>::from_fn(|k, _| [0.01, -0.5, 0.03][k]); x.len()];
    finder.find(&mesh, &x, Some(&fall), activation, true, &mut out);
    let between_bodies = |s: &ContactStencil| {
        let bodies: Vec<_> = s.corners().iter().map(|&v| mesh.body_of(v)).collect();
        bodies.iter().any(|b| *b != bodies[0])
    };
    assert!(!out.is_empty());
    assert!(out.iter().all(between_bodies), "{out:?}");
    let all = box_pairs(&mesh, &x, Some(&fall), activation);
    // ... though the boxes of some of its own pairs overlap all along the fall.
    assert!(all.iter().any(|s| !between_bodies(s)));
}

#[test]
fn a_translated_body_keeps_its_far_pairs_out_in_2d() {
    a_translated_body_keeps_its_far_pairs_out::<2>();
}

#[test]
fn a_translated_body_keeps_its_far_pairs_out_in_3d() {
    a_translated_body_keeps_its_far_pairs_out::<3>();
}

/// A position that is not a number poisons its body's mean motion: the
/// certificate then drops none of that body's pairs (the boxes decide,
/// as without it), so a far pair between finite vertices of that body
/// stays a candidate where its boxes overlap.
#[test]
fn a_position_that_is_not_a_number_drops_no_pair() {
    let activation = 0.05;
    let (mesh, x) = stacked::<3>(3, 0.03);
    let mut finder = CandidateFinder::<3>::default();
    let mut out = Vec::new();
    finder.find(&mesh, &x, None, activation, true, &mut out);
    let mut fall = vec![Vector::<3>::new(0.0, -0.5, 0.0); x.len()];
    fall[0] = Vector::<3>::new(f64::NAN, 0.0, 0.0);
    finder.find(&mesh, &x, Some(&fall), activation, true, &mut out);
    // The pairs of the poisoned body (the first box) between finite vertices.
    let finite = |s: &ContactStencil| {
        s.corners()
            .iter()
            .all(|&v| v < x.len() / 2 && x[v].iter().chain(fall[v].iter()).all(|c| c.is_finite()))
    };
    let expected: Vec<_> = box_pairs(&mesh, &x, Some(&fall), activation)
        .into_iter()
        .filter(finite)
        .collect();
    let got: Vec<_> = out.into_iter().filter(finite).collect();
    assert!(expected.len() > 10, "{}", expected.len());
    assert!(got == expected, "{} of {} kept", got.len(), expected.len());
}
