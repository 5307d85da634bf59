//! Solver options and scene composition: the report's gradient descent, the
//! iteration cap, and effects that exist only when a scene asks for them.

use crate::support::*;
use elasto::math::Vector2;
use elasto::mesh::Mesh;
use elasto::sim::{Effects, Ground, Simulation, SimulationSettings};
use elasto::solver::{SolverMethod, SolverSettings};

fn falling_box(solver: SolverSettings, ground: bool) -> Simulation<2> {
    let mesh =
        Mesh::axis_aligned_box(Vector2::new(0.0, 0.2), Vector2::new(1.0, 1.2), [2, 2]).unwrap();
    let effects = Effects {
        gravity: Some(Vector2::new(0.0, -9.81)),
        ground: ground.then_some(Ground {
            height: 0.0,
            activation_distance: 0.1,
            stiffness: None,
            friction: 0.0,
        }),
        contact: None,
        pinned: Vec::new(),
        obstacles: Vec::new(),
    };
    Simulation::new(
        mesh,
        stvk(),
        1.0,
        effects,
        SimulationSettings {
            dt: 0.01,
            solver,
            ..Default::default()
        },
        Vector2::new(0.3, -1.0),
    )
    .unwrap()
}

#[test]
fn gradient_descent_reaches_the_newton_solution_at_far_greater_cost() {
    let tolerance = 1e-6;
    let mut newton = falling_box(
        SolverSettings {
            tolerance,
            ..Default::default()
        },
        false,
    );
    let newton_stats = newton.step().unwrap().solver;
    let descent_settings = SolverSettings {
        method: SolverMethod::GradientDescent { step: 1e-5 },
        tolerance,
        max_iterations: 1_000_000,
        max_subdivisions: 0,
        ..Default::default()
    };
    let mut descent = falling_box(descent_settings, false);
    let descent_stats = descent.step().unwrap().solver;
    assert!(newton_stats.converged && descent_stats.converged);
    let difference = newton
        .positions()
        .iter()
        .zip(descent.positions())
        .map(|(a, b)| (a - b).amax())
        .fold(0.0, f64::max);
    assert!(
        difference < 1e-5,
        "gradient descent ended {difference:e} away from Newton"
    );
    assert!(
        descent_stats.iterations > 50 * newton_stats.iterations,
        "gradient descent took {} iterations, Newton {}",
        descent_stats.iterations,
        newton_stats.iterations
    );
    assert_eq!(descent_stats.linear_solves, 0);
}

#[test]
fn the_iteration_cap_is_reported_not_fatal() {
    let mut sim = falling_box(
        SolverSettings {
            max_iterations: 1,
            tolerance: 1e-12,
            max_subdivisions: 0,
            ..Default::default()
        },
        true,
    );
    let stats = sim.step().unwrap().solver;
    assert_eq!(stats.iterations, 1);
    assert!(!stats.converged);
    let frame = sim.advance_frame(3).unwrap();
    assert_eq!(frame.unconverged_steps, 3);
    assert_eq!(frame.iterations, 3);
}

#[test]
fn a_scene_without_ground_has_no_contact_term() {
    let without = falling_box(SolverSettings::default(), false);
    let names: Vec<&str> = without.potentials().iter().map(|t| t.name()).collect();
    assert_eq!(names, ["elastic", "gravity"]);
    assert_eq!(without.ground().map(|g| g.stiffness()), None);
    assert_eq!(without.frame_stats().min_height, None);
    let with = falling_box(SolverSettings::default(), true);
    let names: Vec<&str> = with.potentials().iter().map(|t| t.name()).collect();
    assert_eq!(names, ["elastic", "gravity", "barrier"]);
    assert!(with.ground().unwrap().stiffness() > 0.0);
}

#[test]
fn invalid_settings_and_bodies_below_ground_are_errors() {
    let mesh =
        || Mesh::axis_aligned_box(Vector2::new(0.0, -0.5), Vector2::new(1.0, 0.5), [2, 2]).unwrap();
    let effects = Effects {
        ground: Some(Ground {
            height: 0.0,
            activation_distance: 0.1,
            stiffness: None,
            friction: 0.0,
        }),
        ..Default::default()
    };
    let below = Simulation::new(
        mesh(),
        stvk(),
        1.0,
        effects,
        SimulationSettings::default(),
        Vector2::zeros(),
    )
    .err()
    .unwrap();
    assert!(
        below.to_string().contains("vertex 0 starts at height -0.5"),
        "{below}"
    );
    let bad_dt = SimulationSettings {
        dt: -1.0,
        ..Default::default()
    };
    let error = Simulation::new(
        mesh(),
        stvk(),
        1.0,
        Effects::default(),
        bad_dt,
        Vector2::zeros(),
    )
    .err()
    .unwrap();
    assert!(error.to_string().contains("dt"), "{error}");
}
