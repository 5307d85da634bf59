//! 3D edge-edge squared distance: classification by the clamped closest
//! parameters of the two lines (ipctk's rule, with its parallel case), then
//! point-point, point-line or line-line.

use super::StencilDerivatives;
use super::primitives::{
    cross_squared_norm, line_line_derivatives, line_line_distance_squared,
    point_line_derivatives_3d, point_line_distance_squared, point_point_derivatives,
    point_point_distance_squared,
};
use crate::math::Vector3;

/// Which features of the edges `a = (ea0, ea1)` and `b = (eb0, eb1)` are
/// closest: an end point (`Ea0`, `Ea1`, `Eb0`, `Eb1`) or an edge's interior
/// (`Ea`, `Eb`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EdgeEdgeDistanceType {
    /// `ea0` and `eb0`.
    Ea0Eb0,
    /// `ea0` and `eb1`.
    Ea0Eb1,
    /// `ea1` and `eb0`.
    Ea1Eb0,
    /// `ea1` and `eb1`.
    Ea1Eb1,
    /// Edge `a`'s interior and `eb0`.
    EaEb0,
    /// Edge `a`'s interior and `eb1`.
    EaEb1,
    /// `ea0` and edge `b`'s interior.
    Ea0Eb,
    /// `ea1` and edge `b`'s interior.
    Ea1Eb,
    /// Both interiors: the distance is the line-line distance.
    EaEb,
}

/// Edges with `|ea x eb|^2 < PARALLEL_THRESHOLD |ea|^2 |eb|^2` (the squared
/// sine of their angle below `2.5e-16`) are treated as parallel, as in
/// ipctk 1.6.1 (whose older releases used an absolute `1e-20`).
const PARALLEL_THRESHOLD: f64 = 2.5e-16;

/// ipctk's classification (a robust form of the clamped closest points of
/// two segments). With `u = ea1 - ea0`, `v = eb1 - eb0`, `w = ea0 - eb0` and
/// `a = u.u`, `b = u.v`, `c = v.v`, `d = u.w`, `e = v.w`, `D = a c - b^2`,
/// the lines' closest parameters are `s = (b e - c d) / D` on `a` and
/// `t = (a e - b d) / D` on `b`. If `s` leaves `[0, 1]`, it is clamped and
/// `t` recomputed for that end point (`t = e / c` or `(e + b) / c`); if `t`
/// then leaves `[0, 1]`, it is clamped and `s = -d / a` or `(b - d) / a`
/// decides the feature on `a`. Nearly parallel edges go to
/// [`edge_edge_parallel_distance_type`]; zero-length edges count as their
/// first end point.
pub fn edge_edge_distance_type(
    ea0: &Vector3,
    ea1: &Vector3,
    eb0: &Vector3,
    eb1: &Vector3,
) -> EdgeEdgeDistanceType {
    use EdgeEdgeDistanceType as T;
    let (u, v, w) = (ea1 - ea0, eb1 - eb0, ea0 - eb0);
    let (a, b, c, d, e) = (u.dot(&u), u.dot(&v), v.dot(&v), u.dot(&w), v.dot(&w));
    let denominator = a * c - b * b;
    if a == 0.0 && c == 0.0 {
        return T::Ea0Eb0;
    } else if a == 0.0 {
        return T::Ea0Eb;
    } else if c == 0.0 {
        return T::EaEb0;
    }
    if u.cross(&v).norm_squared() < PARALLEL_THRESHOLD * a * c {
        return edge_edge_parallel_distance_type(ea0, ea1, eb0, eb1);
    }
    // t = t_numerator / t_denominator once s is settled.
    let s_numerator = b * e - c * d;
    let (t_numerator, t_denominator, interior_t_type) = if s_numerator <= 0.0 {
        (e, c, T::Ea0Eb)
    } else if s_numerator >= denominator {
        (e + b, c, T::Ea1Eb)
    } else {
        (a * e - b * d, denominator, T::EaEb)
    };
    if t_numerator <= 0.0 {
        if -d <= 0.0 {
            T::Ea0Eb0
        } else if -d >= a {
            T::Ea1Eb0
        } else {
            T::EaEb0
        }
    } else if t_numerator >= t_denominator {
        if b - d <= 0.0 {
            T::Ea0Eb1
        } else if b - d >= a {
            T::Ea1Eb1
        } else {
            T::EaEb1
        }
    } else {
        interior_t_type
    }
}

