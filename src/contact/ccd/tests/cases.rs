//! Constructed CCD cases with known answers: head-on contacts, long throws,
//! grazing and sliding, no relative motion, close starts, thickness, budget,
//! non-finite input.

use super::*;

fn v2(x: f64, y: f64) -> Vector2 {
    Vector2::new(x, y)
}
fn v3(x: f64, y: f64, z: f64) -> Vector3 {
    Vector3::new(x, y, z)
}
fn unit_edge() -> [Vector2; 2] {
    [v2(0.0, 0.0), v2(1.0, 0.0)]
}
fn unit_triangle() -> [Vector3; 3] {
    [v3(0.0, 0.0, 0.0), v3(1.0, 0.0, 0.0), v3(0.0, 1.0, 0.0)]
}
fn point_on_static_edge(p: Vector2, dp: Vector2) -> PointEdge {
    let [e0, e1] = unit_edge();
    Motion {
        x: [p, e0, e1],
        dx: [dp, Vector2::zeros(), Vector2::zeros()],
    }
}
fn point_on_static_triangle(p: Vector3, dp: Vector3) -> Triangle {
    let [t0, t1, t2] = unit_triangle();
    Motion {
        x: [p, t0, t1, t2],
        dx: [dp, Vector3::zeros(), Vector3::zeros(), Vector3::zeros()],
    }
}

fn assert_close(actual: f64, expected: f64, tolerance: f64) {
    assert!(
        (actual - expected).abs() <= tolerance,
        "{actual} vs {expected}"
    );
}

/// Head-on at the approach speed: the first step reaches `s toi` and the
/// second would close the gap, so the answer is `0.9 toi`.
#[test]
fn head_on_contacts_answer_the_rescaled_time_of_impact() {
    let settings = CcdSettings::default();
    // A vertex onto an edge's end point, from above and along the edge's line.
    for (p, dp) in [(v2(1.0, 1.0), v2(0.0, -2.0)), (v2(2.0, 0.0), v2(-2.0, 0.0))] {
        let motion = point_on_static_edge(p, dp);
        let outcome = pe_ccd(&motion, 1.0, &settings);
        assert_close(outcome.step, 0.45, 1e-12);
        check(&motion, outcome, Some(0.5), pe_distance, 1.0);
    }
    // A common translation of both primitives changes nothing (the mean
    // displacement is taken out before the Lipschitz bound).
    let shifted = Motion {
        x: [v2(1.0, 1.0), v2(0.0, 0.0), v2(1.0, 0.0)],
        dx: [v2(5.0, -2.0), v2(5.0, 0.0), v2(5.0, 0.0)],
    };
    assert_close(pe_ccd(&shifted, 1.0, &settings).step, 0.45, 1e-12);
    // A vertex onto a triangle's corner.
    assert_close(
        pe_contact(&point_on_static_edge(v2(1.0, 1.0), v2(0.0, -2.0))).unwrap(),
        0.5,
        1e-12,
    );
    let motion = point_on_static_triangle(v3(0.0, 0.0, 1.0), v3(0.0, 0.0, -2.0));
    assert_close(pt_ccd(&motion, 1.0, &settings).step, 0.45, 1e-12);
    // An edge's end point onto the other edge's end point (out of plane).
    let motion = Motion {
        x: [
            v3(0.0, 0.0, 0.0),
            v3(1.0, 0.0, 0.0),
            v3(1.0, 1.0, 0.0),
            v3(1.0, 2.0, 1.0),
        ],
        dx: [
            Vector3::zeros(),
            Vector3::zeros(),
            v3(0.0, -2.0, 0.0),
            v3(0.0, -2.0, 0.0),
        ],
    };
    assert_close(ee_contact(&motion).unwrap(), 0.5, 1e-12);
    assert_close(ee_ccd(&motion, 1.0, &settings).step, 0.45, 1e-12);
    // A point at -100 units/s over a 1/30 s step: 1 unit away, impact at 0.3.
    let motion = point_on_static_triangle(v3(0.2, 0.2, 1.0), v3(0.0, 0.0, -100.0 / 30.0));
    assert_close(pt_contact(&motion).unwrap(), 0.3, 1e-12);
    assert_close(pt_ccd(&motion, 1.0, &settings).step, 0.27, 1e-12);
    // A smaller t_max caps the answer; a t_max past 0.9 toi does not.
    let motion = point_on_static_edge(v2(1.0, 1.0), v2(0.0, -2.0));
    assert_eq!(pe_ccd(&motion, 0.3, &settings).step, 0.3);
    assert_close(pe_ccd(&motion, 0.46, &settings).step, 0.45, 1e-12);
}

