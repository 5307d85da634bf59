//! The health of a finished run: what went wrong without stopping it.
//!
//! A run can finish with results that should not be trusted: steps that hit
//! the iteration cap, steps whose line search stalled (both after every
//! subdivision), inverted elements (volume ratio `J <= 0`) where a material
//! forbids them, or a body that reached the ground. A material that allows
//! inversion (stable Neo-Hookean, fixed corotated) may pass through `J <= 0`
//! in an impact: that is reported with the volume ratio of the last frame
//! (recovered or not), not counted as a failure. In a closed scene (no
//! pinned region that moves, so nothing does work on the bodies) the total
//! energy must not rise: a frame whose total energy is above frame 0's by
//! more than [`ENERGY_RISE_LIMIT`] of frame 0's energies (the sum of their
//! magnitudes) is a failure, the integrator having created energy; with
//! friction the work it took out counts as energy the bodies still have
//! (so the check holds the friction to account too), and the summary says
//! how much of the energy lost friction took. [`RunHealth`]
//! gathers these from every output frame's statistics; when any occurred,
//! `run` prints its one-line summary on stderr, and `--strict` makes it a
//! failure (exit code 1).

use crate::scene::approx;
use crate::sim::FrameStats;

/// How far the total energy of a closed scene may rise above frame 0's, as
/// a fraction of the sum of the magnitudes of frame 0's energies.
pub const ENERGY_RISE_LIMIT: f64 = 0.01;

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
    /// Whether nothing does work on the bodies (no moving pinned region), so
    /// the total energy must not rise.
    closed: bool,
    /// Frame 0's total energy and the sum of its parts' magnitudes.
    start_energy: Option<(f64, f64)>,
    /// The first frame whose total energy rose beyond the limit, with that energy.
    energy_rise: Option<(f64, usize)>,
    /// Smallest gap to the ground over all frames, and its frame (`None`
    /// without a ground).
    lowest_gap: Option<(f64, usize)>,
    /// Smallest distance between surface primitives in contact range over
    /// all frames, and its frame (`None` while no pair came within `d_hat`).
    closest_contact: Option<(f64, usize)>,
    /// The last frame's total energy and the work friction had taken out by
    /// then (`None` without friction).
    friction: Option<(f64, f64)>,
}