/// ipctk's classification of (nearly) parallel edges, where the line-line
/// distance is undefined: with `alpha`, `beta` the parameters of `eb0`,
/// `eb1` projected on edge `a`'s line, the closest pair is an end point of
/// one edge against the other edge (or an end point), chosen by where the
/// projections fall.
pub fn edge_edge_parallel_distance_type(
    ea0: &Vector3,
    ea1: &Vector3,
    eb0: &Vector3,
    eb1: &Vector3,
) -> EdgeEdgeDistanceType {
    use EdgeEdgeDistanceType as T;
    #[derive(PartialEq)]
    enum Feature {
        Start,
        End,
        Interior,
    }
    let ea = ea1 - ea0;
    let alpha = (eb0 - ea0).dot(&ea) / ea.norm_squared();
    let beta = (eb1 - ea0).dot(&ea) / ea.norm_squared();
    let beta_inside = (0.0..=1.0).contains(&beta);
    let (on_a, on_b) = if alpha < 0.0 {
        let on_a = if beta_inside {
            Feature::Interior
        } else {
            Feature::Start
        };
        let on_b = if beta <= alpha {
            Feature::Start
        } else if beta <= 1.0 {
            Feature::End
        } else {
            Feature::Interior
        };
        (on_a, on_b)
    } else if alpha > 1.0 {
        let on_a = if beta_inside {
            Feature::Interior
        } else {
            Feature::End
        };
        let on_b = if beta >= alpha {
            Feature::Start
        } else if 0.0 <= beta {
            Feature::End
        } else {
            Feature::Interior
        };
        (on_a, on_b)
    } else {
        (Feature::Interior, Feature::Start)
    };
    match (on_a, on_b) {
        (Feature::Start, Feature::Start) => T::Ea0Eb0,
        (Feature::Start, Feature::End) => T::Ea0Eb1,
        (Feature::End, Feature::Start) => T::Ea1Eb0,
        (Feature::End, Feature::End) => T::Ea1Eb1,
        (Feature::Interior, Feature::Start) => T::EaEb0,
        (Feature::Interior, Feature::End) => T::EaEb1,
        (Feature::Start, Feature::Interior) => T::Ea0Eb,
        (Feature::End, Feature::Interior) => T::Ea1Eb,
        // Unreachable for parallel edges (ipctk asserts it away).
        (Feature::Interior, Feature::Interior) => T::EaEb,
    }
}

/// The squared distance between the segments `(ea0, ea1)` and `(eb0, eb1)`.
pub fn edge_edge_distance_squared(
    ea0: &Vector3,
    ea1: &Vector3,
    eb0: &Vector3,
    eb1: &Vector3,
) -> f64 {
    use EdgeEdgeDistanceType as T;
    match edge_edge_distance_type(ea0, ea1, eb0, eb1) {
        T::Ea0Eb0 => point_point_distance_squared(ea0, eb0),
        T::Ea0Eb1 => point_point_distance_squared(ea0, eb1),
        T::Ea1Eb0 => point_point_distance_squared(ea1, eb0),
        T::Ea1Eb1 => point_point_distance_squared(ea1, eb1),
        T::EaEb0 => point_line_distance_squared(eb0, ea0, ea1),
        T::EaEb1 => point_line_distance_squared(eb1, ea0, ea1),
        T::Ea0Eb => point_line_distance_squared(ea0, eb0, eb1),
        T::Ea1Eb => point_line_distance_squared(ea1, eb0, eb1),
        T::EaEb => line_line_distance_squared(ea0, ea1, eb0, eb1),
    }
}

