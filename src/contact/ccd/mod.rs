//! Additive continuous collision detection (Li, Kaufman, Jiang 2021, "Codimensional
//! Incremental Potential Contact", §5): the largest safe fraction of a linear motion.
//!
//! A stencil's points move linearly, `x_i(t) = x_i + t dx_i`, for `t` in `[0, t_max]`.
//! The query returns a time `t` such that the primitives stay more than `ξ` apart
//! (`ξ`: [`CcdSettings::min_distance`]) on all of `[0, t]`. It never computes a
//! root; it adds up lower bounds on the time of impact, so it is conservative by
//! construction (up to rounding in the distance evaluations).
//!
//! **Relative motion.** The distance is invariant under a common translation, so
//! the mean displacement `(1/n) Σ dx_i` is subtracted from every `dx_i` first; this
//! makes two primitives that move together (no relative motion) stand still.
//!
//! **Lipschitz bound.** Every point of a primitive is a convex combination of its
//! corners, so it moves at most `max_i |dx_i|` (over the primitive's corners) per
//! unit of `t`. The distance between the two primitives therefore shrinks at most
//! at the rate
//!
//! ```text
//! l_p = max_{i in A} |dx_i| + max_{j in B} |dx_j|
//!   point-edge:     |dp| + max(|de0|, |de1|)
//!   point-triangle: |dp| + max(|dt0|, |dt1|, |dt2|)
//!   edge-edge:      max(|dea0|, |dea1|) + max(|deb0|, |deb1|)
//! ```
//!
//! and if the current distance is `d`, no contact (distance `ξ`) happens before
//! `t + (d - ξ) / l_p`. If `l_p = 0` nothing moves relative to anything: the answer
//! is `t_max`.
//!
//! **Iteration** (the IPC toolkit's `AdditiveCCD::additive_ccd`, with its
//! `conservative_rescaling` `s = 0.9`; the paper and the solid-sim tutorial write
//! `s = 1 - η`, `η = 0.1`). With `d - ξ` evaluated as `(d² - ξ²) / (d + ξ)`
//! (from the squared distance, without cancellation near `ξ`):
//!
//! ```text
//! if d_0² <= ξ²: return 0                      (already in contact)
//! gap = (1 - s) (d_0² - ξ²) / (d_0 + ξ)        (the separation the answer keeps)
//! t = 0
//! repeat at most max_iterations times:
//!     t_l = s (d² - ξ²) / ((d + ξ) l_p)        (a lower bound on the remaining time)
//!     x  += t_l dx;  d² = distance²(x)
//!     if t > 0 and (d² - ξ²) / (d + ξ) < gap: return t    (the last step is dropped)
//!     t += t_l
//!     if t > t_max: return t_max               (no contact before t_max)
//! return t (budget exhausted)
//! ```
//!
//! Each step closes at most the fraction `s` of the remaining separation, so after
//! the first step the separation is at least `gap`; the loop stops at the first
//! step that would go below `gap` and returns the time before it. The answer thus
//! keeps at least `(1 - s)` of the initial separation (`d(t) - ξ >= gap`) unless it
//! is `t_max`. The first step is always accepted (it is safe by the Lipschitz
//! bound; only a distance that evaluates to `<= ξ` after it stops at 0), so a
//! query that starts apart does not answer 0 through rounding. For a head-on
//! relative translation (along the closest points' direction), `l_p` equals the
//! approach speed and the first step alone reaches `s` times the time of
//! impact: the answer lies in `[s toi, toi)`.
//!
//! **Cost.** A motion that stays at distance `h` for a relative travel `L` needs
//! about `L / (s h)` iterations (sliding contact); hence the budget
//! [`CcdSettings::max_iterations`]. When it runs out, the time reached so far is
//! returned (safe, never more) and [`CcdOutcome::budget_exhausted`] is set.
//!
//! **Deviations from the IPC toolkit.** Its edge-edge distance falls back to the
//! nearest endpoint pair when the distance reads `<= ξ` (a guard for its
//! near-parallel formula); ours is exact for closed segments, so the fallback
//! would only hide real contacts and is left out. Non-finite input (NaN or infinite
//! coordinates, a NaN `t_max`) answers `0` (do not move); a non-positive `t_max`
//! answers `0`; an infinite `t_max` is allowed. A separation that turns NaN or
//! non-positive through rounding or overflow stops the iteration at the safe time
//! reached.
//!
//! No Rust crate offers additive CCD (the toolkit is C++); this is elasto's own
//! code. Everything is on fixed-size arrays: no heap allocation.

use super::distance::{
    edge_edge_distance_squared, point_edge_distance_squared, point_triangle_distance_squared,
};
use crate::math::{Vector, Vector2, Vector3};

/// Settings of one CCD query.
#[derive(Debug, Clone, Copy)]
pub struct CcdSettings {
    /// Fraction of the distance to impact the step may close (default 0.9 in ipctk's conservative rescaling).
    /// In `(0, 1]`; the answer keeps `1 - conservative_rescaling` of the initial separation.
    pub conservative_rescaling: f64,
    /// Minimum separation ξ kept (default 0).
    pub min_distance: f64,
    /// Iteration budget per query (default 10 000). A query costs about
    /// `travel / (s · distance)` iterations when the primitives slide past each
    /// other at a small distance; 10 000 covers sliding over 9 000 times the
    /// distance (about 1 ms per query at the limit, measured with elasto's
    /// distances) and an exhausted query still returns a safe step of that much
    /// travel. A smaller budget would shorten line-search steps, and every
    /// extra Newton iteration costs a linear solve, far more than 1 ms.
    pub max_iterations: usize,
}

impl Default for CcdSettings {
    fn default() -> Self {
        Self {
            conservative_rescaling: 0.9,
            min_distance: 0.0,
            max_iterations: 10_000,
        }
    }
}

