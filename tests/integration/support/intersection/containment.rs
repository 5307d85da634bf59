//! Containment: one vertex per component against every other closed
//! component, by winding numbers (see the parent module's documentation).

use super::geometry::{cross, dot, norm, orient2d, sub};
use super::{Intersection, SavedSurface};

/// Components lying inside others (see the module doc).
pub(super) fn containment(surface: &SavedSurface) -> Vec<Intersection> {
    let component = surface.components();
    let count = component.iter().max().map_or(0, |&c| c + 1);
    let v = &surface.vertices;
    let three_d = !surface.triangles.is_empty();
    let mut facets: Vec<Vec<Vec<usize>>> = vec![Vec::new(); count];
    if three_d {
        for t in &surface.triangles {
            facets[component[t[0]]].push(t.to_vec());
        }
    } else {
        for s in &surface.segments {
            facets[component[s[0]]].push(s.to_vec());
        }
    }
    let closed: Vec<bool> = facets
        .iter()
        .map(|f| !f.is_empty() && is_closed(f))
        .collect();
    let mut first_vertex = vec![usize::MAX; count];
    for (vertex, &c) in component.iter().enumerate().rev() {
        first_vertex[c] = vertex;
    }
    let winding = |p: [f64; 3], f: &[Vec<usize>]| {
        if three_d {
            winding_number_3d(p, f, v)
        } else {
            winding_number_2d(p, f, v)
        }
    };
    let mut found = Vec::new();
    for inner in (0..count).filter(|&c| !facets[c].is_empty()) {
        let vertex = first_vertex[inner];
        if closed[inner] && signed_measure(&facets[inner], v, v[vertex]) <= 0.0 {
            continue; // a hole: the inside wall of a hollow body
        }
        let obstacle = |c: usize| surface.is_obstacle(first_vertex[c]);
        let windings: Vec<(usize, f64)> = (0..count)
            .filter(|&outer| outer != inner && closed[outer])
            .filter(|&outer| !(obstacle(inner) && obstacle(outer)))
            .map(|outer| (outer, winding(v[vertex], &facets[outer])))
            .collect();
        if windings.iter().map(|w| w.1).sum::<f64>() > 0.5 {
            let outside_of = windings.iter().filter(|w| w.1 > 0.5);
            found.extend(outside_of.map(|&(outer, _)| Intersection::Contained {
                inner,
                outer,
                vertex,
            }));
        }
    }
    found
}

/// Whether oriented facets close up: 2D edges start at each vertex as often
/// as they end there; 3D directed edges equal their reverses as multisets.
pub(super) fn is_closed(facets: &[Vec<usize>]) -> bool {
    let (mut forward, mut backward) = (Vec::new(), Vec::new());
    for f in facets {
        if f.len() == 2 {
            forward.push((f[0], 0));
            backward.push((f[1], 0));
        } else {
            for k in 0..f.len() {
                let (a, b) = (f[k], f[(k + 1) % f.len()]);
                forward.push((a, b));
                backward.push((b, a));
            }
        }
    }
    forward.sort_unstable();
    backward.sort_unstable();
    forward == backward
}

/// Signed area (2D, Σ (a × b) / 2) or volume (3D, Σ a · (b × c) / 6), with
/// positions taken relative to `origin`.
pub(super) fn signed_measure(facets: &[Vec<usize>], v: &[[f64; 3]], origin: [f64; 3]) -> f64 {
    let at = |i: usize| sub(v[i], origin);
    facets
        .iter()
        .map(|f| match f[..] {
            [a, b] => orient2d([0.0; 3], at(a), at(b)) / 2.0,
            [a, b, c] => dot(at(a), cross(at(b), at(c))) / 6.0,
            _ => 0.0,
        })
        .sum()
}

/// Winding number of a closed oriented polyline around p, by signed crossings
/// of the ray from p towards +x (half-open in y, so vertices count once).
fn winding_number_2d(p: [f64; 3], segments: &[Vec<usize>], v: &[[f64; 3]]) -> f64 {
    let mut winding = 0i64;
    for s in segments {
        let (a, b) = (v[s[0]], v[s[1]]);
        if a[1] <= p[1] {
            if b[1] > p[1] && orient2d(a, b, p) > 0.0 {
                winding += 1;
            }
        } else if b[1] <= p[1] && orient2d(a, b, p) < 0.0 {
            winding -= 1;
        }
    }
    winding as f64
}

/// Generalised winding number `Σ Ω / (4π)` of closed oriented triangles
/// around p (van Oosterom–Strackee solid angles).
pub(super) fn winding_number_3d(p: [f64; 3], triangles: &[Vec<usize>], v: &[[f64; 3]]) -> f64 {
    let total: f64 = triangles
        .iter()
        .map(|t| {
            let (a, b, c) = (sub(v[t[0]], p), sub(v[t[1]], p), sub(v[t[2]], p));
            let (la, lb, lc) = (norm(a), norm(b), norm(c));
            let numerator = dot(a, cross(b, c));
            let denominator = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
            2.0 * numerator.atan2(denominator)
        })
        .sum();
    total / (4.0 * std::f64::consts::PI)
}
