//! The simulation against closed forms: free fall, rigid motions, the finite-volume
//! force, and a bar hanging under its own weight.

use crate::support::*;
use elasto::energy::{Elasticity, EnergyTerm};
use elasto::finite_volume::{finite_volume_forces, report_face_sum};
use elasto::material::{LameParameters, Material, NeoHookean, StVenantKirchhoff, YoungPoisson};
use elasto::math::{Matrix, Vector};
use elasto::mesh::Mesh;
use elasto::sim::{Effects, PinRegion, Simulation, SimulationSettings};
use elasto::solver::SolverSettings;
use std::sync::Arc;

both_dimensions! {
    free_fall_matches_the_discrete_closed_form => free_fall_2d, free_fall_3d;
    rigid_motions_have_no_energy_and_no_force => rigid_motion_2d, rigid_motion_3d;
    finite_volume_force_is_minus_the_energy_gradient => finite_volume_2d, finite_volume_3d;
}

fn unit<const D: usize>(axis: usize) -> Vector<D> {
    Vector::<D>::from_fn(|k, _| if k == axis { 1.0 } else { 0.0 })
}

/// Backward Euler on free fall: `v_{n+1} = v_n + dt g`, `x_{n+1} = x_n + dt v_{n+1}`,
/// so `x_n = x_0 + n dt v_0 + g dt^2 n (n + 1) / 2` (with `g` pointing down).
fn free_fall_matches_the_discrete_closed_form<const D: usize>() {
    let mesh = unit_box::<D>();
    let rest = mesh.rest_positions().to_vec();
    let g = unit::<D>(1) * -9.81;
    let v0 = unit::<D>(0) * 0.7 + unit::<D>(1) * 2.0;
    let dt = 0.01;
    let settings = SimulationSettings {
        dt,
        integrator: Default::default(),
        solver: SolverSettings {
            tolerance: 1e-9,
            ..Default::default()
        },
    };
    let effects = Effects {
        gravity: Some(g),
        ..Default::default()
    };
    let mut sim = Simulation::new(mesh, stvk(), 3.0, effects, settings, v0).unwrap();
    let steps = 50;
    for _ in 0..steps {
        sim.step().unwrap();
    }
    let n = steps as f64;
    let mut worst = 0.0f64;
    for (x, x0) in sim.positions().iter().zip(&rest) {
        let expected = x0 + v0 * (n * dt) + g * (dt * dt * n * (n + 1.0) / 2.0);
        worst = worst.max((x - expected).amax());
    }
    assert!(
        worst < 1e-12,
        "{D}D free fall deviates from the closed form by {worst:e}"
    );
}

fn rotation<const D: usize>(angle: f64) -> Matrix<D> {
    // A rotation in the (0, 1) plane, composed with one in the (1, D-1) plane in 3D.
    let mut r = Matrix::<D>::identity();
    let (s, c) = angle.sin_cos();
    r[(0, 0)] = c;
    r[(0, 1)] = -s;
    r[(1, 0)] = s;
    r[(1, 1)] = c;
    if D == 3 {
        let mut q = Matrix::<D>::identity();
        let (s, c) = (0.5 * angle).sin_cos();
        q[(1, 1)] = c;
        q[(1, D - 1)] = -s;
        q[(D - 1, 1)] = s;
        q[(D - 1, D - 1)] = c;
        r = q * r;
    }
    r
}

fn rigid_motions_have_no_energy_and_no_force<const D: usize>() {
    let mesh = Arc::new(unit_box::<D>());
    for material in [stvk(), neo_hookean()] {
        let elasticity = Elasticity::new(mesh.clone(), material);
        for angle in [0.0, 0.3, 1.7, -2.9] {
            let r = rotation::<D>(angle);
            let shift = Vector::<D>::from_fn(|k, _| 1.5 - k as f64);
            let x: Vec<Vector<D>> = mesh
                .rest_positions()
                .iter()
                .map(|p| r * p + shift)
                .collect();
            let energy = elasticity.value(&x);
            let mut gradient = vec![Vector::<D>::zeros(); x.len()];
            elasticity.add_gradient(&x, 1.0, &mut gradient);
            let force = gradient.iter().map(|g| g.amax()).fold(0.0, f64::max);
            // Stresses are of order E = 100; round-off of order 1e-13 relative.
            assert!(
                energy.abs() < 1e-12,
                "{material:?} {D}D: rigid motion (angle {angle}) has energy {energy:e}"
            );
            assert!(
                force < 1e-11,
                "{material:?} {D}D: rigid motion (angle {angle}) has force {force:e}"
            );
        }
    }
}

