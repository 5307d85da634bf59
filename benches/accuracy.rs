//! What accuracy costs in time: error against wall time for the report's
//! example, across time steps, Newton tolerances, the two minimisers and mesh
//! resolutions.
//!
//! Run with `cargo bench --bench accuracy`. The error of a run is the largest
//! distance of a vertex (or, across resolutions, of the centre of mass) from a
//! reference run with a 10x smaller time step and a tight tolerance, at the
//! same simulated time. Wall times are medians of three runs.

use elasto::material::{LameParameters, Material, StVenantKirchhoff, YoungPoisson};
use elasto::math::Vector2;
use elasto::mesh::Mesh;
use elasto::sim::{Effects, Ground, Simulation, SimulationSettings};
use elasto::solver::{SolverMethod, SolverSettings};
use std::time::Instant;

struct Run {
    cells: usize,
    dt: f64,
    solver: SolverSettings,
}

/// Simulates the report's drop until `end` seconds; returns positions, centre of mass, median wall time and iterations per step.
fn simulate(run: &Run, end: f64) -> (Vec<Vector2>, Vector2, f64, f64) {
    let mut times = Vec::new();
    let mut result = None;
    let mut iterations = 0;
    for _ in 0..3 {
        let mesh = Mesh::axis_aligned_box(
            Vector2::new(0.0, 10.0),
            Vector2::new(1.0, 11.0),
            [run.cells; 2],
        )
        .unwrap();
        let lame: LameParameters = YoungPoisson {
            young: 300.0,
            poisson: 0.3,
        }
        .into();
        let effects = Effects {
            gravity: Some(Vector2::new(0.0, -1.0)),
            ground: Some(Ground {
                height: 0.0,
                activation_distance: 0.1,
                stiffness: None,
            }),
            pinned: Vec::new(),
        };
        let settings = SimulationSettings {
            dt: run.dt,
            integrator: Default::default(),
            solver: run.solver,
        };
        let material = Material::StVenantKirchhoff(StVenantKirchhoff { lame });
        let mut sim =
            Simulation::new(mesh, material, 1.0, effects, settings, Vector2::zeros()).unwrap();
        let steps = (end / run.dt).round() as usize;
        let start = Instant::now();
        let mut com = Vector2::zeros();
        iterations = 0;
        for _ in 0..steps {
            let step = sim.step().unwrap();
            com = step.centre_of_mass;
            iterations += step.solver.iterations;
        }
        times.push(start.elapsed().as_secs_f64() * 1e3);
        result = Some((sim.positions().to_vec(), com));
    }
    times.sort_by(f64::total_cmp);
    let (positions, com) = result.unwrap();
    let steps = (end / run.dt).round();
    (positions, com, times[1], iterations as f64 / steps)
}

fn max_distance(a: &[Vector2], b: &[Vector2]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max)
}

fn newton(tolerance: f64) -> SolverSettings {
    SolverSettings {
        method: SolverMethod::Newton,
        tolerance,
        max_iterations: 100,
    }
}

fn row(label: &str, wall_ms: f64, reference_ms: f64, error: f64, iterations: f64) {
    println!(
        "{label:<40} {wall_ms:>10.1} {:>9.3} {error:>12.3e} {iterations:>10.1}",
        wall_ms / reference_ms
    );
}

fn main() {
    // Through the impact (about 4.5 s) and into the rebound.
    let end = 5.0;
    let baseline = Run {
        cells: 5,
        dt: 1.0 / 300.0,
        solver: newton(1e-4),
    };
    let (_, _, baseline_ms, _) = simulate(&baseline, end);
    println!(
        "report-drop-2d to t = {end} s; wall time relative to the scene's defaults (dt 1/300, tol 1e-4, 5x5 cells: {baseline_ms:.0} ms)"
    );
    println!(
        "{:<40} {:>10} {:>9} {:>12} {:>10}",
        "run", "wall ms", "x default", "error", "its/step"
    );

    let reference = simulate(
        &Run {
            cells: 5,
            dt: 1.0 / 3000.0,
            solver: newton(1e-8),
        },
        end,
    );
    for dt in [1.0 / 30.0, 1.0 / 100.0, 1.0 / 300.0, 1.0 / 1000.0] {
        let (x, _, ms, its) = simulate(
            &Run {
                cells: 5,
                dt,
                solver: newton(1e-4),
            },
            end,
        );
        row(
            &format!("newton dt 1/{:.0}", 1.0 / dt),
            ms,
            baseline_ms,
            max_distance(&x, &reference.0),
            its,
        );
    }
    for tolerance in [1e-1, 1e-2, 1e-3, 1e-4, 1e-6] {
        let (x, _, ms, its) = simulate(
            &Run {
                cells: 5,
                dt: 1.0 / 300.0,
                solver: newton(tolerance),
            },
            end,
        );
        row(
            &format!("newton tol {tolerance:e}"),
            ms,
            baseline_ms,
            max_distance(&x, &reference.0),
            its,
        );
    }
    // The report's gradient descent (alpha 1e-6) before the impact: 1 s of
    // free fall. Run to the same velocity tolerance as Newton (its stopping
    // rule measures |M^-1 grad E| / dt), and with a fixed number of
    // iterations per step as the report ran it.
    let short = 1.0;
    let reference_short = simulate(
        &Run {
            cells: 5,
            dt: 1.0 / 3000.0,
            solver: newton(1e-8),
        },
        short,
    );
    let (_, _, newton_short_ms, _) = simulate(&baseline, short);
    let descent = |tolerance: f64, max_iterations: usize| SolverSettings {
        method: SolverMethod::GradientDescent { step: 1e-6 },
        tolerance,
        max_iterations,
    };
    for (label, solver) in [
        (
            "gradient descent x100".to_owned(),
            descent(f64::MIN_POSITIVE, 100),
        ),
        (
            "gradient descent x1000".to_owned(),
            descent(f64::MIN_POSITIVE, 1000),
        ),
        (
            "gradient descent tol 1e-2".to_owned(),
            descent(1e-2, 1_000_000),
        ),
        (
            "gradient descent tol 1e-4".to_owned(),
            descent(1e-4, 1_000_000),
        ),
    ] {
        let (x, _, ms, its) = simulate(
            &Run {
                cells: 5,
                dt: 1.0 / 300.0,
                solver,
            },
            short,
        );
        row(
            &format!("{label} (t = {short} s)"),
            ms,
            newton_short_ms,
            max_distance(&x, &reference_short.0),
            its,
        );
    }
    let (x, _, ms, its) = simulate(&baseline, short);
    row(
        &format!("newton tol 1e-4 (t = {short} s)"),
        ms,
        newton_short_ms,
        max_distance(&x, &reference_short.0),
        its,
    );
    // Resolution: the centre of mass against a 40 x 40 mesh.
    let fine = simulate(
        &Run {
            cells: 40,
            dt: 1.0 / 300.0,
            solver: newton(1e-6),
        },
        end,
    );
    for cells in [2, 5, 10, 20] {
        let (_, com, ms, its) = simulate(
            &Run {
                cells,
                dt: 1.0 / 300.0,
                solver: newton(1e-4),
            },
            end,
        );
        row(
            &format!("newton {cells}x{cells} cells (centre of mass)"),
            ms,
            baseline_ms,
            (com - fine.1).norm(),
            its,
        );
    }
}
