//! IPC's edge-edge mollifier (Li et al. 2020, §4.3; ipctk
//! `edge_edge_mollifier`): a factor that takes the edge-edge barrier
//! smoothly to zero as the edges turn parallel, where the closest-feature
//! type, and with it the distance's Hessian, jumps.

use super::StencilDerivatives;
use super::primitives::{cross_squared_norm_derivatives, scatter};
use crate::math::Vector3;

/// The mollifier's scale from the rest positions:
/// `eps_x = 1e-3 |ea1_rest - ea0_rest|^2 |eb1_rest - eb0_rest|^2`.
pub fn edge_edge_mollifier_threshold(
    ea0_rest: &Vector3,
    ea1_rest: &Vector3,
    eb0_rest: &Vector3,
    eb1_rest: &Vector3,
) -> f64 {
    1e-3 * (ea1_rest - ea0_rest).norm_squared() * (eb1_rest - eb0_rest).norm_squared()
}

/// `c = |(ea1 - ea0) x (eb1 - eb0)|^2`, the mollifier's argument.
pub fn edge_edge_cross_squared_norm(
    ea0: &Vector3,
    ea1: &Vector3,
    eb0: &Vector3,
    eb1: &Vector3,
) -> f64 {
    (ea1 - ea0).cross(&(eb1 - eb0)).norm_squared()
}

/// `m(c) = (2 - c / eps_x) c / eps_x` for `c < eps_x`, 1 otherwise, with
/// `c` = [`edge_edge_cross_squared_norm`].
pub fn edge_edge_mollifier(
    ea0: &Vector3,
    ea1: &Vector3,
    eb0: &Vector3,
    eb1: &Vector3,
    eps_x: f64,
) -> f64 {
    mollifier_of_cross(edge_edge_cross_squared_norm(ea0, ea1, eb0, eb1), eps_x).0
}

/// [`edge_edge_mollifier`] with its gradient and Hessian over
/// `(ea0, ea1, eb0, eb1)`: `grad m = m'(c) grad c`,
/// `hess m = m'(c) hess c + m''(c) grad c grad c^T` (zero for `c >= eps_x`).
pub fn edge_edge_mollifier_derivatives(
    ea0: &Vector3,
    ea1: &Vector3,
    eb0: &Vector3,
    eb1: &Vector3,
    eps_x: f64,
) -> StencilDerivatives<12> {
    let local = cross_squared_norm_derivatives(&(ea1 - ea0), &(eb1 - eb0));
    let (m, dm, ddm) = mollifier_of_cross(local.value, eps_x);
    if dm == 0.0 && ddm == 0.0 {
        return StencilDerivatives::constant(m);
    }
    let c: StencilDerivatives<12> = scatter::<3, 6, 12>(&local, &[(1, 0), (3, 2)]);
    StencilDerivatives {
        value: m,
        gradient: c.gradient * dm,
        hessian: c.hessian * dm + c.gradient * c.gradient.transpose() * ddm,
    }
}