/// Bodies thrown 100 times their size in one step.
#[test]
fn steps_far_longer_than_the_primitives() {
    let settings = CcdSettings::default();
    let motion = point_on_static_edge(v2(0.5, 50.0), v2(0.0, -100.0));
    assert_close(pe_ccd(&motion, 1.0, &settings).step, 0.45, 1e-12);
    // A triangle thrown through a static point (impact at 0.5).
    let [t0, t1, t2] = unit_triangle();
    let throw = v3(0.0, 0.0, -100.0);
    let motion = Motion::through(
        [v3(0.25, 0.25, 0.0), t0, t1, t2],
        [Vector3::zeros(), throw, throw, throw],
        0.5,
    );
    assert_close(pt_contact(&motion).unwrap(), 0.5, 1e-12);
    let outcome = pt_ccd(&motion, 1.0, &settings);
    assert_close(outcome.step, 0.45, 1e-12);
    // An edge thrown across another (impact at 0.5).
    let motion = Motion {
        x: [
            v3(0.0, 0.0, 0.0),
            v3(1.0, 0.0, 0.0),
            v3(0.5, 50.0, -0.5),
            v3(0.5, 50.0, 0.5),
        ],
        dx: [
            Vector3::zeros(),
            Vector3::zeros(),
            v3(0.0, -100.0, 0.0),
            v3(0.0, -100.0, 0.0),
        ],
    };
    assert_close(ee_ccd(&motion, 1.0, &settings).step, 0.45, 1e-12);
    // Thrown past at half a unit: no contact, but the first step (0.9 of the
    // initial distance, 50) is all the answer takes: the next would come
    // within 10% of it.
    let motion = point_on_static_edge(v2(-50.0, 0.5), v2(100.0, 0.0));
    assert_eq!(pe_contact(&motion), None);
    let outcome = pe_ccd(&motion, 1.0, &settings);
    check(&motion, outcome, None, pe_distance, 1.0);
    assert_close(outcome.step, 0.9 * 2500.25f64.sqrt() / 100.0, 1e-12);
}

#[test]
fn grazing_and_sliding_motions() {
    let settings = CcdSettings::default();
    let h = 1e-3;
    // Passing over the edge's line at height h from far away: the answer
    // stops one step before the point comes within 10% of its start distance.
    let motion = point_on_static_edge(v2(-1.0, h), v2(3.0, 0.0));
    assert_eq!(pe_contact(&motion), None);
    let outcome = pe_ccd(&motion, 1.0, &settings);
    check(&motion, outcome, None, pe_distance, 1.0);
    assert_close(outcome.step, 0.9 * (1.0 + h * h).sqrt() / 3.0, 1e-12);
    // Sliding at height h along the edge and over the triangle: ~900 and
    // ~500 iterations of 0.9 h, then the whole step.
    let motion = point_on_static_edge(v2(0.1, h), v2(0.8, 0.0));
    assert_eq!(
        pe_ccd(&motion, 1.0, &settings),
        CcdOutcome {
            step: 1.0,
            budget_exhausted: false
        }
    );
    let motion = point_on_static_triangle(v3(0.1, 0.1, h), v3(0.3, 0.3, 0.0));
    assert_eq!(
        pt_ccd(&motion, 1.0, &settings),
        CcdOutcome {
            step: 1.0,
            budget_exhausted: false
        }
    );
    // Parallel edges sliding at distance h, then sliding while closing in
    // (contact at 0.5 after a very oblique approach: ~640 iterations).
    let edges = |db: Vector3| Motion {
        x: [
            v3(0.0, 0.0, 0.0),
            v3(1.0, 0.0, 0.0),
            v3(0.0, h, 0.0),
            v3(1.0, h, 0.0),
        ],
        dx: [Vector3::zeros(), Vector3::zeros(), db, db],
    };
    let sliding = edges(v3(0.5, 0.0, 0.0));
    assert_eq!(
        ee_ccd(&sliding, 1.0, &settings),
        CcdOutcome {
            step: 1.0,
            budget_exhausted: false
        }
    );
    let closing = edges(v3(0.5, -2.0 * h, 0.0));
    let outcome = ee_ccd(&closing, 1.0, &settings);
    check(&closing, outcome, Some(0.5), ee_distance, 1.0);
    assert!(outcome.step > 0.44, "{}", outcome.step);
}

