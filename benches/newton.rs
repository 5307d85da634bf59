//! Cost of one projected-Newton iteration, split into its phases, for 2D and 3D
//! boxes of growing size.
//!
//! Run with `cargo bench --bench newton`. Each row is the median over several
//! steps that each take exactly one Newton iteration (assembly with PSD
//! projection, numeric Cholesky factorisation and solve, line search), for a
//! box falling towards the ground (gravity and the ground barrier active).
//! Set `ELASTO_BENCH_QUICK=1` for a short run with small meshes only.

use elasto::material::{LameParameters, Material, NeoHookean, YoungPoisson};
use elasto::math::Vector;
use elasto::mesh::Mesh;
use elasto::sim::{Effects, Ground, Simulation, SimulationSettings};
use elasto::solver::PhaseTimes;
use elasto::solver::SolverSettings;
use std::time::{Duration, Instant};

const SAMPLES: usize = 5;

fn median(mut values: Vec<Duration>) -> f64 {
    values.sort();
    values[values.len() / 2].as_secs_f64() * 1e3
}

fn bench<const D: usize>(cells: [usize; D]) {
    let min = Vector::<D>::from_fn(|k, _| if k == 1 { 0.5 } else { 0.0 });
    let mesh = Mesh::axis_aligned_box(min, min + Vector::<D>::from_element(1.0), cells).unwrap();
    let (vertices, elements) = (mesh.vertex_count(), mesh.element_count());
    let lame: LameParameters = YoungPoisson {
        young: 1e4,
        poisson: 0.3,
    }
    .into();
    let effects = Effects {
        gravity: Some(Vector::<D>::from_fn(
            |k, _| if k == 1 { -9.81 } else { 0.0 },
        )),
        ground: Some(Ground {
            height: 0.0,
            activation_distance: 0.1,
            stiffness: None,
        }),
        pinned: Vec::new(),
    };
    let settings = SimulationSettings {
        dt: 1.0 / 300.0,
        integrator: Default::default(),
        solver: SolverSettings {
            max_iterations: 1,
            ..Default::default()
        },
    };
    let velocity = Vector::<D>::from_fn(|k, _| if k == 0 { 0.5 } else { -1.0 });
    let setup = Instant::now();
    let mut sim = Simulation::new(
        mesh,
        Material::NeoHookean(NeoHookean { lame }),
        1000.0,
        effects,
        settings,
        velocity,
    )
    .unwrap();
    let setup = setup.elapsed();
    let mut phases: Vec<PhaseTimes> = Vec::new();
    for _ in 0..SAMPLES {
        let stats = sim.step().unwrap().solver;
        phases.push(stats.times);
    }
    let assembly = median(phases.iter().map(|t| t.assembly).collect());
    let factorisation = median(phases.iter().map(|t| t.factorisation).collect());
    let line_search = median(phases.iter().map(|t| t.line_search).collect());
    println!(
        "{D}D {:>14} {vertices:>8} {elements:>9} {:>10.1} {assembly:>10.2} {factorisation:>10.2} {line_search:>10.2} {:>10.2}",
        format!("{cells:?}"),
        setup.as_secs_f64() * 1e3,
        assembly + factorisation + line_search
    );
}

fn main() {
    let quick = std::env::var_os("ELASTO_BENCH_QUICK").is_some();
    println!(
        "one Newton iteration, median of {SAMPLES} (milliseconds), {} rayon threads",
        rayon::current_num_threads()
    );
    println!(
        "dim {:>14} {:>8} {:>9} {:>10} {:>10} {:>10} {:>10} {:>10}",
        "cells", "vertices", "elements", "setup", "assembly", "factorise", "line srch", "total"
    );
    let sizes_2d: &[usize] = if quick {
        &[10, 20]
    } else {
        &[10, 40, 100, 160]
    };
    for &n in sizes_2d {
        bench::<2>([n, n]);
    }
    let sizes_3d: &[usize] = if quick { &[4, 6] } else { &[5, 10, 16, 21] };
    for &n in sizes_3d {
        bench::<3>([n, n, n]);
    }
}