/// A query's answer: the largest safe step fraction in [0, t_max], and whether the budget ran out
/// (then `step` is still safe: the time reached so far, never more).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CcdOutcome {
    /// A step fraction in `[0, t_max]` along which the primitives keep more than
    /// the minimum distance apart.
    pub step: f64,
    /// Whether the iteration budget ran out before the query finished.
    pub budget_exhausted: bool,
}

impl CcdOutcome {
    fn finished(step: f64) -> Self {
        Self {
            step,
            budget_exhausted: false,
        }
    }
}

/// 2D: the safe step fraction of point `p` moving by `dp` against the edge
/// `(e0, e1)` moving by `(de0, de1)`, up to `t_max`.
#[allow(clippy::too_many_arguments)]
pub fn point_edge_ccd(
    p: &Vector2,
    e0: &Vector2,
    e1: &Vector2,
    dp: &Vector2,
    de0: &Vector2,
    de1: &Vector2,
    t_max: f64,
    settings: &CcdSettings,
) -> CcdOutcome {
    additive_ccd(
        [*p, *e0, *e1],
        [*dp, *de0, *de1],
        1,
        |[p, e0, e1]| point_edge_distance_squared(p, e0, e1),
        t_max,
        settings,
    )
}

/// 3D: the safe step fraction of point `p` moving by `dp` against the triangle
/// `(t0, t1, t2)` moving by `(dt0, dt1, dt2)`, up to `t_max`.
#[allow(clippy::too_many_arguments)]
pub fn point_triangle_ccd(
    p: &Vector3,
    t0: &Vector3,
    t1: &Vector3,
    t2: &Vector3,
    dp: &Vector3,
    dt0: &Vector3,
    dt1: &Vector3,
    dt2: &Vector3,
    t_max: f64,
    settings: &CcdSettings,
) -> CcdOutcome {
    additive_ccd(
        [*p, *t0, *t1, *t2],
        [*dp, *dt0, *dt1, *dt2],
        1,
        |[p, t0, t1, t2]| point_triangle_distance_squared(p, t0, t1, t2),
        t_max,
        settings,
    )
}

/// 3D: the safe step fraction of edge `(ea0, ea1)` moving by `(dea0, dea1)`
/// against edge `(eb0, eb1)` moving by `(deb0, deb1)`, up to `t_max`.
#[allow(clippy::too_many_arguments)]
pub fn edge_edge_ccd(
    ea0: &Vector3,
    ea1: &Vector3,
    eb0: &Vector3,
    eb1: &Vector3,
    dea0: &Vector3,
    dea1: &Vector3,
    deb0: &Vector3,
    deb1: &Vector3,
    t_max: f64,
    settings: &CcdSettings,
) -> CcdOutcome {
    additive_ccd(
        [*ea0, *ea1, *eb0, *eb1],
        [*dea0, *dea1, *deb0, *deb1],
        2,
        |[ea0, ea1, eb0, eb1]| edge_edge_distance_squared(ea0, ea1, eb0, eb1),
        t_max,
        settings,
    )
}

/// The shared iteration of the module doc. The first `first_primitive_corners`
/// points form one primitive, the rest the other.
fn additive_ccd<const N: usize, const D: usize>(
    mut points: [Vector<D>; N],
    mut displacements: [Vector<D>; N],
    first_primitive_corners: usize,
    distance_squared: impl Fn(&[Vector<D>; N]) -> f64,
    t_max: f64,
    settings: &CcdSettings,
) -> CcdOutcome {
    let rescaling = settings.conservative_rescaling;
    let min_distance = settings.min_distance;
    debug_assert!(rescaling > 0.0 && rescaling <= 1.0, "rescaling {rescaling}");
    debug_assert!(min_distance >= 0.0, "min_distance {min_distance}");
    let finite = |v: &[Vector<D>; N]| v.iter().all(|x| x.iter().all(|c| c.is_finite()));
    if !(t_max > 0.0) || !finite(&points) || !finite(&displacements) {
        return CcdOutcome::finished(0.0);
    }
    let min_distance_squared = min_distance * min_distance;
    // d - ξ, as (d² - ξ²) / (d + ξ); NaN when d² is NaN.
    let separation =
        |d_squared: f64| (d_squared - min_distance_squared) / (d_squared.sqrt() + min_distance);

    let d_squared = distance_squared(&points);
    if !(d_squared > min_distance_squared) {
        return CcdOutcome::finished(0.0);
    }

    let mean = displacements.iter().sum::<Vector<D>>() / N as f64;
    for dx in &mut displacements {
        *dx -= mean;
    }
    let largest_norm = |dx: &[Vector<D>]| dx.iter().map(|v| v.norm()).fold(0.0, f64::max);
    let (first, second) = displacements.split_at(first_primitive_corners);
    let lipschitz = largest_norm(first) + largest_norm(second);
    if lipschitz == 0.0 {
        return CcdOutcome::finished(t_max);
    }

    let mut current = separation(d_squared);
    let gap = (1.0 - rescaling) * current;
    let mut t = 0.0;
    for _ in 0..settings.max_iterations {
        let step_lower_bound = rescaling * current / lipschitz;
        for (x, dx) in points.iter_mut().zip(&displacements) {
            *x += dx * step_lower_bound;
        }
        current = separation(distance_squared(&points));
        if !(current > 0.0) || (t > 0.0 && current < gap) {
            return CcdOutcome::finished(t);
        }
        t += step_lower_bound;
        if t > t_max {
            return CcdOutcome::finished(t_max);
        }
    }
    CcdOutcome {
        step: t,
        budget_exhausted: true,
    }
}

#[cfg(test)]
mod tests;
