//! The sparse Cholesky on its own: the Hessian of a 3D box (Neo-Hookean,
//! slightly deformed, plus the lumped mass over dt^2, as in a time step) at
//! 16^3 and 21^3 cells, analysed and factorised with the nested-dissection
//! order elasto uses and, for comparison, with faer's AMD (the order before).
//!
//! Run with `cargo bench --bench cholesky`. Times are medians of 3 numeric
//! factorisations on one core (the analysis, done once per simulation, is
//! timed once). Each matrix is also written in Matrix Market format to
//! `target/cholesky/box-N.mtx` (lower triangle, `symmetric`), for
//! `benches/cholmod_compare.c` to time CHOLMOD on the very same matrices.
//! Set `ELASTO_BENCH_QUICK=1` for 8^3 and 10^3 cells.

use elasto::assembly::{SparseCholesky, SparseHessian};
use elasto::energy::{Elasticity, EnergyTerm};
use elasto::material::{LameParameters, Material, NeoHookean, YoungPoisson};
use elasto::math::{Matrix, Vector};
use elasto::mesh::Mesh;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use std::io::Write;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

const SAMPLES: usize = 3;

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// The Hessian of a time step of the `n^3` box, with its analysis time (s).
fn box_hessian(n: usize) -> (SparseHessian<3>, f64) {
    let mesh = Mesh::axis_aligned_box(Vector::<3>::zeros(), Vector::<3>::from_element(1.0), [n; 3])
        .unwrap();
    let x: Vec<Vector<3>> = mesh
        .rest_positions()
        .iter()
        .enumerate()
        .map(|(v, p)| p * (1.0 + 0.02 * ((v * 7919) % 13) as f64 / 13.0))
        .collect();
    let masses = mesh.lumped_masses(1000.0);
    let start = Instant::now();
    let free = (0..mesh.vertex_count()).map(Some).collect();
    let mut hessian = SparseHessian::new(&mesh, free).unwrap();
    let analysis = start.elapsed().as_secs_f64();
    let lame: LameParameters = YoungPoisson {
        young: 1e4,
        poisson: 0.3,
    }
    .into();
    let elasticity = Elasticity::new(Arc::new(mesh), Material::NeoHookean(NeoHookean { lame }));
    let dt = 1.0 / 300.0;
    hessian.clear();
    for (v, m) in masses.iter().enumerate() {
        hessian.add_vertex_block(v, &(Matrix::<3>::identity() * *m));
    }
    elasticity.add_hessian(&x, dt * dt, &mut hessian);
    (hessian, analysis)
}

/// Writes the stored lower triangle as a symmetric Matrix Market file.
fn write_matrix_market(hessian: &SparseHessian<3>, path: &Path) -> std::io::Result<()> {
    let (col_ptr, row_idx, values) = hessian.lower_triangle();
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(out, "%%MatrixMarket matrix coordinate real symmetric")?;
    let n = hessian.dofs();
    writeln!(out, "{n} {n} {}", values.len())?;
    for col in 0..n {
        for t in col_ptr[col]..col_ptr[col + 1] {
            writeln!(out, "{} {} {:e}", row_idx[t] + 1, col + 1, values[t])?;
        }
    }
    out.flush()
}

fn main() {
    let quick = std::env::var_os("ELASTO_BENCH_QUICK").is_some();
    let sizes: &[usize] = if quick { &[8, 10] } else { &[16, 21] };
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/cholesky");
    std::fs::create_dir_all(&folder).unwrap();
    println!(
        "sparse Cholesky of a 3D box Hessian, one core; analysis once, factorisation median of {SAMPLES} (seconds)"
    );
    println!(
        "{:>6} {:>7} {:>10} | {:>9} {:>9} {:>11} | {:>9} {:>9} {:>11}",
        "cells",
        "dofs",
        "nnz(A)",
        "ND anal.",
        "ND fact.",
        "ND nnz(L)",
        "AMD anal.",
        "AMD fact.",
        "AMD nnz(L)"
    );
    for &n in sizes {
        let (mut hessian, nd_analysis) = box_hessian(n);
        let nd_factor: Vec<f64> = (0..SAMPLES)
            .map(|_| {
                let start = Instant::now();
                hessian.factorise().unwrap();
                start.elapsed().as_secs_f64()
            })
            .collect();
        let path = folder.join(format!("box-{n}.mtx"));
        write_matrix_market(&hessian, &path).unwrap();

        let (col_ptr, row_idx, values) = hessian.lower_triangle();
        let dofs = hessian.dofs();
        let start = Instant::now();
        let mut amd = SparseCholesky::analyse(dofs, col_ptr, row_idx, None).unwrap();
        let amd_analysis = start.elapsed().as_secs_f64();
        let matrix = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(dofs, dofs, col_ptr, None, row_idx),
            values,
        );
        let amd_factor: Vec<f64> = (0..SAMPLES)
            .map(|_| {
                let start = Instant::now();
                amd.factorise(matrix).unwrap();
                start.elapsed().as_secs_f64()
            })
            .collect();
        println!(
            "{:>6} {dofs:>7} {:>10} | {nd_analysis:>9.3} {:>9.3} {:>11} | {amd_analysis:>9.3} {:>9.3} {:>11}",
            format!("{n}^3"),
            values.len(),
            median(nd_factor),
            hessian.factor_non_zeros(),
            median(amd_factor),
            amd.factor_non_zeros(),
        );
    }
    println!("matrices written to {}", folder.display());
}
