//! The observed order of convergence: the least-squares slope of
//! `log error` against `log dt`.

/// The slope `p` of the least-squares line through `(log dt, log error)`
/// of `points` (`(dt, error)` pairs). `None` when fewer than two distinct
/// positive step sizes have a positive, finite error (no line to fit).
pub fn observed_order(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(dt, e)| *dt > 0.0 && *e > 0.0 && dt.is_finite() && e.is_finite())
        .map(|(dt, e)| (dt.ln(), e.ln()))
        .collect();
    let n = logs.len() as f64;
    let mean_x = logs.iter().map(|p| p.0).sum::<f64>() / n;
    let mean_y = logs.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = logs.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    // Distinct step sizes leave a spread in log dt; equal ones do not.
    (logs.len() >= 2 && sxx > 1e-12).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_slope_of_a_power_law_is_its_exponent() {
        for p in [1.0, 2.0, 0.5] {
            let points: Vec<(f64, f64)> = [0.1, 0.05, 0.025, 0.0125]
                .iter()
                .map(|&dt| (dt, 3.0 * f64::powf(dt, p)))
                .collect();
            let order = observed_order(&points).unwrap();
            assert!((order - p).abs() < 1e-12, "{order} vs {p}");
        }
    }

    #[test]
    fn no_line_without_two_distinct_steps() {
        assert_eq!(observed_order(&[]), None);
        assert_eq!(observed_order(&[(0.1, 1.0)]), None);
        assert_eq!(observed_order(&[(0.1, 1.0), (0.1, 2.0)]), None);
        // A zero or NaN error is left out, not fitted as -inf.
        assert_eq!(observed_order(&[(0.1, 1.0), (0.05, 0.0)]), None);
        assert_eq!(observed_order(&[(0.1, 1.0), (0.05, f64::NAN)]), None);
    }
}
