//! The exact predicates and distances of the checker, on `[f64; 3]` points:
//! orientations, 2D segment contact, 3D edge against triangle (see the
//! crossings in the parent module's documentation), and the closest-point
//! distances [`super::find_intersections_within`] compares with its tolerance.

// ---- vectors -------------------------------------------------------------

pub(super) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub(super) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub(super) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn along(a: [f64; 3], d: [f64; 3], t: f64) -> [f64; 3] {
    [a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]]
}
pub(super) fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
/// The point with z dropped (2D segments are judged in the plane).
pub(super) fn flat(a: [f64; 3]) -> [f64; 3] {
    [a[0], a[1], 0.0]
}
fn sign(x: f64) -> i8 {
    (x > 0.0) as i8 - (x < 0.0) as i8
}

// ---- 2D segments ---------------------------------------------------------

/// `(b − a) × (c − a)` in the xy-plane: > 0 when c is left of ab.
pub(super) fn orient2d(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Whether c, known to be on the line ab, lies in the closed segment ab.
fn in_box(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> bool {
    (0..2).all(|k| a[k].min(b[k]) <= c[k] && c[k] <= a[k].max(b[k]))
}

/// A point common to the closed segments ab and cd (xy only), if any.
pub(super) fn segment_contact_2d(
    a: [f64; 3],
    b: [f64; 3],
    c: [f64; 3],
    d: [f64; 3],
) -> Option<[f64; 2]> {
    let (abc, abd) = (orient2d(a, b, c), orient2d(a, b, d));
    let (cda, cdb) = (orient2d(c, d, a), orient2d(c, d, b));
    if sign(abc) * sign(abd) < 0 && sign(cda) * sign(cdb) < 0 {
        let p = along(a, sub(b, a), cda / (cda - cdb));
        return Some([p[0], p[1]]);
    }
    let touch = [
        (abc, a, b, c),
        (abd, a, b, d),
        (cda, c, d, a),
        (cdb, c, d, b),
    ];
    touch
        .into_iter()
        .find(|&(o, s, e, p)| o == 0.0 && in_box(s, e, p))
        .map(|(_, _, _, p)| [p[0], p[1]])
}

// ---- 3D edge against triangle --------------------------------------------

/// `((b − a) × (c − a)) · (d − a)`: six times the signed volume of abcd.
fn orient3d(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> f64 {
    dot(cross(sub(b, a), sub(c, a)), sub(d, a))
}

/// Whether the closed segment pq meets the closed triangle abc.
pub(super) fn edge_meets_triangle(p: [f64; 3], q: [f64; 3], [a, b, c]: [[f64; 3]; 3]) -> bool {
    let normal = cross(sub(b, a), sub(c, a));
    if normal == [0.0; 3] {
        return false;
    }
    let (side_p, side_q) = (sign(dot(normal, sub(p, a))), sign(dot(normal, sub(q, a))));
    if side_p * side_q > 0 {
        return false;
    }
    let signs = [
        orient3d(p, q, a, b),
        orient3d(p, q, b, c),
        orient3d(p, q, c, a),
    ]
    .map(sign);
    // All three volumes zero: the edge lies in the triangle's plane, whatever
    // rounding made of `side_p` and `side_q` (a hair off zero): the 2D test.
    if (side_p == 0 && side_q == 0) || signs == [0; 3] {
        // Coplanar: work in the plane of the two axes other than the normal's largest.
        let drop = (0..3)
            .max_by(|&i, &j| normal[i].abs().total_cmp(&normal[j].abs()))
            .unwrap_or(2);
        let keep = |x: [f64; 3]| [x[(drop + 1) % 3], x[(drop + 2) % 3], 0.0];
        let (p, q, a, b, c) = (keep(p), keep(q), keep(a), keep(b), keep(c));
        let signs = [orient2d(a, b, p), orient2d(b, c, p), orient2d(c, a, p)].map(sign);
        let inside = !(signs.contains(&1) && signs.contains(&-1));
        return inside
            || [(a, b), (b, c), (c, a)]
                .iter()
                .any(|&(s, e)| segment_contact_2d(p, q, s, e).is_some());
    }
    !(signs.contains(&1) && signs.contains(&-1))
}

/// The point of segment ab closest to p.
fn point_segment_closest(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    let d = sub(b, a);
    let length2 = dot(d, d);
    let t = if length2 > 0.0 {
        (dot(sub(p, a), d) / length2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    along(a, d, t)
}

/// The distance between segments pq and rs and the midpoint of the closest
/// points: the least over the four endpoint–segment pairs and, when the lines
/// are not parallel, the interior stationary point of `|p + s(q−p) − r − t(s−r)|²`,
/// `s = (b e − c d) / (a c − b²)`, `t = (a e − b d) / (a c − b²)`.
pub(super) fn segment_segment_closest(
    p: [f64; 3],
    q: [f64; 3],
    r: [f64; 3],
    s: [f64; 3],
) -> (f64, [f64; 3]) {
    let pair = |x: [f64; 3], y: [f64; 3]| (norm(sub(x, y)), along(x, sub(y, x), 0.5));
    let mut best = [
        pair(p, point_segment_closest(p, r, s)),
        pair(q, point_segment_closest(q, r, s)),
        pair(r, point_segment_closest(r, p, q)),
        pair(s, point_segment_closest(s, p, q)),
    ]
    .into_iter()
    .min_by(|x, y| x.0.total_cmp(&y.0))
    .unwrap_or((f64::INFINITY, p));
    let (d1, d2, w) = (sub(q, p), sub(s, r), sub(p, r));
    let (a, b, c, d, e) = (
        dot(d1, d1),
        dot(d1, d2),
        dot(d2, d2),
        dot(d1, w),
        dot(d2, w),
    );
    let denominator = a * c - b * b;
    if denominator > 1e-14 * a * c {
        let (u, t) = ((b * e - c * d) / denominator, (a * e - b * d) / denominator);
        if (0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&t) {
            let interior = pair(along(p, d1, u), along(r, d2, t));
            if interior.0 < best.0 {
                best = interior;
            }
        }
    }
    best
}

/// The distance from p to triangle abc: to its plane when the foot falls
/// inside, else to the nearest edge.
fn point_triangle_distance(p: [f64; 3], [a, b, c]: [[f64; 3]; 3]) -> f64 {
    let normal = cross(sub(b, a), sub(c, a));
    let area2 = dot(normal, normal);
    if area2 > 0.0 {
        let height = dot(normal, sub(p, a)) / area2;
        let foot = along(p, normal, -height);
        let sides =
            [(a, b), (b, c), (c, a)].map(|(s, e)| dot(cross(sub(e, s), sub(foot, s)), normal));
        if sides.iter().all(|&x| x >= 0.0) {
            return height.abs() * area2.sqrt();
        }
    }
    [(a, b), (b, c), (c, a)]
        .map(|(s, e)| norm(sub(p, point_segment_closest(p, s, e))))
        .into_iter()
        .fold(f64::INFINITY, f64::min)
}

/// The distance between segment pq and triangle abc that it does not meet.
pub(super) fn segment_triangle_distance(
    p: [f64; 3],
    q: [f64; 3],
    corners @ [a, b, c]: [[f64; 3]; 3],
) -> f64 {
    let to_edges = [(a, b), (b, c), (c, a)].map(|(s, e)| segment_segment_closest(p, q, s, e).0);
    to_edges
        .into_iter()
        .chain([
            point_triangle_distance(p, corners),
            point_triangle_distance(q, corners),
        ])
        .fold(f64::INFINITY, f64::min)
}
