//! The three time integrators against what each scheme promises: its order of convergence, its energy behaviour, free fall, the report's example, and the scene key `time.integrator`.

use crate::cli_common as common;
use crate::support;

use crate::support::report_drop;
use elasto::energy::{Elasticity, EnergyTerm};
use elasto::integrator::IntegratorKind;
use elasto::math::{DenseMatrix, Vector, Vector2};
use elasto::mesh::Mesh;
use elasto::sim::{Effects, Ground, PinRegion, Simulation, SimulationSettings};
use elasto::solver::SolverSettings;
use std::sync::Arc;

both_dimensions! {
    free_fall_follows_the_parabola => free_fall_2d, free_fall_3d;
}

const BACKWARD_EULER: IntegratorKind = IntegratorKind::BackwardEuler;
const BDF2: IntegratorKind = IntegratorKind::Bdf2;
const NEWMARK: IntegratorKind = IntegratorKind::Newmark;

fn settings(integrator: IntegratorKind, dt: f64, tolerance: f64) -> SimulationSettings {
    SimulationSettings {
        dt,
        integrator,
        solver: SolverSettings {
            tolerance,
            ..Default::default()
        },
    }
}

/// A 4 x 1 Neo-Hookean bar of 4 x 1 cells (8 triangles, 10 vertices), pinned at its left end.
fn bar(gravity: Option<Vector2>) -> (Mesh<2>, Effects<2>) {
    let mesh = Mesh::axis_aligned_box(Vector2::zeros(), Vector2::new(4.0, 1.0), [4, 1]).unwrap();
    let effects = Effects {
        gravity,
        ground: None,
        contact: None,
        pinned: vec![PinRegion::new(
            Vector2::new(-1.0, -1.0),
            Vector2::new(1e-9, 2.0),
        )],
        obstacles: Vec::new(),
    };
    (mesh, effects)
}

fn bar_simulation(
    integrator: IntegratorKind,
    dt: f64,
    gravity: Option<Vector2>,
    velocity: Vector2,
) -> Simulation<2> {
    let (mesh, effects) = bar(gravity);
    Simulation::new(
        mesh,
        support::neo_hookean(),
        1.0,
        effects,
        settings(integrator, dt, 1e-10),
        velocity,
    )
    .unwrap()
}

/// The bar sagging under gravity `(0, -2)` from rest: positions after `steps` steps of `dt`.
fn sagging_bar(integrator: IntegratorKind, dt: f64, steps: usize) -> Vec<Vector2> {
    let mut sim = bar_simulation(
        integrator,
        dt,
        Some(Vector2::new(0.0, -2.0)),
        Vector2::zeros(),
    );
    for _ in 0..steps {
        sim.step().unwrap();
    }
    sim.positions().to_vec()
}

fn max_distance<const D: usize>(a: &[Vector<D>], b: &[Vector<D>]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max)
}

/// Least-squares slope of `log y` against `log x`.
fn log_log_slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = x.iter().zip(y).map(|(a, b)| (a.ln(), b.ln())).unzip();
    let mx = lx.iter().sum::<f64>() / n;
    let my = ly.iter().sum::<f64>() / n;
    let sxy: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = lx.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

/// Positions at `T = 1 s` of the sagging bar for `dt = T/40 ... T/320` against a
/// Newmark reference with `dt = T/10240` (its error is `(1/32)^2` of the finest
/// Newmark run's): the slope of log error against log dt is the order.
#[test]
fn measured_orders_of_convergence() {
    let end_time = 1.0;
    let reference_steps = 10240;
    let reference = sagging_bar(NEWMARK, end_time / reference_steps as f64, reference_steps);
    let steps = [40usize, 80, 160, 320];
    let dts: Vec<f64> = steps.iter().map(|n| end_time / *n as f64).collect();
    for (kind, expected, spread) in [
        (BACKWARD_EULER, 1.0, 0.15),
        (BDF2, 2.0, 0.2),
        (NEWMARK, 2.0, 0.2),
    ] {
        let errors: Vec<f64> = steps
            .iter()
            .zip(&dts)
            .map(|(n, dt)| max_distance(&sagging_bar(kind, *dt, *n), &reference))
            .collect();
        let order = log_log_slope(&dts, &errors);
        println!("{}: errors {errors:?}, order {order:.3}", kind.name());
        assert!(
            (order - expected).abs() <= spread,
            "{}: measured order {order:.3}, expected {expected} ± {spread} (errors {errors:?} for dt {dts:?})",
            kind.name()
        );
    }
}