#[test]
fn no_relative_motion_answers_t_max() {
    let settings = CcdSettings::default();
    let still = point_on_static_edge(v2(0.5, 0.1), Vector2::zeros());
    assert_eq!(
        pe_ccd(&still, 0.7, &settings),
        CcdOutcome {
            step: 0.7,
            budget_exhausted: false
        }
    );
    // A subnormal motion: its norm underflows to 0, no relative motion.
    let creeping = point_on_static_edge(v2(0.5, 0.1), v2(0.0, -1e-320));
    assert_eq!(pe_ccd(&creeping, 0.7, &settings).step, 0.7);
    // Moving together (0.1 is not exact in binary: the mean leaves ~1e-17).
    let common2 = v2(0.1, -3.0);
    let together = Motion {
        x: still.x,
        dx: [common2; 3],
    };
    assert_eq!(pe_ccd(&together, 0.7, &settings).step, 0.7);
    let common3 = v3(0.1, -3.0, 0.7);
    let pt = point_on_static_triangle(v3(0.2, 0.2, 0.01), Vector3::zeros());
    assert_eq!(pt_ccd(&pt, 0.7, &settings).step, 0.7);
    assert_eq!(
        pt_ccd(
            &Motion {
                x: pt.x,
                dx: [common3; 4]
            },
            0.7,
            &settings
        )
        .step,
        0.7
    );
    let ee = Motion {
        x: [
            v3(0.0, 0.0, 0.0),
            v3(1.0, 0.0, 0.0),
            v3(0.5, -0.5, 0.01),
            v3(0.5, 0.5, 0.01),
        ],
        dx: [Vector3::zeros(); 4],
    };
    assert_eq!(ee_ccd(&ee, 0.7, &settings).step, 0.7);
    assert_eq!(
        ee_ccd(
            &Motion {
                x: ee.x,
                dx: [common3; 4]
            },
            0.7,
            &settings
        )
        .step,
        0.7
    );
}

#[test]
fn starting_very_close() {
    let settings = CcdSettings::default();
    // 1e-8 away, closing at 1e-6 per step: impact at 0.01, also far from the origin.
    for offset in [0.0, 1e3] {
        let [e0, e1] = unit_edge();
        let shift = v2(offset, 0.0);
        let motion = Motion {
            x: [v2(0.5 + offset, 1e-8), e0 + shift, e1 + shift],
            dx: [v2(0.0, -1e-6), Vector2::zeros(), Vector2::zeros()],
        };
        let outcome = pe_ccd(&motion, 1.0, &settings);
        check(&motion, outcome, Some(0.01), pe_distance, 1.0);
        assert_close(outcome.step, 0.009, 1e-12);
    }
    let motion = point_on_static_triangle(v3(0.2, 0.2, 1e-8), v3(0.0, 0.0, -1e-6));
    assert_close(pt_ccd(&motion, 1.0, &settings).step, 0.009, 1e-12);
    // Touching or within the minimum distance: do not move.
    let touching = point_on_static_edge(v2(0.5, 0.0), v2(0.0, 1.0));
    assert_eq!(pe_ccd(&touching, 1.0, &settings).step, 0.0);
    let thick = CcdSettings {
        min_distance: 0.1,
        ..settings
    };
    let inside = point_on_static_edge(v2(0.5, 0.05), v2(0.0, 1.0));
    assert_eq!(pe_ccd(&inside, 1.0, &thick).step, 0.0);
}

