//! Regression: Newton tested its tolerance before taking its first step, so with
//! a loose tolerance (1e-2 length/s) a body starting at rest never moved.

use crate::support::stvk;
use elasto::math::Vector2;
use elasto::mesh::Mesh;
use elasto::sim::{Effects, Simulation, SimulationSettings};
use elasto::solver::SolverSettings;

#[test]
fn a_loose_tolerance_still_takes_the_newton_step() {
    let mesh = Mesh::axis_aligned_box(Vector2::zeros(), Vector2::new(1.0, 1.0), [3, 3]).unwrap();
    let rest = mesh.rest_positions().to_vec();
    let g = Vector2::new(0.0, -1.0);
    let dt = 1.0 / 300.0;
    let settings = SimulationSettings {
        dt,
        integrator: Default::default(),
        solver: SolverSettings {
            tolerance: 1e-1,
            ..Default::default()
        },
    };
    let effects = Effects {
        gravity: Some(g),
        ..Default::default()
    };
    let mut sim = Simulation::new(mesh, stvk(), 1.0, effects, settings, Vector2::zeros()).unwrap();
    let steps = 30;
    for _ in 0..steps {
        let stats = sim.step().unwrap();
        assert_eq!(
            stats.solver.iterations, 1,
            "one Newton step meets a loose tolerance"
        );
    }
    // Free fall is quadratic: one Newton step is exact, so the closed form holds.
    let n = steps as f64;
    for (x, x0) in sim.positions().iter().zip(&rest) {
        let expected = x0 + g * (dt * dt * n * (n + 1.0) / 2.0);
        assert!((x - expected).amax() < 1e-12, "{x:?} vs {expected:?}");
    }
}