fn finite_volume_force_is_minus_the_energy_gradient<const D: usize>() {
    let mut rng = Rng::new(11);
    let mesh = Arc::new(unit_box::<D>());
    let lame = lame();
    let x = perturbed(mesh.rest_positions(), 0.1, &mut rng);
    let check = |material: Material, fv: Vec<Vector<D>>, literal: Vec<Vector<D>>| {
        let elasticity = Elasticity::new(mesh.clone(), material);
        let mut gradient = vec![Vector::<D>::zeros(); x.len()];
        elasticity.add_gradient(&x, 1.0, &mut gradient);
        let scale = gradient.iter().map(|g| g.amax()).fold(0.0, f64::max);
        for (v, ((f, g), sum)) in fv.iter().zip(&gradient).zip(&literal).enumerate() {
            assert!(
                (f + g).amax() < 1e-12 * scale,
                "{D}D vertex {v}: finite-volume force {f:?} vs -gradient {:?}",
                -g
            );
            // The report's literal sum is D times the force.
            assert!((sum - f * D as f64).amax() < 1e-12 * scale);
        }
    };
    let svk = StVenantKirchhoff { lame };
    check(
        Material::StVenantKirchhoff(svk),
        finite_volume_forces(&mesh, &svk, &x),
        report_face_sum(&mesh, &svk, &x),
    );
    let nh = NeoHookean { lame };
    check(
        Material::NeoHookean(nh),
        finite_volume_forces(&mesh, &nh, &x),
        report_face_sum(&mesh, &nh, &x),
    );
}

/// A bar of length `L` hanging from its pinned top under gravity: in small
/// strain, uniaxial stress `sigma(s) = rho g s` at distance `s` above the tip, so
/// the tip moves down by `rho g L^2 / (2 E')`. With Poisson's ratio 0 the lateral
/// contraction that the pinned top would resist vanishes and `E' = E` in 3D and in
/// 2D plane strain alike (for nu != 0, a 2D plane-strain bar free at its sides has
/// `E' = E / (1 - nu^2)`).
///
/// One backward-Euler step with a huge time step (1e4 s) is the static
/// equilibrium: the inertia term is negligible next to `dt^2 U`.
fn hanging_bar_tip<const D: usize>(cells_along: usize, cells_across: usize) -> (f64, f64) {
    let (length, width, young, density, g) = (4.0, 0.4, 1.0e5, 1.0, 1.0);
    let min = Vector::<D>::from_fn(|k, _| if k == 1 { -length } else { 0.0 });
    let max = Vector::<D>::from_fn(|k, _| if k == 1 { 0.0 } else { width });
    let cells: [usize; D] =
        std::array::from_fn(|k| if k == 1 { cells_along } else { cells_across });
    let mesh = Mesh::axis_aligned_box(min, max, cells).unwrap();
    let lame: LameParameters = YoungPoisson {
        young,
        poisson: 0.0,
    }
    .into();
    // The top row (rest y = 0) is pinned.
    let pinned = PinRegion::new(
        Vector::<D>::from_fn(|k, _| if k == 1 { -1e-9 } else { -1.0 }),
        Vector::<D>::from_element(1.0),
    );
    let effects = Effects {
        gravity: Some(unit::<D>(1) * -g),
        ground: None,
        contact: None,
        pinned: vec![pinned],
        obstacles: Vec::new(),
    };
    let settings = SimulationSettings {
        dt: 1e4,
        integrator: Default::default(),
        solver: SolverSettings {
            tolerance: 1e-12,
            max_iterations: 100,
            ..Default::default()
        },
    };
    let mut sim = Simulation::new(
        mesh,
        Material::NeoHookean(NeoHookean { lame }),
        density,
        effects,
        settings,
        Vector::<D>::zeros(),
    )
    .unwrap();
    let stats = sim.step().unwrap().solver;
    assert!(
        stats.converged,
        "{D}D static solve did not converge: {stats:?}"
    );
    let tip: f64 = sim
        .mesh()
        .rest_positions()
        .iter()
        .zip(sim.positions())
        .filter(|(p, _)| p[1] < -length + 1e-9)
        .map(|(p, x)| p[1] - x[1])
        .sum::<f64>()
        / sim
            .mesh()
            .rest_positions()
            .iter()
            .filter(|p| p[1] < -length + 1e-9)
            .count() as f64;
    (tip, density * g * length * length / (2.0 * young))
}

#[test]
fn hanging_bar_2d_matches_small_strain_theory() {
    let (tip, analytic) = hanging_bar_tip::<2>(40, 4);
    let error = relative_error(tip, analytic, 0.0);
    eprintln!("2D tip {tip:e} analytic {analytic:e}");
    assert!(
        error < 0.02,
        "2D tip displacement {tip:e} vs analytic {analytic:e} ({:.2}%)",
        100.0 * error
    );
}

#[test]
fn hanging_bar_3d_matches_small_strain_theory() {
    let (tip, analytic) = hanging_bar_tip::<3>(24, 2);
    let error = relative_error(tip, analytic, 0.0);
    assert!(
        error < 0.02,
        "3D tip displacement {tip:e} vs analytic {analytic:e} ({:.2}%)",
        100.0 * error
    );
}
