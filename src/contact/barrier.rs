//! IPC's clamped log barrier (Li et al. 2020, eq. 6), the one barrier function of elasto's contacts.
//!
//! For a distance measure `d` (the ground uses the gap itself; body contact
//! uses the squared distance `s = d^2` against `s_hat = d_hat^2`, as the IPC
//! toolkit does) and an activation width `a`:
//!
//! ```text
//! b(d) = -(d - a)^2 ln(d / a)   for 0 < d < a,      0 for d >= a,     +inf for d <= 0,
//! b'(d)  = -2 (d - a) ln(d / a) - (d - a)^2 / d,
//! b''(d) = -2 ln(d / a) - 4 (d - a) / d + (d - a)^2 / d^2   (> 0 on (0, a): convex).
//! ```
//!
//! It is C2 at `d = a` (value, slope and curvature vanish there), so Newton
//! sees no kick when a pair enters the barrier, and infinite at contact, so a
//! line search that never crosses `d = 0` keeps every pair apart.

/// `b(d)` for barrier width `a`.
pub fn barrier(d: f64, a: f64) -> f64 {
    if d <= 0.0 {
        f64::INFINITY
    } else if d >= a {
        0.0
    } else {
        -(d - a).powi(2) * (d / a).ln()
    }
}

/// `b'(d)`.
pub fn barrier_derivative(d: f64, a: f64) -> f64 {
    if d >= a || d <= 0.0 {
        if d <= 0.0 { f64::NEG_INFINITY } else { 0.0 }
    } else {
        -2.0 * (d - a) * (d / a).ln() - (d - a).powi(2) / d
    }
}

/// `b''(d)`.
pub fn barrier_second_derivative(d: f64, a: f64) -> f64 {
    if d >= a || d <= 0.0 {
        if d <= 0.0 { f64::INFINITY } else { 0.0 }
    } else {
        -2.0 * (d / a).ln() - 4.0 * (d - a) / d + (d - a).powi(2) / (d * d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_match_finite_differences_and_vanish_at_the_width() {
        let a = 1e-2;
        for d in [1e-5, 1e-4, 1e-3, 5e-3, 9e-3] {
            let h = 1e-7 * d;
            let slope = (barrier(d + h, a) - barrier(d - h, a)) / (2.0 * h);
            assert!((slope - barrier_derivative(d, a)).abs() <= 1e-6 * slope.abs());
            let curvature =
                (barrier_derivative(d + h, a) - barrier_derivative(d - h, a)) / (2.0 * h);
            assert!((curvature - barrier_second_derivative(d, a)).abs() <= 1e-6 * curvature.abs());
            assert!(barrier_second_derivative(d, a) > 0.0);
        }
        let below = a * (1.0 - 1e-9);
        assert!(barrier(below, a).abs() < 1e-20);
        assert!(barrier_derivative(below, a).abs() < 1e-12);
        assert!(barrier_second_derivative(below, a).abs() < 1e-7);
        assert_eq!(barrier(0.0, a), f64::INFINITY);
        assert_eq!(barrier(2.0 * a, a), 0.0);
    }
}
