//! 2D point-edge squared distance: classification by the projection
//! parameter, then point-point or point-line.

use super::StencilDerivatives;
use super::primitives::{
    point_line_derivatives_2d, point_line_distance_squared, point_point_derivatives,
    point_point_distance_squared,
};
use crate::math::Vector2;

/// Which feature of the edge `(e0, e1)` is closest to the point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointEdgeDistanceType {
    /// The end point `e0` (the projection parameter is below 0).
    PointEdge0,
    /// The end point `e1` (the projection parameter is above 1).
    PointEdge1,
    /// The edge's interior (parameter in `[0, 1]`): the distance is the
    /// point-line distance.
    PointEdge,
}

/// The projection parameter `t = (p - e0) . e / |e|^2`, `e = e1 - e0`:
/// [`PointEdgeDistanceType::PointEdge0`] for `t < 0`, `PointEdge1` for
/// `t > 1`, `PointEdge` otherwise (ipctk's rule; a zero-length edge counts
/// as its end point `e0`).
pub fn point_edge_distance_type(p: &Vector2, e0: &Vector2, e1: &Vector2) -> PointEdgeDistanceType {
    let e = e1 - e0;
    let length_squared = e.norm_squared();
    if length_squared == 0.0 {
        return PointEdgeDistanceType::PointEdge0;
    }
    let t = e.dot(&(p - e0)) / length_squared;
    if t < 0.0 {
        PointEdgeDistanceType::PointEdge0
    } else if t > 1.0 {
        PointEdgeDistanceType::PointEdge1
    } else {
        PointEdgeDistanceType::PointEdge
    }
}

/// The squared distance from `p` to the segment `(e0, e1)`.
pub fn point_edge_distance_squared(p: &Vector2, e0: &Vector2, e1: &Vector2) -> f64 {
    match point_edge_distance_type(p, e0, e1) {
        PointEdgeDistanceType::PointEdge0 => point_point_distance_squared(p, e0),
        PointEdgeDistanceType::PointEdge1 => point_point_distance_squared(p, e1),
        PointEdgeDistanceType::PointEdge => point_line_distance_squared(p, e0, e1),
    }
}

/// [`point_edge_distance_squared`] with its gradient and Hessian over
/// `(p, e0, e1)` (the formula of the closest feature, zeros for the vertex
/// it leaves out).
pub fn point_edge_distance_squared_derivatives(
    p: &Vector2,
    e0: &Vector2,
    e1: &Vector2,
) -> StencilDerivatives<6> {
    match point_edge_distance_type(p, e0, e1) {
        PointEdgeDistanceType::PointEdge0 => point_point_derivatives(p, e0, [0, 1]),
        PointEdgeDistanceType::PointEdge1 => point_point_derivatives(p, e1, [0, 2]),
        PointEdgeDistanceType::PointEdge => point_line_derivatives_2d(p, e0, e1, [0, 1, 2]),
    }
}