/// With a thickness ξ the contact is at distance ξ: 1 unit away at unit
/// speed, it is at 0.9, and the answer keeps 10% of the remaining 0.9.
#[test]
fn minimum_distance_is_kept() {
    let thick = CcdSettings {
        min_distance: 0.1,
        ..CcdSettings::default()
    };
    let motion = point_on_static_edge(v2(0.5, 1.0), v2(0.0, -1.0));
    assert_close(pe_ccd(&motion, 1.0, &thick).step, 0.81, 1e-12);
    let motion = point_on_static_triangle(v3(0.2, 0.2, 1.0), v3(0.0, 0.0, -1.0));
    assert_close(pt_ccd(&motion, 1.0, &thick).step, 0.81, 1e-12);
}

#[test]
fn an_exhausted_budget_returns_the_safe_time_reached() {
    let tiny = CcdSettings {
        max_iterations: 3,
        ..CcdSettings::default()
    };
    let h = 1e-3;
    // Sliding at height h: each iteration advances 0.9 h / 0.8.
    let motion = point_on_static_edge(v2(0.1, h), v2(0.8, 0.0));
    let outcome = pe_ccd(&motion, 1.0, &tiny);
    assert!(outcome.budget_exhausted);
    assert_close(outcome.step, 3.0 * 0.9 * h / 0.8, 1e-15);
    assert_close(pe_distance(&motion.at(outcome.step)).sqrt(), h, 1e-15);
    let none = CcdSettings {
        max_iterations: 0,
        ..tiny
    };
    assert_eq!(
        pe_ccd(&motion, 1.0, &none),
        CcdOutcome {
            step: 0.0,
            budget_exhausted: true
        }
    );
    // The default budget also runs out for sliding over 1e6 times the distance.
    let motion = point_on_static_edge(v2(0.1, 1e-7), v2(0.8, 0.0));
    let outcome = pe_ccd(&motion, 1.0, &CcdSettings::default());
    assert!(outcome.budget_exhausted);
    assert_close(outcome.step, 10_000.0 * 0.9 * 1e-7 / 0.8, 1e-12);
}

#[test]
fn non_finite_input_answers_zero() {
    let settings = CcdSettings::default();
    let good = point_on_static_edge(v2(0.5, 1.0), v2(0.0, -2.0));
    let stop = CcdOutcome {
        step: 0.0,
        budget_exhausted: false,
    };
    for bad in [f64::NAN, f64::INFINITY] {
        let mut position = good;
        position.x[1].x = bad;
        assert_eq!(pe_ccd(&position, 1.0, &settings), stop);
        let mut displacement = good;
        displacement.dx[0].y = bad;
        assert_eq!(pe_ccd(&displacement, 1.0, &settings), stop);
        let mut pt = point_on_static_triangle(v3(0.2, 0.2, 1.0), v3(0.0, 0.0, -2.0));
        pt.dx[3].z = bad;
        assert_eq!(pt_ccd(&pt, 1.0, &settings), stop);
        let mut ee = Motion {
            x: [
                v3(0.0, 0.0, 0.0),
                v3(1.0, 0.0, 0.0),
                v3(0.5, -0.5, 1.0),
                v3(0.5, 0.5, 1.0),
            ],
            dx: [Vector3::zeros(); 4],
        };
        ee.x[2].y = bad;
        assert_eq!(ee_ccd(&ee, 1.0, &settings), stop);
    }
    assert_eq!(pe_ccd(&good, f64::NAN, &settings), stop);
    assert_eq!(pe_ccd(&good, -1.0, &settings), stop);
    // An unbounded t_max with a separating motion ends too (the steps grow
    // geometrically until the positions overflow) at a huge, safe step.
    let apart = point_on_static_edge(v2(0.5, 1.0), v2(0.0, 1.0));
    let outcome = pe_ccd(&apart, f64::INFINITY, &settings);
    assert!(
        outcome.step > 1e100 && !outcome.budget_exhausted,
        "{outcome:?}"
    );
}