/// [`edge_edge_distance_squared`] with its gradient and Hessian over
/// `(ea0, ea1, eb0, eb1)`.
pub fn edge_edge_distance_squared_derivatives(
    ea0: &Vector3,
    ea1: &Vector3,
    eb0: &Vector3,
    eb1: &Vector3,
) -> StencilDerivatives<12> {
    use EdgeEdgeDistanceType as T;
    match edge_edge_distance_type(ea0, ea1, eb0, eb1) {
        T::Ea0Eb0 => point_point_derivatives(ea0, eb0, [0, 2]),
        T::Ea0Eb1 => point_point_derivatives(ea0, eb1, [0, 3]),
        T::Ea1Eb0 => point_point_derivatives(ea1, eb0, [1, 2]),
        T::Ea1Eb1 => point_point_derivatives(ea1, eb1, [1, 3]),
        T::EaEb0 => point_line_derivatives_3d(eb0, ea0, ea1, [2, 0, 1]),
        T::EaEb1 => point_line_derivatives_3d(eb1, ea0, ea1, [3, 0, 1]),
        T::Ea0Eb => point_line_derivatives_3d(ea0, eb0, eb1, [0, 2, 3]),
        T::Ea1Eb => point_line_derivatives_3d(ea1, eb0, eb1, [1, 2, 3]),
        T::EaEb => line_line_derivatives(ea0, ea1, eb0, eb1),
    }
}

