//! 3D point-triangle squared distance: classification by the edges'
//! in-plane normals (ipctk's rule), then point-point, point-line or
//! point-plane.

use super::StencilDerivatives;
use super::primitives::{
    point_line_derivatives_3d, point_line_distance_squared, point_plane_derivatives,
    point_plane_distance_squared, point_point_derivatives, point_point_distance_squared,
};
use crate::math::Vector3;

/// Which feature of the triangle `(t0, t1, t2)` is closest to the point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointTriangleDistanceType {
    /// The vertex `t0`.
    PointT0,
    /// The vertex `t1`.
    PointT1,
    /// The vertex `t2`.
    PointT2,
    /// The interior of the edge `(t0, t1)`.
    PointEdge01,
    /// The interior of the edge `(t1, t2)`.
    PointEdge12,
    /// The interior of the edge `(t2, t0)`.
    PointEdge20,
    /// The triangle's interior: the distance is the point-plane distance.
    PointTriangle,
}

/// The edges `(start, end)` in the order `(t0, t1)`, `(t1, t2)`, `(t2, t0)`,
/// with their types.
const EDGES: [(usize, usize, PointTriangleDistanceType); 3] = [
    (0, 1, PointTriangleDistanceType::PointEdge01),
    (1, 2, PointTriangleDistanceType::PointEdge12),
    (2, 0, PointTriangleDistanceType::PointEdge20),
];

/// ipctk's classification. For each edge `(a, b)` (in the order of
/// [`PointTriangleDistanceType`]), with `e = b - a` and the triangle normal
/// `n = (t1 - t0) x (t2 - t0)`: the parameter `s = e . (p - a) / |e|^2` of
/// the projection on the edge's line and the side `o = (e x n) . (p - a)`
/// (`e x n` is the edge's outward in-plane normal). The first edge with
/// `0 < s < 1` and `o >= 0` is the closest feature; otherwise vertex `a` is
/// closest when `s <= 0` on its outgoing edge and `s >= 1` on its incoming
/// one; otherwise the point projects inside the triangle.
pub fn point_triangle_distance_type(
    p: &Vector3,
    t0: &Vector3,
    t1: &Vector3,
    t2: &Vector3,
) -> PointTriangleDistanceType {
    let t = [t0, t1, t2];
    let normal = (t1 - t0).cross(&(t2 - t0));
    let mut along = [0.0; 3];
    for (k, &(a, b, edge_type)) in EDGES.iter().enumerate() {
        let e = t[b] - t[a];
        let r = p - t[a];
        along[k] = e.dot(&r) / e.norm_squared();
        let outside = e.cross(&normal).dot(&r) >= 0.0;
        if along[k] > 0.0 && along[k] < 1.0 && outside {
            return edge_type;
        }
    }
    if along[0] <= 0.0 && along[2] >= 1.0 {
        PointTriangleDistanceType::PointT0
    } else if along[1] <= 0.0 && along[0] >= 1.0 {
        PointTriangleDistanceType::PointT1
    } else if along[2] <= 0.0 && along[1] >= 1.0 {
        PointTriangleDistanceType::PointT2
    } else {
        PointTriangleDistanceType::PointTriangle
    }
}

/// The squared distance from `p` to the triangle `(t0, t1, t2)`.
pub fn point_triangle_distance_squared(
    p: &Vector3,
    t0: &Vector3,
    t1: &Vector3,
    t2: &Vector3,
) -> f64 {
    use PointTriangleDistanceType as T;
    match point_triangle_distance_type(p, t0, t1, t2) {
        T::PointT0 => point_point_distance_squared(p, t0),
        T::PointT1 => point_point_distance_squared(p, t1),
        T::PointT2 => point_point_distance_squared(p, t2),
        T::PointEdge01 => point_line_distance_squared(p, t0, t1),
        T::PointEdge12 => point_line_distance_squared(p, t1, t2),
        T::PointEdge20 => point_line_distance_squared(p, t2, t0),
        T::PointTriangle => point_plane_distance_squared(p, t0, t1, t2),
    }
}

