//! Issue 33, item 5 (in part): valid-looking extreme parameters that fail
//! at step 0 printed a Rust debug string (`sparse Cholesky factorisation
//! failed: NonPositivePivot { index: 70 }`). The failure now says in words
//! what went wrong and what may help; no Debug-formatted internals. (The
//! command line refuses these parameters before the run now, see
//! `regression_extreme_parameters_failed_at_step_0`; the library, which has
//! no such check, still reports the failure in words.)

use elasto::material::{LameParameters, Material, StVenantKirchhoff, YoungPoisson};
use elasto::math::Vector;
use elasto::mesh::Mesh;
use elasto::sim::{Effects, Ground, Simulation, SimulationSettings};

#[test]
fn a_factorisation_that_fails_says_why_in_words() {
    let mesh = Mesh::axis_aligned_box(
        Vector::<2>::new(0.0, 10.0),
        Vector::<2>::new(1.0, 11.0),
        [5, 5],
    )
    .unwrap();
    let lame: LameParameters = YoungPoisson {
        young: 300.0,
        poisson: 0.3,
    }
    .into();
    let effects = Effects {
        gravity: Some(Vector::<2>::new(0.0, -1.0)),
        ground: Some(Ground {
            height: 0.0,
            activation_distance: 0.1,
            stiffness: None,
            friction: 0.0,
        }),
        contact: None,
        pinned: Vec::new(),
        obstacles: Vec::new(),
    };
    let settings = SimulationSettings {
        dt: 1.0 / 300.0,
        integrator: Default::default(),
        solver: Default::default(),
    };
    // The report's box with its masses lost beside dt² K (density 1e-20).
    let mut sim = Simulation::new(
        mesh,
        Material::StVenantKirchhoff(StVenantKirchhoff { lame }),
        1e-20,
        effects,
        settings,
        Vector::<2>::zeros(),
    )
    .unwrap();
    let err = sim.advance_frame(10).unwrap_err().to_string();
    assert!(
        err.contains("the system matrix is not positive definite in floating point")
            && err.contains("material.density")
            && !err.contains("NonPositivePivot")
            && !err.contains("{ index"),
        "{err}"
    );
}
