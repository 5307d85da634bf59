//! Cost of one projected-Newton iteration, split into its phases, for 2D and 3D
//! boxes of growing size.
//!
//! Run with `cargo bench --bench newton`. Each row is the median over several
//! steps that each take exactly one Newton iteration (assembly with PSD
//! projection, numeric Cholesky factorisation and solve, line search), for a
//! box falling towards the ground (gravity and the ground barrier active).
//! Set `ELASTO_BENCH_QUICK=1` for a short run with small meshes only.
//!
//! Then, per mesh: the element work alone (gradient and PSD-projected
//! Hessian of the elasticity with the scatter into the gradient and the
//! gather into the matrix, on one thread, median of 15 passes), in
//! microseconds per element; and, at the end, the peak resident memory of
//! the process (`VmHWM`, after the largest 3D mesh) against the storage of
//! that mesh's Cholesky factor (`nnz(L)` times 8 bytes).

use elasto::assembly::SparseHessian;
use elasto::energy::{Elasticity, EnergyTerm};
use elasto::material::{LameParameters, Material, NeoHookean, YoungPoisson};
use elasto::math::Vector;
use elasto::mesh::Mesh;
use elasto::sim::{Effects, Ground, Simulation, SimulationSettings};
use elasto::solver::PhaseTimes;
use elasto::solver::SolverSettings;
use std::sync::Arc;
use std::time::{Duration, Instant};

const SAMPLES: usize = 5;

fn median(mut values: Vec<Duration>) -> f64 {
    values.sort();
    values[values.len() / 2].as_secs_f64() * 1e3
}

/// Microseconds per element of one gradient-and-Hessian pass of the
/// elasticity (fill, scatter, gather) on one thread, and `nnz(L)`. Each
/// vertex is scaled by a factor in [0.99, 1.01], so that some elements are
/// stretched (a positive definite `dP/dF`, kept as it is) and others
/// compressed (an indefinite one, projected in the SVD frame).
fn element_work<const D: usize>(mesh: &Mesh<D>, material: Material) -> (f64, usize) {
    let mesh = Arc::new(mesh.clone());
    let x: Vec<Vector<D>> = mesh
        .rest_positions()
        .iter()
        .enumerate()
        .map(|(v, p)| p * (1.0 + 0.02 * (((v * 7919) % 13) as f64 / 13.0 - 0.5)))
        .collect();
    let free = (0..mesh.vertex_count()).map(Some).collect();
    let mut hessian = SparseHessian::new(&mesh, free).unwrap();
    let mut gradient = vec![Vector::<D>::zeros(); mesh.vertex_count()];
    let elasticity = Elasticity::new(mesh.clone(), material);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let mut times = Vec::new();
    pool.install(|| {
        for _ in 0..15 {
            hessian.clear();
            let start = Instant::now();
            elasticity.add_gradient_and_hessian(&x, 1.0, &mut gradient, &mut hessian);
            times.push(start.elapsed());
        }
    });
    let per_element = median(times) * 1e3 / mesh.element_count() as f64;
    (per_element, hessian.factor_non_zeros())
}

/// Peak resident memory of this process so far, in MB (`VmHWM`).
fn peak_resident_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

fn bench<const D: usize>(cells: [usize; D]) -> usize {
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
            friction: 0.0,
        }),
        contact: None,
        pinned: Vec::new(),
        obstacles: Vec::new(),
    };
    let settings = SimulationSettings {
        dt: 1.0 / 300.0,
        integrator: Default::default(),
        // One iteration per step, and no retrying of the (unconverged) step as
        // half steps: with the default `max_subdivisions` each step ran 31.
        solver: SolverSettings {
            max_iterations: 1,
            max_subdivisions: 0,
            ..Default::default()
        },
    };
    let velocity = Vector::<D>::from_fn(|k, _| if k == 0 { 0.5 } else { -1.0 });
    let setup = Instant::now();
    let (element_us, factor_non_zeros) =
        element_work(&mesh, Material::NeoHookean(NeoHookean { lame }));
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
    let solve = median(phases.iter().map(|t| t.solve).collect());
    let line_search = median(phases.iter().map(|t| t.line_search).collect());
    println!(
        "{D}D {:>14} {vertices:>8} {elements:>9} {:>10.1} {assembly:>10.2} {factorisation:>10.2} {solve:>8.2} {line_search:>10.2} {:>10.2} {:>7.2} {element_us:>9.2} {factor_non_zeros:>11}",
        format!("{cells:?}"),
        setup.as_secs_f64() * 1e3,
        assembly + factorisation + solve + line_search,
        (assembly + factorisation + solve + line_search) / factorisation,
    );
    factor_non_zeros
}

fn main() {
    let quick = std::env::var_os("ELASTO_BENCH_QUICK").is_some();
    println!(
        "one Newton iteration, median of {SAMPLES} (milliseconds), {} rayon threads",
        rayon::current_num_threads()
    );
    println!(
        "dim {:>14} {:>8} {:>9} {:>10} {:>10} {:>10} {:>8} {:>10} {:>10} {:>7} {:>9} {:>11}",
        "cells",
        "vertices",
        "elements",
        "setup",
        "assembly",
        "factorise",
        "solve",
        "line srch",
        "total",
        "tot/fac",
        "us/elem",
        "nnz(L)"
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
    let mut factor_non_zeros = 0;
    for &n in sizes_3d {
        factor_non_zeros = bench::<3>([n, n, n]);
    }
    let factor_mb = (factor_non_zeros * 8) as f64 / (1024.0 * 1024.0);
    if let Some(peak) = peak_resident_mb() {
        println!(
            "peak resident memory {peak:.0} MB; largest 3D factor L {factor_mb:.0} MB ({factor_non_zeros} non-zeros); ratio {:.2}",
            peak / factor_mb
        );
    }
}