impl RunHealth {
    /// Nothing recorded yet, for a run whose materials forbid inversion
    /// (`inversion_allowed = false`) or all allow it, and that is `closed`
    /// (no moving pinned region: its energy must not rise) or not.
    pub fn new(inversion_allowed: bool, closed: bool) -> Self {
        Self {
            steps: 0,
            capped_steps: 0,
            stalled_steps: 0,
            min_volume_ratio: None,
            last_volume_ratio: None,
            inversion_allowed,
            closed,
            start_energy: None,
            energy_rise: None,
            lowest_gap: None,
            closest_contact: None,
            friction: None,
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
        // Friction's work is energy the bodies had: with it, the total must
        // not rise either.
        let total = stats.energy.total() + stats.friction_dissipated.unwrap_or(0.0);
        self.friction = stats
            .friction_dissipated
            .map(|work| (stats.energy.total(), work));
        match self.start_energy {
            None => {
                let magnitude = stats.energy.entries().map(|(_, e)| e.abs()).sum();
                self.start_energy = Some((total, magnitude));
            }
            Some((start, magnitude)) if self.closed && self.energy_rise.is_none() => {
                if !(total <= start + ENERGY_RISE_LIMIT * magnitude) {
                    self.energy_rise = Some((total, frame));
                }
            }
            Some(_) => {}
        }
    }

    /// The first frame whose total energy rose beyond `ENERGY_RISE_LIMIT`
    /// (a closed scene only), and the sentence that says so.
    pub fn energy_rise(&self) -> Option<(usize, String)> {
        let ((total, frame), (start, _)) = self.energy_rise.zip(self.start_energy)?;
        let what = if self.friction.is_some() {
            "total energy plus friction's work"
        } else {
            "total energy"
        };
        Some((
            frame,
            format!(
                "{what} {} at frame {frame}, above frame 0's {} by more than {}%: \
                 the integrator created energy",
                approx(total),
                approx(start),
                ENERGY_RISE_LIMIT * 100.0
            ),
        ))
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
        let energy_rose = self.energy_rise.is_some();
        self.capped_steps > 0
            || self.stalled_steps > 0
            || inverted
            || grounded
            || touching
            || energy_rose
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
        if let (Some((last, work)), Some((start, _))) = (self.friction, self.start_energy) {
            parts.push(format!(
                "friction took out {} of the {} of energy lost since frame 0",
                approx(work),
                approx(start - last)
            ));
        }
        if let Some((_, rise)) = self.energy_rise() {
            parts.push(rise);
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
            projected_iterations: 0,
            unconverged_steps: unconverged,
            stalled_steps: 0,
            reanalyses: 0,
            subdivided_steps: 0,
            damped_steps: 0,
            blocked_by: None,
            boundary_error: None,
            contact: None,
            friction_dissipated: None,
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
        let mut health = RunHealth::new(false, true);
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
        let mut capped = RunHealth::new(false, true);
        capped.add(1, 10, &frame(3, 1.0, None));
        capped.add(2, 10, &frame(4, 1.0, None));
        assert!(capped.has_problems());
        assert!(
            capped
                .summary(7)
                .starts_with("7 of 20 steps hit the iteration cap")
        );
        assert!(!capped.summary(7).contains("ground"));

        let mut inverted = RunHealth::new(false, true);
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

        let mut nan = RunHealth::new(false, true);
        nan.add(1, 10, &frame(0, 0.5, None));
        nan.add(2, 10, &frame(0, f64::NAN, None));
        nan.add(3, 10, &frame(0, 0.1, None));
        assert!(nan.has_problems());
        assert!(
            nan.summary(50).contains("NaN (frame 2)"),
            "{}",
            nan.summary(50)
        );

        let mut grounded = RunHealth::new(false, true);
        grounded.add(1, 10, &frame(0, 1.0, Some(0.0)));
        assert!(grounded.has_problems());
        assert!(grounded.summary(50).ends_with("on or below the ground"));
    }

    fn with_energy(mut stats: FrameStats<2>, kinetic: f64, gravity: f64) -> FrameStats<2> {
        stats.energy = EnergyBreakdown {
            kinetic,
            potentials: vec![("elastic", 0.0), ("gravity", gravity)],
        };
        stats
    }

    #[test]
    fn an_inversion_the_material_allows_is_reported_with_its_outcome() {
        let mut recovered = RunHealth::new(true, true);
        recovered.add(1, 10, &frame(0, 0.9, None));
        recovered.add(2, 10, &frame(0, -0.4, None));
        recovered.add(3, 10, &frame(0, 0.8, None));
        assert!(!recovered.has_problems());
        assert!(
            recovered.summary(50).contains(
                "min volume ratio -0.4 (frame 2): inverted, which the material allows, \
                 and recovered (J = 0.8 at the end)"
            ),
            "{}",
            recovered.summary(50)
        );

        let mut held = RunHealth::new(true, true);
        held.add(1, 10, &frame(0, -0.4, None));
        held.add(2, 10, &frame(0, -0.3, None));
        assert!(!held.has_problems());
        assert!(
            held.summary(50)
                .contains("still inverted at the end (J = -0.3)"),
            "{}",
            held.summary(50)
        );

        // The same frames are a failure where the material forbids inversion,
        // and a NaN is one even where it allows it.
        let mut forbidden = RunHealth::new(false, true);
        forbidden.add(1, 10, &frame(0, -0.4, None));
        forbidden.add(2, 10, &frame(0, 0.8, None));
        assert!(forbidden.has_problems());
        let mut nan = RunHealth::new(true, true);
        nan.add(1, 10, &frame(0, f64::NAN, None));
        assert!(nan.has_problems());
    }

    #[test]
    fn a_closed_scene_whose_energy_rises_beyond_one_percent_fails() {
        // Frame 0: kinetic 8, gravity 2 (magnitudes sum 10): the limit is 10.1.
        let mut health = RunHealth::new(false, true);
        health.add(0, 0, &with_energy(frame(0, 1.0, None), 8.0, 2.0));
        health.add(1, 10, &with_energy(frame(0, 1.0, None), 5.0, 5.09));
        assert!(!health.has_problems(), "{}", health.summary(50));
        assert_eq!(health.energy_rise(), None);
        health.add(2, 10, &with_energy(frame(0, 1.0, None), 5.0, 5.2));
        health.add(3, 10, &with_energy(frame(0, 1.0, None), 500.0, 5.2));
        assert!(health.has_problems());
        let (frame_index, sentence) = health.energy_rise().expect("a rise");
        assert_eq!(frame_index, 2, "the first frame above the limit");
        assert!(
            sentence.contains("total energy 10.2 at frame 2, above frame 0's 10 by more than 1%"),
            "{sentence}"
        );
        assert!(
            health
                .summary(50)
                .ends_with("the integrator created energy")
        );

        // A NaN energy is a rise; a scene with moving pinned regions is not checked.
        let mut nan = RunHealth::new(false, true);
        nan.add(0, 0, &with_energy(frame(0, 1.0, None), 8.0, 2.0));
        nan.add(1, 10, &with_energy(frame(0, 1.0, None), f64::NAN, 2.0));
        assert!(nan.has_problems());
        // Friction's work counts: 10 lost, of which friction took 9.95, is
        // healthy and said; taking out 10.2 would be a rise.
        let with_friction = |work: f64| {
            let mut stats = with_energy(frame(0, 1.0, None), 0.0, 0.0);
            stats.friction_dissipated = Some(work);
            stats
        };
        let mut sliding = RunHealth::new(false, true);
        sliding.add(0, 0, &with_energy(frame(0, 1.0, None), 8.0, 2.0));
        sliding.add(1, 10, &with_friction(9.95));
        assert!(!sliding.has_problems(), "{}", sliding.summary(50));
        assert!(
            sliding
                .summary(50)
                .ends_with("friction took out 9.95 of the 10 of energy lost since frame 0"),
            "{}",
            sliding.summary(50)
        );
        sliding.add(2, 10, &with_friction(10.2));
        assert!(sliding.has_problems());
        assert!(
            sliding.energy_rise().is_some_and(
                |(f, s)| f == 2 && s.starts_with("total energy plus friction's work 10.2")
            ),
            "{:?}",
            sliding.energy_rise()
        );

        let mut driven = RunHealth::new(false, false);
        driven.add(0, 0, &with_energy(frame(0, 1.0, None), 8.0, 2.0));
        driven.add(1, 10, &with_energy(frame(0, 1.0, None), 80.0, 2.0));
        assert!(!driven.has_problems());
    }
}