/// [`point_triangle_distance_squared`] with its gradient and Hessian over
/// `(p, t0, t1, t2)`.
pub fn point_triangle_distance_squared_derivatives(
    p: &Vector3,
    t0: &Vector3,
    t1: &Vector3,
    t2: &Vector3,
) -> StencilDerivatives<12> {
    use PointTriangleDistanceType as T;
    match point_triangle_distance_type(p, t0, t1, t2) {
        T::PointT0 => point_point_derivatives(p, t0, [0, 1]),
        T::PointT1 => point_point_derivatives(p, t1, [0, 2]),
        T::PointT2 => point_point_derivatives(p, t2, [0, 3]),
        T::PointEdge01 => point_line_derivatives_3d(p, t0, t1, [0, 1, 2]),
        T::PointEdge12 => point_line_derivatives_3d(p, t1, t2, [0, 2, 3]),
        T::PointEdge20 => point_line_derivatives_3d(p, t2, t0, [0, 3, 1]),
        T::PointTriangle => point_plane_derivatives(p, t0, t1, t2),
    }
}

/// Barycentric coordinates `(b1, b2)` of the triangle's point closest to
/// `p` (that point is `t0 + b1 (t1 - t0) + b2 (t2 - t0)`), following
/// [`point_triangle_distance_type`]: a vertex's corner, the clamped
/// projection on an edge, or, inside, the solution of
/// `[e1.e1 e1.e2; e1.e2 e2.e2] (b1, b2) = (e1.r, e2.r)` with
/// `e1 = t1 - t0`, `e2 = t2 - t0`, `r = p - t0` (determinant
/// `|e1 x e2|^2`).
pub fn point_triangle_closest_barycentric(
    p: &Vector3,
    t0: &Vector3,
    t1: &Vector3,
    t2: &Vector3,
) -> (f64, f64) {
    use PointTriangleDistanceType as T;
    let along = |a: &Vector3, b: &Vector3| {
        let e = b - a;
        (e.dot(&(p - a)) / e.norm_squared()).clamp(0.0, 1.0)
    };
    match point_triangle_distance_type(p, t0, t1, t2) {
        T::PointT0 => (0.0, 0.0),
        T::PointT1 => (1.0, 0.0),
        T::PointT2 => (0.0, 1.0),
        T::PointEdge01 => (along(t0, t1), 0.0),
        T::PointEdge12 => {
            let s = along(t1, t2);
            (1.0 - s, s)
        }
        T::PointEdge20 => (0.0, 1.0 - along(t2, t0)),
        T::PointTriangle => {
            let (e1, e2, r) = (t1 - t0, t2 - t0, p - t0);
            let (a11, a12, a22) = (e1.norm_squared(), e1.dot(&e2), e2.norm_squared());
            let (r1, r2) = (e1.dot(&r), e2.dot(&r));
            let determinant = e1.cross(&e2).norm_squared();
            (
                (a22 * r1 - a12 * r2) / determinant,
                (a11 * r2 - a12 * r1) / determinant,
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::primitives::point_line_derivatives_3d;
    use super::super::test_support::{Rng, check_finite_differences, point, stack};
    use super::*;
    use PointTriangleDistanceType as T;
    use nalgebra::SVector;

    fn value(x: &SVector<f64, 12>) -> f64 {
        point_triangle_distance_squared(&point(x, 0), &point(x, 1), &point(x, 2), &point(x, 3))
    }

    fn derivatives(x: &SVector<f64, 12>) -> StencilDerivatives<12> {
        point_triangle_distance_squared_derivatives(
            &point(x, 0),
            &point(x, 1),
            &point(x, 2),
            &point(x, 3),
        )
    }

    /// A random triangle that is not too thin.
    fn triangle(rng: &mut Rng) -> [Vector3; 3] {
        loop {
            let t = [rng.vector3(1.0), rng.vector3(1.0), rng.vector3(1.0)];
            let e = [t[1] - t[0], t[2] - t[1], t[0] - t[2]];
            let area2 = e[0].cross(&e[1]).norm();
            if e.iter().all(|e| area2 > 0.4 * e.norm_squared()) {
                return t;
            }
        }
    }

    /// Outward in-plane unit normal of edge `k` (`t[k] -> t[k+1]`).
    fn outward(t: &[Vector3; 3], k: usize) -> Vector3 {
        let normal = (t[1] - t[0]).cross(&(t[2] - t[0]));
        (t[(k + 1) % 3] - t[k]).cross(&normal).normalize()
    }

    /// A point whose closest feature is `expected`, at a random height.
    fn point_in_region(rng: &mut Rng, t: &[Vector3; 3], expected: T) -> Vector3 {
        let unit_normal = (t[1] - t[0]).cross(&(t[2] - t[0])).normalize();
        let height = unit_normal * rng.uniform(-0.5, 0.5);
        let vertex = |k: usize, rng: &mut Rng| {
            let (before, after) = (outward(t, (k + 2) % 3), outward(t, k));
            t[k] + before * rng.uniform(0.05, 0.5) + after * rng.uniform(0.05, 0.5)
        };
        let edge = |k: usize, rng: &mut Rng| {
            let s = rng.uniform(0.05, 0.95);
            t[k] + (t[(k + 1) % 3] - t[k]) * s + outward(t, k) * rng.uniform(0.05, 0.5)
        };
        height
            + match expected {
                T::PointT0 => vertex(0, rng),
                T::PointT1 => vertex(1, rng),
                T::PointT2 => vertex(2, rng),
                T::PointEdge01 => edge(0, rng),
                T::PointEdge12 => edge(1, rng),
                T::PointEdge20 => edge(2, rng),
                T::PointTriangle => {
                    let b1 = rng.uniform(0.05, 0.9);
                    let b2 = rng.uniform(0.05, 0.95 - b1);
                    t[0] + (t[1] - t[0]) * b1 + (t[2] - t[0]) * b2
                }
            }
    }

    const ALL_TYPES: [T; 7] = [
        T::PointT0,
        T::PointT1,
        T::PointT2,
        T::PointEdge01,
        T::PointEdge12,
        T::PointEdge20,
        T::PointTriangle,
    ];

    #[test]
    fn derivatives_match_finite_differences_for_every_type() {
        let mut rng = Rng::new(3);
        for expected in ALL_TYPES {
            for _ in 0..20 {
                let t = triangle(&mut rng);
                let p = point_in_region(&mut rng, &t, expected);
                assert_eq!(
                    point_triangle_distance_type(&p, &t[0], &t[1], &t[2]),
                    expected
                );
                let x = stack(&[p, t[0], t[1], t[2]]);
                check_finite_differences(&x, value, derivatives, 1e-6, 1e-6);
            }
        }
    }

    /// The classified distance is the true minimum over the triangle (dense
    /// sampling never beats it), and the closest barycentric point attains it.
    #[test]
    fn distance_is_the_minimum_over_the_triangle() {
        let mut rng = Rng::new(4);
        for _ in 0..200 {
            let t = triangle(&mut rng);
            let p = rng.vector3(2.0);
            let d = point_triangle_distance_squared(&p, &t[0], &t[1], &t[2]);
            let (b1, b2) = point_triangle_closest_barycentric(&p, &t[0], &t[1], &t[2]);
            assert!(
                b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0 + 1e-12,
                "({b1}, {b2})"
            );
            let closest = t[0] + (t[1] - t[0]) * b1 + (t[2] - t[0]) * b2;
            assert!(((p - closest).norm_squared() - d).abs() < 1e-12 * d.max(1.0));
            let n = 40;
            for i in 0..=n {
                for j in 0..=(n - i) {
                    let (s1, s2) = (i as f64 / n as f64, j as f64 / n as f64);
                    let q = t[0] + (t[1] - t[0]) * s1 + (t[2] - t[0]) * s2;
                    assert!((p - q).norm_squared() >= d - 1e-12);
                }
            }
        }
    }

    #[test]
    fn known_values() {
        let t0 = Vector3::new(0.0, 0.0, 0.0);
        let t1 = Vector3::new(2.0, 0.0, 0.0);
        let t2 = Vector3::new(0.0, 2.0, 0.0);
        let cases = [
            (
                Vector3::new(0.5, 0.5, 3.0),
                T::PointTriangle,
                9.0,
                (0.25, 0.25),
            ),
            (
                Vector3::new(1.0, -1.0, 1.0),
                T::PointEdge01,
                2.0,
                (0.5, 0.0),
            ),
            (Vector3::new(2.0, 2.0, 0.0), T::PointEdge12, 2.0, (0.5, 0.5)),
            (
                Vector3::new(-1.0, 1.5, 0.0),
                T::PointEdge20,
                1.0,
                (0.0, 0.75),
            ),
            (Vector3::new(-1.0, -2.0, 2.0), T::PointT0, 9.0, (0.0, 0.0)),
            (Vector3::new(4.0, -1.0, 0.0), T::PointT1, 5.0, (1.0, 0.0)),
            (Vector3::new(0.0, 3.0, -1.0), T::PointT2, 2.0, (0.0, 1.0)),
        ];
        for (p, expected, distance, barycentric) in cases {
            assert_eq!(point_triangle_distance_type(&p, &t0, &t1, &t2), expected);
            assert_eq!(point_triangle_distance_squared(&p, &t0, &t1, &t2), distance);
            assert_eq!(
                point_triangle_closest_barycentric(&p, &t0, &t1, &t2),
                barycentric
            );
        }
    }

    /// A point exactly over an edge (dyadic coordinates, so the side test
    /// gives exactly 0) counts as the edge; the squared distance is C^1
    /// across the edge, so its gradient matches central differences of the
    /// full function, and the Hessian is the point-line one. A point exactly
    /// over a vertex counts as the vertex.
    #[test]
    fn point_exactly_over_an_edge_or_a_vertex() {
        let mut rng = Rng::new(5);
        let dyadic = |v: Vector3| v.map(|c| (c * 32.0).round() / 32.0);
        let mut tested = 0;
        while tested < 30 {
            let mut t = [0; 3].map(|_| dyadic(rng.vector3(1.0)));
            for v in &mut t {
                v.z = 0.25;
            }
            let normal = (t[1] - t[0]).cross(&(t[2] - t[0]));
            if normal.z.abs() < 0.3 {
                continue;
            }
            tested += 1;
            let height = Vector3::new(0.0, 0.0, (rng.uniform(0.1, 1.0) * 32.0).round() / 32.0);
            let k = tested % 3;
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let p = a + (b - a) * 0.375 + height;
            let x = stack(&[p, t[0], t[1], t[2]]);
            assert_eq!(
                point_triangle_distance_type(&p, &t[0], &t[1], &t[2]),
                EDGES[k].2
            );
            let at = [0, 1 + k, 1 + (k + 1) % 3];
            let line = |x: &SVector<f64, 12>| {
                point_line_derivatives_3d(&point(x, 0), &point(x, at[1]), &point(x, at[2]), at)
            };
            let d = check_finite_differences(&x, value, line, 1e-7, 1e-6);
            assert!((d.value - height.z * height.z).abs() < 1e-14);
            assert_eq!(derivatives(&x).hessian, d.hessian);

            let p = t[k] + height;
            let vertex_type = [T::PointT0, T::PointT1, T::PointT2][k];
            assert_eq!(
                point_triangle_distance_type(&p, &t[0], &t[1], &t[2]),
                vertex_type
            );
            assert_eq!(
                point_triangle_distance_squared(&p, &t[0], &t[1], &t[2]),
                height.z * height.z
            );
        }
    }
}
