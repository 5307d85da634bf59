//! The health of a finished run: what went wrong without stopping it.
//!
//! A run can finish with results that should not be trusted: steps that hit
//! the iteration cap, steps whose line search stalled (both after every
//! subdivision), inverted elements (volume ratio `J <= 0`) where a material
//! forbids them, or a body that reached the ground. A material that allows
//! inversion (stable Neo-Hookean, fixed corotated) may pass through `J <= 0`
//! in an impact: that is reported with the volume ratio of the last frame
//! (recovered or not), not counted as a failure. [`RunHealth`]
//! gathers these from every output frame's statistics; when any occurred,
//! `run` prints its one-line summary on stderr, and `--strict` makes it a
//! failure (exit code 1).

use crate::scene::approx;
use crate::sim::FrameStats;

/// What went wrong over the frames of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunHealth {
    /// Time steps taken.
    steps: usize,
    /// Steps that hit the iteration cap without meeting the tolerance.
    capped_steps: usize,
    /// Steps whose line search stalled before meeting the tolerance.
    stalled_steps: usize,
    /// Smallest volume ratio over all frames, and its frame.
    min_volume_ratio: Option<(f64, usize)>,
    /// The volume ratio of the last frame recorded.
    last_volume_ratio: Option<f64>,
    /// Whether every material allows inversion.
    inversion_allowed: bool,
    /// Smallest gap to the ground over all frames, and its frame (`None`
    /// without a ground).
    lowest_gap: Option<(f64, usize)>,
    /// Smallest distance between surface primitives in contact range over
    /// all frames, and its frame (`None` while no pair came within `d_hat`).
    closest_contact: Option<(f64, usize)>,
}

impl RunHealth {
    /// Nothing recorded yet, for a run whose materials forbid inversion
    /// (`inversion_allowed = false`) or all allow it.
    pub fn new(inversion_allowed: bool) -> Self {
        Self {
            steps: 0,
            capped_steps: 0,
            stalled_steps: 0,
            min_volume_ratio: None,
            last_volume_ratio: None,
            inversion_allowed,
            lowest_gap: None,
            closest_contact: None,
        }
    }

    /// Records output frame `frame`, reached in `steps` time steps.
    pub fn add<const D: usize>(&mut self, frame: usize, steps: usize, stats: &FrameStats<D>) {
        self.steps += steps;
        self.capped_steps += stats.unconverged_steps;
        self.stalled_steps += stats.stalled_steps;
        // The lowest value and its first frame; a NaN is worse than any number.
        let lower = |current: Option<(f64, usize)>, value: f64| match current {
            Some((low, _)) if low.is_nan() => current,
            Some((low, _)) if !value.is_nan() && value >= low => current,
            _ => Some((value, frame)),
        };
        self.min_volume_ratio = lower(self.min_volume_ratio, stats.min_volume_ratio);
        self.last_volume_ratio = Some(stats.min_volume_ratio);
        if let Some(gap) = stats.min_height {
            self.lowest_gap = lower(self.lowest_gap, gap);
        }
        if let Some(distance) = stats.contact.and_then(|c| c.min_distance) {
            self.closest_contact = lower(self.closest_contact, distance);
        }
    }

    /// The first frame where two surface primitives touched or crossed
    /// (distance `<= 0`: it must never happen), if one did.
    pub fn first_contact_failure(&self) -> Option<usize> {
        self.closest_contact
            .filter(|(d, _)| !(*d > 0.0))
            .map(|(_, frame)| frame)
    }

    /// Whether anything went wrong: a step at the iteration cap or stalled,
    /// an inverted (or non-finite) element, or a vertex on or below the ground.
    pub fn has_problems(&self) -> bool {
        let inverted = self.min_volume_ratio.is_some_and(|(j, _)| {
            if self.inversion_allowed {
                j.is_nan()
            } else {
                !(j > 0.0)
            }
        });
        let grounded = self.lowest_gap.is_some_and(|(gap, _)| !(gap > 0.0));
        let touching = self.first_contact_failure().is_some();
        self.capped_steps > 0 || self.stalled_steps > 0 || inverted || grounded || touching
    }