/// The parameter `t` in `[0, 1]` of the point `e0 + t (e1 - e0)` of the
/// segment closest to `p` (0 for a zero-length edge).
pub fn point_edge_closest_parameter(p: &Vector2, e0: &Vector2, e1: &Vector2) -> f64 {
    let e = e1 - e0;
    let length_squared = e.norm_squared();
    if length_squared == 0.0 {
        return 0.0;
    }
    (e.dot(&(p - e0)) / length_squared).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{Rng, check_finite_differences, point, stack};
    use super::*;
    use nalgebra::SVector;

    fn value(x: &SVector<f64, 6>) -> f64 {
        point_edge_distance_squared(&point(x, 0), &point(x, 1), &point(x, 2))
    }

    fn derivatives(x: &SVector<f64, 6>) -> StencilDerivatives<6> {
        point_edge_distance_squared_derivatives(&point(x, 0), &point(x, 1), &point(x, 2))
    }

    /// A random edge and a point at parameter `t` along it, offset by
    /// `offset` along the edge's normal.
    fn configuration(rng: &mut Rng, t: f64, offset: f64) -> [Vector2; 3] {
        let e0 = rng.vector2(1.0);
        let e = Vector2::new(rng.uniform(0.5, 1.5), rng.uniform(-1.0, 1.0));
        let normal = Vector2::new(-e.y, e.x).normalize();
        [e0 + e * t + normal * offset, e0, e0 + e]
    }

    #[test]
    fn derivatives_match_finite_differences_for_every_type() {
        let mut rng = Rng::new(1);
        let cases = [
            (PointEdgeDistanceType::PointEdge0, -1.5, -0.05),
            (PointEdgeDistanceType::PointEdge1, 1.05, 1.5),
            (PointEdgeDistanceType::PointEdge, 0.05, 0.95),
        ];
        for (expected, t_lo, t_hi) in cases {
            for _ in 0..30 {
                let t = rng.uniform(t_lo, t_hi);
                let offset = rng.uniform(-0.5, 0.5);
                let [p, e0, e1] = configuration(&mut rng, t, offset);
                assert_eq!(point_edge_distance_type(&p, &e0, &e1), expected);
                let d =
                    check_finite_differences(&stack(&[p, e0, e1]), value, derivatives, 1e-6, 1e-6);
                // The closest point is the one the type names.
                let closest = e0 + (e1 - e0) * point_edge_closest_parameter(&p, &e0, &e1);
                assert!((d.value - (p - closest).norm_squared()).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn known_values() {
        let (e0, e1) = (Vector2::new(0.0, 0.0), Vector2::new(2.0, 0.0));
        let p = Vector2::new(0.5, 3.0);
        assert_eq!(point_edge_distance_squared(&p, &e0, &e1), 9.0);
        assert_eq!(point_edge_closest_parameter(&p, &e0, &e1), 0.25);
        let p = Vector2::new(-3.0, 4.0);
        assert_eq!(point_edge_distance_squared(&p, &e0, &e1), 25.0);
        assert_eq!(point_edge_closest_parameter(&p, &e0, &e1), 0.0);
        let p = Vector2::new(3.0, -1.0);
        assert_eq!(point_edge_distance_squared(&p, &e0, &e1), 2.0);
        assert_eq!(point_edge_closest_parameter(&p, &e0, &e1), 1.0);
        // Point on the edge: distance 0, gradient 0.
        let d = point_edge_distance_squared_derivatives(&Vector2::new(1.0, 0.0), &e0, &e1);
        assert_eq!(d.value, 0.0);
        assert_eq!(d.gradient.amax(), 0.0);
        // The Hessian of the point-line distance along the normal: 2 n n^T on p.
        assert!((d.hessian[(1, 1)] - 2.0).abs() < 1e-15 && d.hessian[(0, 0)].abs() < 1e-15);
    }

    /// At an edge's end the type switches from point-point to point-line
    /// (parameter exactly 0 or 1, built from dyadic numbers so that it is
    /// exact). The squared distance is C^1 there: its gradient matches
    /// central differences of the full function, and the Hessian is the
    /// point-line one.
    #[test]
    fn point_exactly_over_an_end_of_the_edge() {
        let mut rng = Rng::new(2);
        let dyadic = |v: Vector2| v.map(|c| (c * 64.0).round() / 64.0);
        for t in [0.0, 1.0] {
            for _ in 0..10 {
                let e0 = dyadic(rng.vector2(1.0));
                let e = dyadic(Vector2::new(rng.uniform(0.5, 1.5), rng.uniform(-1.0, 1.0)));
                let scale = (rng.uniform(0.2, 1.0) * 8.0).round() / 8.0;
                let offset = Vector2::new(-e.y, e.x) * scale;
                let e1 = e0 + e;
                let p = e0 + e * t + offset;
                assert_eq!(
                    point_edge_distance_type(&p, &e0, &e1),
                    PointEdgeDistanceType::PointEdge
                );
                let x = stack(&[p, e0, e1]);
                let line = |x: &SVector<f64, 6>| {
                    point_line_derivatives_2d(&point(x, 0), &point(x, 1), &point(x, 2), [0, 1, 2])
                };
                let d = check_finite_differences(&x, value, line, 1e-7, 1e-6);
                let full = derivatives(&x);
                assert_eq!(full.gradient, d.gradient);
                assert_eq!(full.hessian, d.hessian);
                assert!((d.value - offset.norm_squared()).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn point_on_the_vertex_has_zero_distance() {
        let (e0, e1) = (Vector2::new(0.3, -0.2), Vector2::new(1.0, 0.4));
        let d = point_edge_distance_squared_derivatives(&e1, &e0, &e1);
        assert_eq!(d.value, 0.0);
        assert_eq!(d.gradient.amax(), 0.0);
    }
}