/// The bar's lowest angular frequency from the linearised problem at rest:
/// the smallest eigenvalue of `M^-1/2 K M^-1/2` over the free unknowns, with
/// `K` the central difference of the elastic gradient.
fn lowest_angular_frequency() -> f64 {
    let (mesh, effects) = bar(None);
    let sim = Simulation::new(
        mesh.clone(),
        support::neo_hookean(),
        1.0,
        effects,
        SimulationSettings::default(),
        Vector2::zeros(),
    )
    .unwrap();
    let free: Vec<usize> = (0..mesh.vertex_count())
        .filter(|&i| sim.free_index()[i].is_some())
        .collect();
    let masses = sim.masses().to_vec();
    let elasticity = Elasticity::new(Arc::new(mesh.clone()), support::neo_hookean());
    let rest = mesh.rest_positions().to_vec();
    let n = 2 * free.len();
    let h = 1e-6;
    let gradient = |x: &[Vector2]| {
        let mut g = vec![Vector2::zeros(); x.len()];
        elasticity.add_gradient(x, 1.0, &mut g);
        g
    };
    let mut k = DenseMatrix::zeros(n, n);
    for (col, &j) in free.iter().enumerate() {
        for a in 0..2 {
            let (mut plus, mut minus) = (rest.clone(), rest.clone());
            plus[j][a] += h;
            minus[j][a] -= h;
            let (gp, gm) = (gradient(&plus), gradient(&minus));
            for (row, &i) in free.iter().enumerate() {
                for b in 0..2 {
                    let stiffness = (gp[i][b] - gm[i][b]) / (2.0 * h);
                    k[(2 * row + b, 2 * col + a)] = stiffness / (masses[i] * masses[j]).sqrt();
                }
            }
        }
    }
    let k = (&k + k.transpose()) * 0.5;
    let lowest = k.symmetric_eigenvalues().min();
    assert!(lowest > 0.0, "the pinned bar must be stable at rest");
    lowest.sqrt()
}

/// The bar vibrating freely (no gravity, no ground) after a uniform kick of
/// `(0, -0.1)`: total energy (kinetic + elastic) after each of 200 steps,
/// 20 per period of the lowest mode (10 periods); element 0 is the start.
fn free_vibration(kind: IntegratorKind, period: f64) -> Vec<f64> {
    let steps_per_period = 20;
    let dt = period / steps_per_period as f64;
    let mut sim = bar_simulation(kind, dt, None, Vector2::new(0.0, -0.1));
    let mut energies = vec![sim.energies().total()];
    for _ in 0..10 * steps_per_period {
        energies.push(sim.step().unwrap().energy.total());
    }
    energies
}

#[test]
fn energy_newmark_keeps_it_backward_euler_loses_it_bdf2_loses_less() {
    let period = 2.0 * std::f64::consts::PI / lowest_angular_frequency();
    let newmark = free_vibration(NEWMARK, period);
    let backward_euler = free_vibration(BACKWARD_EULER, period);
    let bdf2 = free_vibration(BDF2, period);
    let initial = newmark[0];
    assert!(initial > 0.0);
    for e in [&backward_euler, &bdf2] {
        assert_eq!(e[0], initial, "all three start from the same state");
    }
    let newmark_drift = newmark
        .iter()
        .map(|e| (e - initial).abs() / initial)
        .fold(0.0, f64::max);
    let last = |e: &[f64]| e[e.len() - 1] / initial;
    println!(
        "period {period:.4} s; Newmark largest drift {newmark_drift:.3e}; energy left after 10 periods: \
         backward Euler {:.2e}, BDF2 {:.4}, Newmark {:.6}",
        last(&backward_euler),
        last(&bdf2),
        last(&newmark)
    );
    assert!(
        newmark_drift < 0.01,
        "Newmark's energy strayed by {newmark_drift:e} of the initial energy"
    );
    for (n, pair) in backward_euler.windows(2).enumerate() {
        assert!(
            pair[1] <= pair[0] + 1e-12 * initial,
            "backward Euler gained energy in step {n}: {} -> {}",
            pair[0],
            pair[1]
        );
    }
    assert!(
        last(&backward_euler) < 0.9,
        "backward Euler at 20 steps per period should visibly damp, kept {}",
        last(&backward_euler)
    );
    assert!(
        last(&bdf2) > last(&backward_euler),
        "BDF2 kept {} of the energy, backward Euler {}",
        last(&bdf2),
        last(&backward_euler)
    );
}