    /// The one-line summary, e.g. `12 of 2990 steps hit the iteration cap
    /// (max_iterations = 50), 0 stalled in the line search, min volume ratio
    /// -0.31 (frame 57): inverted elements, lowest ground gap 0.0012 (frame 56)`.
    pub fn summary(&self, max_iterations: usize) -> String {
        let mut parts = Vec::new();
        parts.push(format!(
            "{} of {} steps hit the iteration cap (max_iterations = {max_iterations})",
            self.capped_steps, self.steps
        ));
        parts.push(format!("{} stalled in the line search", self.stalled_steps));
        if let Some((j, frame)) = self.min_volume_ratio {
            let verdict = match self.last_volume_ratio {
                _ if j > 0.0 => String::new(),
                Some(last) if self.inversion_allowed && last > 0.0 => format!(
                    ": inverted, which the material allows, and recovered (J = {} at the end)",
                    approx(last)
                ),
                Some(last) if self.inversion_allowed => format!(
                    ": inverted, which the material allows, and still inverted at the end \
                     (J = {}): the load is more than the material can hold",
                    approx(last)
                ),
                _ => ": inverted elements".to_owned(),
            };
            parts.push(format!(
                "min volume ratio {} (frame {frame}){verdict}",
                approx(j)
            ));
        }
        if let Some((gap, frame)) = self.lowest_gap {
            let verdict = if gap > 0.0 {
                ""
            } else {
                ": on or below the ground"
            };
            parts.push(format!(
                "lowest ground gap {} (frame {frame}){verdict}",
                approx(gap)
            ));
        }
        if let Some((distance, frame)) = self.closest_contact {
            let verdict = if distance > 0.0 {
                ""
            } else {
                ": surfaces touched or crossed"
            };
            parts.push(format!(
                "closest contact distance {} (frame {frame}){verdict}",
                approx(distance)
            ));
        }
        parts.join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vector;
    use crate::sim::EnergyBreakdown;

    fn frame(unconverged: usize, j: f64, gap: Option<f64>) -> FrameStats<2> {
        FrameStats {
            time: 0.0,
            iterations: 0,
            linear_solves: 0,
            backtracks: 0,
            unconverged_steps: unconverged,
            stalled_steps: 0,
            reanalyses: 0,
            subdivided_steps: 0,
            boundary_error: None,
            contact: None,
            energy: EnergyBreakdown::default(),
            centre_of_mass: Vector::<2>::zeros(),
            min_height: gap,
            min_volume_ratio: j,
            times: Default::default(),
            wall_time: Default::default(),
        }
    }

    #[test]
    fn a_healthy_run_has_no_problems() {
        let mut health = RunHealth::new(false);
        health.add(0, 0, &frame(0, 1.0, Some(10.0)));
        health.add(1, 10, &frame(0, 0.98, Some(0.05)));
        health.add(2, 10, &frame(0, 0.99, Some(0.07)));
        assert!(!health.has_problems());
        assert_eq!(
            health.summary(50),
            "0 of 20 steps hit the iteration cap (max_iterations = 50), 0 stalled in the line search, \
             min volume ratio 0.98 (frame 1), lowest ground gap 0.05 (frame 1)"
        );
    }

    #[test]
    fn capped_steps_inversions_and_contact_are_problems() {
        let mut capped = RunHealth::new(false);
        capped.add(1, 10, &frame(3, 1.0, None));
        capped.add(2, 10, &frame(4, 1.0, None));
        assert!(capped.has_problems());
        assert!(
            capped
                .summary(7)
                .starts_with("7 of 20 steps hit the iteration cap")
        );
        assert!(!capped.summary(7).contains("ground"));

        let mut inverted = RunHealth::new(false);
        inverted.add(1, 10, &frame(0, 0.5, Some(1.0)));
        inverted.add(2, 10, &frame(0, -0.25, Some(2.0)));
        inverted.add(3, 10, &frame(0, 0.1, Some(3.0)));
        assert!(inverted.has_problems());
        assert!(
            inverted
                .summary(50)
                .contains("min volume ratio -0.25 (frame 2): inverted elements"),
            "{}",
            inverted.summary(50)
        );

        let mut nan = RunHealth::new(false);
        nan.add(1, 10, &frame(0, 0.5, None));
        nan.add(2, 10, &frame(0, f64::NAN, None));
        nan.add(3, 10, &frame(0, 0.1, None));
        assert!(nan.has_problems());
        assert!(
            nan.summary(50).contains("NaN (frame 2)"),
            "{}",
            nan.summary(50)
        );

        let mut grounded = RunHealth::new(false);
        grounded.add(1, 10, &frame(0, 1.0, Some(0.0)));
        assert!(grounded.has_problems());
        assert!(grounded.summary(50).ends_with("on or below the ground"));
    }
}