/// `(m, dm/dc, d^2m/dc^2)`: with `x = c / eps_x`, `m = (2 - x) x`,
/// `m' = 2 (1 - x) / eps_x`, `m'' = -2 / eps_x^2` below the threshold
/// (`m = 1`, `m' = 0` at `c = eps_x`: the mollifier is C^1), `(1, 0, 0)`
/// above it.
fn mollifier_of_cross(c: f64, eps_x: f64) -> (f64, f64, f64) {
    if c < eps_x {
        let x = c / eps_x;
        (
            (2.0 - x) * x,
            2.0 * (1.0 - x) / eps_x,
            -2.0 / (eps_x * eps_x),
        )
    } else {
        (1.0, 0.0, 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{Rng, check_finite_differences, point, stack};
    use super::*;
    use nalgebra::SVector;

    /// Edges of lengths about 1 at a random small angle, so that `c` falls
    /// below `eps_x = 1e-3 |ea|^2 |eb|^2`.
    fn nearly_parallel(rng: &mut Rng, sine: f64) -> [Vector3; 4] {
        let ea0 = rng.vector3(1.0);
        let u = rng.vector3(1.0).normalize() * rng.uniform(0.8, 1.2);
        let turned = (u.normalize() * (1.0 - sine * sine).sqrt() + rng.perpendicular(&u) * sine)
            * rng.uniform(0.8, 1.2);
        let eb0 = ea0 + rng.vector3(0.5);
        [ea0, ea0 + u, eb0, eb0 + turned]
    }

    #[test]
    fn derivatives_match_finite_differences_below_the_threshold() {
        let mut rng = Rng::new(9);
        for _ in 0..40 {
            let sine = rng.uniform(0.002, 0.03);
            let [ea0, ea1, eb0, eb1] = nearly_parallel(&mut rng, sine);
            let eps_x = edge_edge_mollifier_threshold(&ea0, &ea1, &eb0, &eb1);
            let c = edge_edge_cross_squared_norm(&ea0, &ea1, &eb0, &eb1);
            assert!(c < 0.95 * eps_x && c > 0.0);
            let value = |x: &SVector<f64, 12>| {
                edge_edge_mollifier(
                    &point(x, 0),
                    &point(x, 1),
                    &point(x, 2),
                    &point(x, 3),
                    eps_x,
                )
            };
            let derivatives = |x: &SVector<f64, 12>| {
                let p = [0, 1, 2, 3].map(|a| point(x, a));
                edge_edge_mollifier_derivatives(&p[0], &p[1], &p[2], &p[3], eps_x)
            };
            // m varies on the scale sqrt(eps_x) ~ 0.03: a small step.
            let x = stack(&[ea0, ea1, eb0, eb1]);
            let d = check_finite_differences(&x, value, derivatives, 1e-7, 1e-6);
            let ratio = c / eps_x;
            assert!((d.value - (2.0 - ratio) * ratio).abs() < 1e-14);
            assert!(d.value > 0.0 && d.value < 1.0);
        }
    }

    #[test]
    fn one_beyond_the_threshold() {
        let mut rng = Rng::new(10);
        for _ in 0..20 {
            let sine = rng.uniform(0.04, 1.0);
            let [ea0, ea1, eb0, eb1] = nearly_parallel(&mut rng, sine);
            let eps_x = edge_edge_mollifier_threshold(&ea0, &ea1, &eb0, &eb1);
            assert!(edge_edge_cross_squared_norm(&ea0, &ea1, &eb0, &eb1) > eps_x);
            assert_eq!(edge_edge_mollifier(&ea0, &ea1, &eb0, &eb1, eps_x), 1.0);
            let d = edge_edge_mollifier_derivatives(&ea0, &ea1, &eb0, &eb1, eps_x);
            assert_eq!(d.value, 1.0);
            assert_eq!(d.gradient.amax(), 0.0);
            assert_eq!(d.hessian.amax(), 0.0);
        }
    }

    /// At `c = eps_x` the value reaches 1 and the slope 0 from below: the
    /// mollifier is C^1 (its second derivative jumps from `-2 / eps_x^2`).
    #[test]
    fn continuously_differentiable_at_the_threshold() {
        let eps_x = 3e-4;
        let (m, dm, ddm) = mollifier_of_cross(eps_x * (1.0 - 1e-12), eps_x);
        assert!((m - 1.0).abs() < 1e-15);
        assert!(dm > 0.0 && dm < 1e-8);
        assert_eq!(ddm, -2.0 / (eps_x * eps_x));
        assert_eq!(mollifier_of_cross(eps_x, eps_x), (1.0, 0.0, 0.0));
        // The one-sided difference quotient from below is exactly
        // delta / eps_x with delta = h / eps_x (m(eps_x - h) = 1 - delta^2):
        // it goes to 0 with h, and the one from above is 0.
        for delta in [1e-3, 1e-4, 1e-5] {
            let h = delta * eps_x;
            let below = (1.0 - mollifier_of_cross(eps_x - h, eps_x).0) / h;
            let above = (mollifier_of_cross(eps_x + h, eps_x).0 - 1.0) / h;
            assert!((below * eps_x - delta).abs() < 1e-9, "{below}");
            assert_eq!(above, 0.0);
        }
        // m(c) = 2 x - x^2 at x = 1/2: 3/4, slope 1 / eps_x.
        let (m, dm, _) = mollifier_of_cross(0.5 * eps_x, eps_x);
        assert_eq!(m, 0.75);
        assert!((dm - 1.0 / eps_x).abs() < 1e-9);
    }

    #[test]
    fn threshold_and_cross_norm_known_values() {
        let ea = [Vector3::new(0.0, 0.0, 0.0), Vector3::new(2.0, 0.0, 0.0)];
        let eb = [Vector3::new(0.0, 1.0, 0.0), Vector3::new(0.0, 1.0, 3.0)];
        assert!(
            (edge_edge_mollifier_threshold(&ea[0], &ea[1], &eb[0], &eb[1]) - 0.036).abs() < 1e-17
        );
        assert_eq!(
            edge_edge_cross_squared_norm(&ea[0], &ea[1], &eb[0], &eb[1]),
            36.0
        );
    }
}