fn unit<const D: usize>(axis: usize) -> Vector<D> {
    Vector::<D>::from_fn(|k, _| if k == axis { 1.0 } else { 0.0 })
}

/// A free unit box (no elastic force in a rigid translation) under gravity
/// with an initial velocity, 50 steps of 0.01 s, against the parabola
/// `x0 + v0 t + g t^2 / 2` and `v0 + g t`:
/// - Newmark is exact (its `a_0 = g` comes from the setup);
/// - BDF2 has exact velocities and, from its backward-Euler first step, the
///   position offset `3/4 g dt^2 (1 - 3^-n)`: exact once started;
/// - backward Euler has exact velocities and the first-order offset
///   `g dt t / 2`.
fn free_fall_follows_the_parabola<const D: usize>() {
    let g = unit::<D>(1) * -9.81;
    let v0 = unit::<D>(0) * 0.7 + unit::<D>(1) * 2.0;
    let dt = 0.01;
    let steps = 50usize;
    for kind in IntegratorKind::ALL {
        let mesh = support::unit_box::<D>();
        let rest = mesh.rest_positions().to_vec();
        let effects = Effects {
            gravity: Some(g),
            ..Default::default()
        };
        let mut sim = Simulation::new(
            mesh,
            support::stvk(),
            3.0,
            effects,
            settings(kind, dt, 1e-9),
            v0,
        )
        .unwrap();
        for n in 1..=steps {
            sim.step().unwrap();
            let t = n as f64 * dt;
            // The scale of the motion, for relative errors.
            let scale = v0.norm() * t + 0.5 * g.norm() * t * t;
            let offset = match kind {
                IntegratorKind::BackwardEuler => g * (0.5 * dt * t),
                IntegratorKind::Bdf2 => g * (0.75 * dt * dt * (1.0 - 3f64.powi(-(n as i32)))),
                IntegratorKind::Newmark => Vector::<D>::zeros(),
            };
            let exact: Vec<Vector<D>> = rest
                .iter()
                .map(|x0| x0 + v0 * t + g * (0.5 * t * t))
                .collect();
            let expected: Vec<Vector<D>> = exact.iter().map(|x| x + offset).collect();
            let position_error = max_distance(sim.positions(), &expected) / scale;
            let velocity_error = sim
                .velocities()
                .iter()
                .map(|v| (v - (v0 + g * t)).norm())
                .fold(0.0, f64::max)
                / (v0 + g * t).norm().max(v0.norm());
            assert!(
                position_error < 1e-9 && velocity_error < 1e-9,
                "{D}D {} step {n}: relative errors {position_error:e} (positions), {velocity_error:e} (velocities)",
                kind.name()
            );
            // Against the parabola itself: second order for BDF2, first for backward Euler.
            let bound = match kind {
                IntegratorKind::BackwardEuler => 0.5 * g.norm() * dt * t,
                IntegratorKind::Bdf2 => 0.75 * g.norm() * dt * dt,
                IntegratorKind::Newmark => 0.0,
            };
            assert!(max_distance(sim.positions(), &exact) <= bound + 1e-9 * scale);
        }
    }
}

/// The report's example (`tests/integration/report_example.rs`): a 5 x 5 St. Venant-Kirchhoff
/// box released 10 units above the ground, run its full 10 s (the fall, the
/// impact at about 4.5 s and the rebound) with each integrator: no vertex
/// comes within 1% of `a` of the ground (the default stiffness rule's
/// promise), nothing leaves the finite numbers, no element inverts.
#[test]
fn the_report_example_runs_with_every_integrator() {
    for kind in IntegratorKind::ALL {
        let mut sim = report_drop(10.0, 0.1, settings(kind, 1.0 / 300.0, 1e-4));
        let mut min_gap = f64::INFINITY;
        let mut min_volume_ratio = f64::INFINITY;
        for _ in 0..3000 {
            let stats = sim.step().unwrap();
            min_gap = min_gap.min(stats.min_height.unwrap());
            min_volume_ratio = min_volume_ratio.min(stats.min_volume_ratio);
            assert!(
                sim.positions()
                    .iter()
                    .chain(sim.velocities())
                    .all(|x| x.iter().all(|c| c.is_finite())),
                "{}: a position or velocity is not finite at t = {}",
                kind.name(),
                stats.time
            );
        }
        println!(
            "{}: min gap {min_gap:.4}, min J {min_volume_ratio:.4}",
            kind.name()
        );
        assert!(
            min_gap > 0.01 * 0.1,
            "{}: a vertex came within {min_gap:e} of the ground",
            kind.name()
        );
        assert!(
            min_volume_ratio > 0.0,
            "{}: an element inverted",
            kind.name()
        );
    }
}

