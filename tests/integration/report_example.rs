//! The report's example: a 2D box of 5 x 5 cells released 10 units above the
//! ground under gravity 1 unit/s^2 with barrier width a = 0.1. The report saw a
//! "kick" off the ground; here no vertex may ever reach the ground (nor come
//! closer than 1% of a, the default stiffness rule's promise) and after the
//! first impact the box never rises back to its release height.

use crate::support::report_drop;
use elasto::sim::SimulationSettings;

#[test]
fn the_box_bounces_without_touching_the_ground_or_gaining_height() {
    let release_height = 10.0;
    let a = 0.1;
    let settings = SimulationSettings {
        dt: 1.0 / 300.0,
        ..Default::default()
    };
    let mut sim = report_drop(release_height, a, settings);
    let initial_com = sim.frame_stats().centre_of_mass.y;

    let mut min_gap = f64::INFINITY;
    let mut impacted = false;
    let mut highest_after_impact = f64::NEG_INFINITY;
    let mut unconverged = 0;
    // 10 s: the fall (about 4.5 s), the impact and the rebound.
    for _ in 0..3000 {
        let stats = sim.step().unwrap();
        unconverged += usize::from(!stats.solver.converged);
        // The step's own statistics: the lowest vertex and the centre of mass.
        let bottom = stats.min_height.unwrap();
        min_gap = min_gap.min(bottom);
        if bottom < a {
            impacted = true;
        }
        if impacted {
            highest_after_impact = highest_after_impact.max(bottom);
            let com = stats.centre_of_mass.y;
            assert!(
                com < initial_com,
                "the centre of mass rose back to {com} (released at {initial_com})"
            );
        }
    }
    assert!(impacted, "the box never reached the barrier");
    assert!(
        min_gap > 0.01 * a,
        "a vertex came within {min_gap:e} of the ground (1% of a is {:e})",
        0.01 * a
    );
    assert!(
        highest_after_impact < release_height,
        "the box rose back to {highest_after_impact} after impact"
    );
    assert!(
        highest_after_impact > 1.0,
        "the box should visibly bounce (rose only to {highest_after_impact})"
    );
    assert_eq!(unconverged, 0, "every step should converge");
}