/// The parameters `(s, t)` in `[0, 1]` of the closest points
/// `ea0 + s (ea1 - ea0)` and `eb0 + t (eb1 - eb0)`, following
/// [`edge_edge_distance_type`]: 0 or 1 at an end point, the clamped
/// projection of an end point on the other edge, or, for two interiors, the
/// lines' closest points `(s, t) = (b e - c d, a e - b d) / D` with the
/// names of [`edge_edge_distance_type`] (`D = |u x v|^2`).
pub fn edge_edge_closest_parameters(
    ea0: &Vector3,
    ea1: &Vector3,
    eb0: &Vector3,
    eb1: &Vector3,
) -> (f64, f64) {
    use EdgeEdgeDistanceType as T;
    let along = |p: &Vector3, e0: &Vector3, e1: &Vector3| {
        let e = e1 - e0;
        let length_squared = e.norm_squared();
        if length_squared == 0.0 {
            0.0
        } else {
            (e.dot(&(p - e0)) / length_squared).clamp(0.0, 1.0)
        }
    };
    match edge_edge_distance_type(ea0, ea1, eb0, eb1) {
        T::Ea0Eb0 => (0.0, 0.0),
        T::Ea0Eb1 => (0.0, 1.0),
        T::Ea1Eb0 => (1.0, 0.0),
        T::Ea1Eb1 => (1.0, 1.0),
        T::EaEb0 => (along(eb0, ea0, ea1), 0.0),
        T::EaEb1 => (along(eb1, ea0, ea1), 1.0),
        T::Ea0Eb => (0.0, along(ea0, eb0, eb1)),
        T::Ea1Eb => (1.0, along(ea1, eb0, eb1)),
        T::EaEb => {
            let (u, v, w) = (ea1 - ea0, eb1 - eb0, ea0 - eb0);
            let (a, b, c, d, e) = (u.dot(&u), u.dot(&v), v.dot(&v), u.dot(&w), v.dot(&w));
            let denominator = cross_squared_norm(&u, &v);
            (
                ((b * e - c * d) / denominator).clamp(0.0, 1.0),
                ((a * e - b * d) / denominator).clamp(0.0, 1.0),
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::primitives::point_line_derivatives_3d;
    use super::super::test_support::{Rng, check_finite_differences, point, stack};
    use super::*;
    use EdgeEdgeDistanceType as T;
    use nalgebra::SVector;

    fn value(x: &SVector<f64, 12>) -> f64 {
        edge_edge_distance_squared(&point(x, 0), &point(x, 1), &point(x, 2), &point(x, 3))
    }

    fn derivatives(x: &SVector<f64, 12>) -> StencilDerivatives<12> {
        edge_edge_distance_squared_derivatives(
            &point(x, 0),
            &point(x, 1),
            &point(x, 2),
            &point(x, 3),
        )
    }

    /// Which end of an edge, or its interior, holds the closest point.
    #[derive(Clone, Copy)]
    enum Feature {
        Start,
        End,
        Interior,
    }

    const CASES: [(Feature, Feature, T); 9] = {
        use Feature::*;
        [
            (Start, Start, T::Ea0Eb0),
            (Start, End, T::Ea0Eb1),
            (End, Start, T::Ea1Eb0),
            (End, End, T::Ea1Eb1),
            (Interior, Start, T::EaEb0),
            (Interior, End, T::EaEb1),
            (Start, Interior, T::Ea0Eb),
            (End, Interior, T::Ea1Eb),
            (Interior, Interior, T::EaEb),
        ]
    };

    /// Two edges (not nearly parallel) whose closest points are the given
    /// features, `gap` apart, built from the optimality conditions of
    /// `|ea0 + s u - eb0 - t v|^2` over `[0, 1]^2`: with `r` from the point on
    /// `b` to the point on `a`, an interior parameter needs `r` orthogonal to
    /// its edge, `s = 0` needs `r.u > 0`, `s = 1` `r.u < 0`, `t = 0` `r.v < 0`
    /// and `t = 1` `r.v > 0` (with margins).
    fn edges_with_closest(rng: &mut Rng, on_a: Feature, on_b: Feature, gap: f64) -> [Vector3; 4] {
        let (u, v) = loop {
            let (u, v) = (rng.vector3(1.0), rng.vector3(1.0));
            let sine = u.cross(&v).norm() / (u.norm() * v.norm());
            if sine > 0.3 && u.norm() > 0.4 && v.norm() > 0.4 {
                break (u, v);
            }
        };
        let wanted = |feature: Feature| match feature {
            Feature::Start => 1.0,
            Feature::End => -1.0,
            Feature::Interior => 0.0,
        };
        // Wanted signs of r.u and r.v (0 for orthogonal).
        let (sign_u, sign_v) = (wanted(on_a), -wanted(on_b));
        let r = loop {
            let mut r = rng.vector3(1.0);
            match (sign_u == 0.0, sign_v == 0.0) {
                (true, true) => r = u.cross(&v),
                (true, false) => r -= u * (r.dot(&u) / u.norm_squared()),
                (false, true) => r -= v * (r.dot(&v) / v.norm_squared()),
                (false, false) => {}
            }
            let r = r.normalize();
            let ok = |sign: f64, e: &Vector3| sign == 0.0 || sign * r.dot(e) > 0.1 * e.norm();
            if ok(sign_u, &u) && ok(sign_v, &v) {
                break r * gap;
            }
        };
        let parameter = |feature: Feature, rng: &mut Rng| match feature {
            Feature::Start => 0.0,
            Feature::End => 1.0,
            Feature::Interior => rng.uniform(0.1, 0.9),
        };
        let (s, t) = (parameter(on_a, rng), parameter(on_b, rng));
        let on_b_point = rng.vector3(1.0);
        let eb0 = on_b_point - v * t;
        let ea0 = on_b_point + r - u * s;
        [ea0, ea0 + u, eb0, eb0 + v]
    }

    #[test]
    fn derivatives_match_finite_differences_for_every_type() {
        let mut rng = Rng::new(6);
        for (on_a, on_b, expected) in CASES {
            for _ in 0..20 {
                let gap = rng.uniform(0.05, 1.0);
                let [ea0, ea1, eb0, eb1] = edges_with_closest(&mut rng, on_a, on_b, gap);
                assert_eq!(edge_edge_distance_type(&ea0, &ea1, &eb0, &eb1), expected);
                let x = stack(&[ea0, ea1, eb0, eb1]);
                let d = check_finite_differences(&x, value, derivatives, 1e-6, 1e-6);
                assert!(
                    (d.value - gap * gap).abs() < 1e-12,
                    "{} vs {}",
                    d.value,
                    gap * gap
                );
                let (s, t) = edge_edge_closest_parameters(&ea0, &ea1, &eb0, &eb1);
                let between = ea0 + (ea1 - ea0) * s - eb0 - (eb1 - eb0) * t;
                assert!((between.norm_squared() - gap * gap).abs() < 1e-12);
            }
        }
    }

    /// Crossing edges: every type at distance 0 gives value 0 and gradient 0;
    /// the interior crossing keeps its smooth line-line Hessian.
    #[test]
    fn crossing_edges_have_zero_distance() {
        let mut rng = Rng::new(7);
        for (on_a, on_b, expected) in CASES {
            let [ea0, ea1, eb0, eb1] = edges_with_closest(&mut rng, on_a, on_b, 0.0);
            let value = edge_edge_distance_squared(&ea0, &ea1, &eb0, &eb1);
            assert!(value < 1e-30, "{expected:?}: {value}");
        }
        let ea = [Vector3::new(-1.0, 0.0, 0.0), Vector3::new(1.0, 0.0, 0.0)];
        let eb = [Vector3::new(0.0, -1.0, 0.0), Vector3::new(0.0, 1.0, 0.0)];
        assert_eq!(
            edge_edge_distance_type(&ea[0], &ea[1], &eb[0], &eb[1]),
            T::EaEb
        );
        let x = stack(&[ea[0], ea[1], eb[0], eb[1]]);
        let d = check_finite_differences(&x, value, derivatives, 1e-6, 1e-6);
        assert_eq!(d.value, 0.0);
        assert_eq!(d.gradient.amax(), 0.0);
        // At a = 0 the Hessian is 2 grad a grad a^T / |n|^2 with n = (0, 0, 4)
        // and d a / d ea0 = -(v x w + u x v) = (0, 0, -2): 2 * 4 / 16 = 0.5.
        assert!((d.hessian[(2, 2)] - 0.5).abs() < 1e-15);
        assert_eq!(
            edge_edge_closest_parameters(&ea[0], &ea[1], &eb[0], &eb[1]),
            (0.5, 0.5)
        );
    }

    /// The classified distance is the true minimum (dense sampling never
    /// beats it) at random edge pairs.
    #[test]
    fn distance_is_the_minimum_over_both_edges() {
        let mut rng = Rng::new(8);
        for _ in 0..200 {
            let [ea0, ea1, eb0, eb1] = [0; 4].map(|_| rng.vector3(1.0));
            let d = edge_edge_distance_squared(&ea0, &ea1, &eb0, &eb1);
            let (s, t) = edge_edge_closest_parameters(&ea0, &ea1, &eb0, &eb1);
            let between = ea0 + (ea1 - ea0) * s - eb0 - (eb1 - eb0) * t;
            assert!((between.norm_squared() - d).abs() < 1e-12 * d.max(1.0));
            let n = 60;
            for i in 0..=n {
                for j in 0..=n {
                    let (s, t) = (i as f64 / n as f64, j as f64 / n as f64);
                    let q = ea0 + (ea1 - ea0) * s - eb0 - (eb1 - eb0) * t;
                    assert!(q.norm_squared() >= d - 1e-12);
                }
            }
        }
    }

    /// Edges in parallel planes `gap` apart, `b` turned by `angle` about the
    /// common normal through both midpoints: the closest points are the
    /// midpoints, at distance `gap`.
    fn turned_edges(angle: f64, gap: f64) -> [Vector3; 4] {
        let half = Vector3::new(angle.cos(), angle.sin(), 0.0) * 0.5;
        let middle_b = Vector3::new(0.5, 0.0, gap);
        [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            middle_b - half,
            middle_b + half,
        ]
    }

    #[test]
    fn nearly_parallel_edges() {
        let gap = 0.25;
        // Clearly above the parallel threshold: the smooth line-line case.
        let [ea0, ea1, eb0, eb1] = turned_edges(1e-3, gap);
        assert_eq!(edge_edge_distance_type(&ea0, &ea1, &eb0, &eb1), T::EaEb);
        let x = stack(&[ea0, ea1, eb0, eb1]);
        let d = check_finite_differences(&x, value, derivatives, 1e-8, 1e-6);
        assert!((d.value - gap * gap).abs() < 1e-14);
        // sin^2 = 1e-14, still above 2.5e-16: line-line, accurate to ~1e-9.
        let [ea0, ea1, eb0, eb1] = turned_edges(1e-7, gap);
        assert_eq!(edge_edge_distance_type(&ea0, &ea1, &eb0, &eb1), T::EaEb);
        let value = edge_edge_distance_squared(&ea0, &ea1, &eb0, &eb1);
        assert!((value - gap * gap).abs() < 1e-8 * gap * gap, "{value}");
        // sin^2 = 1e-18: parallel, b's start against a's interior.
        let [ea0, ea1, eb0, eb1] = turned_edges(1e-9, gap);
        assert_eq!(edge_edge_distance_type(&ea0, &ea1, &eb0, &eb1), T::EaEb0);
        let value = edge_edge_distance_squared(&ea0, &ea1, &eb0, &eb1);
        assert!((value - gap * gap).abs() < 1e-15);
    }

    /// Exactly parallel edges: the distance between the lines, through the
    /// parallel classification; the derivatives are those of the chosen
    /// point-line primitive, checked by finite differences of it.
    #[test]
    fn exactly_parallel_edges() {
        let cases = [
            // b overlaps a's middle: eb0 against a's interior.
            ((0.25, 1.5), T::EaEb0, [2, 0, 1]),
            // b starts before a and ends inside it: eb1 against a's interior.
            ((-1.0, 0.5), T::EaEb1, [3, 0, 1]),
            // b starts before a and covers it: ea0 against b's interior
            // (ipctk's rule picks a's start).
            ((-1.0, 2.0), T::Ea0Eb, [0, 2, 3]),
            // b entirely beyond a's end: end points.
            ((1.5, 2.5), T::Ea1Eb0, [1, 2, 3]),
        ];
        let offset = Vector3::new(0.0, 0.375, -0.5);
        for ((alpha, beta), expected, at) in cases {
            let ea0 = Vector3::new(0.0, 0.0, 0.0);
            let ea1 = Vector3::new(2.0, 0.0, 0.0);
            let eb0 = Vector3::new(2.0 * alpha, 0.0, 0.0) + offset;
            let eb1 = Vector3::new(2.0 * beta, 0.0, 0.0) + offset;
            assert_eq!(edge_edge_distance_type(&ea0, &ea1, &eb0, &eb1), expected);
            let x = stack(&[ea0, ea1, eb0, eb1]);
            let full = derivatives(&x);
            if expected == T::Ea1Eb0 {
                assert_eq!(full.value, 1.0 + offset.norm_squared());
                continue;
            }
            assert_eq!(full.value, offset.norm_squared());
            let line = |x: &SVector<f64, 12>| {
                point_line_derivatives_3d(&point(x, at[0]), &point(x, at[1]), &point(x, at[2]), at)
            };
            let d = check_finite_differences(&x, |x| line(x).value, line, 1e-6, 1e-6);
            assert_eq!(full.gradient, d.gradient);
            assert_eq!(full.hessian, d.hessian);
        }
    }
}