#[test]
fn scene_files_choose_the_integrator_and_bad_names_list_the_three() {
    let tmp = tempfile::tempdir().unwrap();
    for name in ["backward-euler", "bdf2", "newmark"] {
        let file = tmp.path().join(format!("{name}.toml"));
        let scene = common::SMALL_SCENE.replace(
            "frames = 4",
            &format!("frames = 4\nintegrator = \"{name}\""),
        );
        std::fs::write(&file, scene).unwrap();
        let o = common::elasto(tmp.path(), &["check", file.to_str().unwrap()]);
        common::assert_code(&o, 0);
        let out = format!("run-{name}");
        let o = common::elasto(
            tmp.path(),
            &[
                "run",
                file.to_str().unwrap(),
                "--no-render",
                "-q",
                "--out",
                &out,
            ],
        );
        common::assert_code(&o, 0);
        let resolved = std::fs::read_to_string(tmp.path().join(&out).join("scene.toml")).unwrap();
        assert!(
            resolved.contains(&format!("integrator = \"{name}\"")),
            "the resolved scene lost the integrator:\n{resolved}"
        );
    }
    let file = tmp.path().join("bad.toml");
    let scene = common::SMALL_SCENE.replace("frames = 4", "frames = 4\nintegrator = \"leapfrog\"");
    std::fs::write(&file, scene).unwrap();
    let o = common::elasto(tmp.path(), &["check", file.to_str().unwrap()]);
    common::assert_code(&o, 2);
    let err = common::stderr(&o);
    assert!(
        err.contains("time.integrator") && err.contains("leapfrog"),
        "{err}"
    );
    for name in ["backward-euler", "bdf2", "newmark"] {
        assert!(err.contains(name), "`{name}` missing from:\n{err}");
    }
}

/// A 3D box of 2 x 2 x 2 cells dropped 0.2 above the ground with a sideways
/// push, 1 s with each integrator: the barrier, gravity and Newton's guards
/// work the same in 3D (no vertex within 1% of `a`, no inversion, every step
/// converged).
#[test]
fn a_3d_drop_runs_with_every_integrator() {
    for kind in IntegratorKind::ALL {
        let min = Vector::<3>::new(0.0, 0.2, 0.0);
        let mesh =
            Mesh::axis_aligned_box(min, min + Vector::<3>::from_element(1.0), [2, 2, 2]).unwrap();
        let effects = Effects {
            gravity: Some(Vector::<3>::new(0.0, -9.81, 0.0)),
            ground: Some(Ground {
                height: 0.0,
                activation_distance: 0.05,
                stiffness: None,
                friction: 0.0,
            }),
            contact: None,
            pinned: Vec::new(),
            obstacles: Vec::new(),
        };
        let mut sim = Simulation::new(
            mesh,
            support::neo_hookean(),
            1.0,
            effects,
            settings(kind, 1.0 / 300.0, 1e-4),
            Vector::<3>::new(0.5, 0.0, 0.0),
        )
        .unwrap();
        let (mut min_gap, mut min_volume_ratio, mut unconverged) =
            (f64::INFINITY, f64::INFINITY, 0);
        for _ in 0..300 {
            let stats = sim.step().unwrap();
            min_gap = min_gap.min(stats.min_height.unwrap());
            min_volume_ratio = min_volume_ratio.min(stats.min_volume_ratio);
            unconverged += usize::from(!stats.solver.converged);
        }
        println!(
            "3D {}: min gap {min_gap:.4}, min J {min_volume_ratio:.4}, unconverged steps {unconverged}",
            kind.name()
        );
        assert!(
            min_gap > 0.01 * 0.05,
            "{}: min gap {min_gap:e}",
            kind.name()
        );
        assert!(
            min_volume_ratio > 0.0,
            "{}: an element inverted",
            kind.name()
        );
        assert_eq!(unconverged, 0, "{}: unconverged steps", kind.name());
        assert!(
            sim.positions()
                .iter()
                .all(|x| x.iter().all(|c| c.is_finite())),
            "{}: positions left the finite numbers",
            kind.name()
        );
    }
}
