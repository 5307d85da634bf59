//! Every gradient and Hessian against central finite differences, in 2D and 3D.
//!
//! Each check is a generic function stamped out for both dimensions by
//! `both_dimensions!`; the relative error bound is 1e-6 throughout.

use crate::support::*;
use elasto::assembly::SparseHessian;
use elasto::contact::CollisionMesh;
use elasto::energy::{
    ContactBarrier, ContactSettings, Elasticity, EnergyTerm, Gravity, GroundBarrier, Inertia,
};
use elasto::material::{
    FixedCorotated, HyperelasticMaterial, NeoHookean, StVenantKirchhoff, StableNeoHookean,
};
use elasto::math::{
    DenseMatrix, Matrix, Vector, project_to_psd, rotation_svd, svd_frame_blocks_by_rotation,
};
use elasto::mesh::Mesh;
use std::sync::Arc;

const TOLERANCE: f64 = 1e-6;

both_dimensions! {
    stress_is_the_energy_derivative => stress_is_the_energy_derivative_2d, stress_is_the_energy_derivative_3d;
    stress_derivative_is_the_stress_derivative => stress_derivative_2d, stress_derivative_3d;
    elastic_gradient_matches_finite_differences => elastic_gradient_2d, elastic_gradient_3d;
    element_hessian_matches_finite_differences => element_hessian_2d, element_hessian_3d;
    assembled_hessian_is_the_sum_of_projected_element_hessians => assembled_hessian_2d, assembled_hessian_3d;
    inertia_gravity_barrier_match_finite_differences => effect_terms_2d, effect_terms_3d;
    robust_materials_match_finite_differences_compressed_and_inverted => robust_materials_2d, robust_materials_3d;
    every_material_is_stress_free_at_rest => rest_stability_2d, rest_stability_3d;
    stable_neo_hookean_energy_is_finite_when_inverted => stable_neo_hookean_inverted_2d, stable_neo_hookean_inverted_3d;
    svd_frame_blocks_match_the_rotated_stress_derivative => svd_frame_blocks_2d, svd_frame_blocks_3d;
    contact_barrier_gradient_matches_finite_differences => contact_barrier_2d, contact_barrier_3d;
}

fn for_each_material<const D: usize>(mut check: impl FnMut(&str, &dyn HyperelasticMaterial<D>)) {
    let lame = lame();
    check("stvk", &StVenantKirchhoff { lame });
    check("neo-hookean", &NeoHookean { lame });
    check("stable-neo-hookean", &StableNeoHookean { lame });
    check("fixed-corotated", &FixedCorotated { lame });
}

/// `P` against central differences of `Psi`, and `dP/dF` against central
/// differences of `P`, at one `F`; returns the larger relative error.
fn finite_difference_error<const D: usize>(
    material: &dyn HyperelasticMaterial<D>,
    f: &Matrix<D>,
) -> f64 {
    let p = material.first_piola(f);
    let dp = material.first_piola_derivative(f);
    let dp_scale = dp.iter().flatten().map(|m| m.amax()).fold(0.0, f64::max);
    let h = 1e-6;
    let mut worst = 0.0f64;
    for k in 0..D {
        for l in 0..D {
            let mut plus = *f;
            plus[(k, l)] += h;
            let mut minus = *f;
            minus[(k, l)] -= h;
            let fd = (material.energy_density(&plus) - material.energy_density(&minus)) / (2.0 * h);
            worst = worst.max(relative_error(p[(k, l)], fd, p.amax()));
            let fd: Matrix<D> =
                (material.first_piola(&plus) - material.first_piola(&minus)) / (2.0 * h);
            worst = worst.max((dp[k][l] - fd).amax() / dp_scale);
        }
    }
    worst
}

/// The robust materials away from rest: strongly compressed (`J` about 0.1 in 3D, 0.2 in 2D)
/// and, for both (their energies are defined there), inverted `F`
/// (one row reflected). Fixed corotated is checked away from degenerate
/// singular values (`sigma_i + sigma_j = 0`), where `dR` is singular.
fn robust_materials_match_finite_differences_compressed_and_inverted<const D: usize>() {
    let mut rng = Rng::new(7);
    let lame = lame();
    let materials: [(&str, &dyn HyperelasticMaterial<D>); 2] = [
        ("stable-neo-hookean", &StableNeoHookean { lame }),
        ("fixed-corotated", &FixedCorotated { lame }),
    ];
    for (name, material) in materials {
        for case in 0..10 {
            let mut f = random_f::<D>(&mut rng, 0.3);
            let kind = if case % 2 == 0 {
                // Compressed: every column shortened to 45%.
                f *= 0.45;
                "compressed"
            } else {
                f.row_mut(0).neg_mut();
                "inverted"
            };
            let j = elasto::math::determinant(&f);
            assert!(
                if kind == "inverted" {
                    j < 0.0
                } else {
                    j > 0.0 && j < 0.35
                },
                "{kind} F with J = {j}"
            );
            let err = finite_difference_error(material, &f);
            assert!(
                err < TOLERANCE,
                "{name} {D}D, {kind} F (J = {j}): rel. error {err:e}"
            );
        }
    }
}

/// Rest stability: `P(I) = 0` (and `Psi(I) = 0`) for every material.
fn every_material_is_stress_free_at_rest<const D: usize>() {
    for_each_material::<D>(|name, material| {
        let identity = Matrix::<D>::identity();
        let p = material.first_piola(&identity);
        assert!(p.amax() < 1e-12, "{name} {D}D: P(I) = {p}");
        let psi = material.energy_density(&identity);
        assert!(psi.abs() < 1e-12, "{name} {D}D: Psi(I) = {psi}");
        assert!(
            material.plane_strain_normal_stress(&identity).abs() < 1e-12,
            "{name}: sigma_zz(I)"
        );
    });
}

/// Stable Neo-Hookean is defined for inverted `F`, with a finite energy
/// larger than at rest and a stress that pushes the element back.
fn stable_neo_hookean_energy_is_finite_when_inverted<const D: usize>() {
    let material = StableNeoHookean { lame: lame() };
    let mut f = Matrix::<D>::identity();
    f[(0, 0)] = -0.5;
    let psi = HyperelasticMaterial::<D>::energy_density(&material, &f);
    assert!(psi.is_finite() && psi > 0.0, "{D}D: Psi = {psi}");
    let p = HyperelasticMaterial::<D>::first_piola(&material, &f);
    assert!(p.iter().all(|v| v.is_finite()), "{D}D: P = {p}");
    // dPsi/dF_00 < 0: growing F_00 back towards +1 lowers the energy.
    assert!(p[(0, 0)] < 0.0, "{D}D: P = {p}");
    let zero = Matrix::<D>::zeros();
    assert!(HyperelasticMaterial::<D>::energy_density(&material, &zero).is_finite());
}

/// A material's closed-form blocks of `dP/dF` in the SVD frame are its own
/// `dP/dF` rotated into that frame, at rest (repeated singular values),
/// stretched, compressed and (where the material allows it) inverted.
fn svd_frame_blocks_match_the_rotated_stress_derivative<const D: usize>() {
    let mut rng = Rng::new(7);
    let mut checked = 0;
    for_each_material::<D>(|name, material| {
        let mut inverted = Matrix::<D>::identity();
        inverted[(0, 0)] = -0.5;
        let mut cases = vec![
            Matrix::<D>::identity(),
            Matrix::<D>::identity() * 0.7,
            inverted,
        ];
        cases.extend((0..6).map(|_| random_f::<D>(&mut rng, 0.3)));
        for f in cases {
            let (u, sigma, v) = rotation_svd(&f);
            let Some(closed_form) = material.stress_derivative_in_svd_frame(&sigma) else {
                continue;
            };
            let dp = material.first_piola_derivative(&f);
            let n = D * D;
            let flat: Vec<f64> = (0..n * n)
                .map(|i| dp[(i / n) / D][(i / n) % D][((i % n) / D, (i % n) % D)])
                .collect();
            let rotated = svd_frame_blocks_by_rotation::<D>(&flat, &u, &v)
                .unwrap_or_else(|| panic!("{name} {D}D: dP/dF not block-diagonal at {f}"));
            let scale = rotated.stretch.amax().max(1.0);
            let err = (closed_form.stretch - rotated.stretch).amax() / scale;
            assert!(
                err < 1e-10,
                "{name} {D}D: stretch block rel. error {err:e} at {f}"
            );
            for (t, (a, b)) in closed_form.twist.iter().zip(&rotated.twist).enumerate() {
                for (x, y) in a.iter().zip(b) {
                    assert!(
                        (x - y).abs() < 1e-10 * scale,
                        "{name} {D}D: twist block {t}: {a:?} against {b:?} at {f}"
                    );
                }
            }
            checked += 1;
        }
    });
    // Every material has them; Neo-Hookean and StVK (its volume barrier)
    // have none for the inverted `F`, where their energies are infinite.
    assert_eq!(checked, 4 * 9 - 2, "{D}D: closed-form cases checked");
}

fn stress_is_the_energy_derivative<const D: usize>() {
    let mut rng = Rng::new(1);
    for_each_material::<D>(|name, material| {
        for _ in 0..5 {
            let f = random_f::<D>(&mut rng, 0.3);
            let p = material.first_piola(&f);
            let h = 1e-6;
            for k in 0..D {
                for l in 0..D {
                    let mut plus = f;
                    plus[(k, l)] += h;
                    let mut minus = f;
                    minus[(k, l)] -= h;
                    let fd = (material.energy_density(&plus) - material.energy_density(&minus))
                        / (2.0 * h);
                    let err = relative_error(p[(k, l)], fd, p.amax());
                    assert!(
                        err < TOLERANCE,
                        "{name} {D}D: P[{k},{l}] = {} vs finite difference {fd} (rel. error {err:e})",
                        p[(k, l)]
                    );
                }
            }
        }
    });
}

fn stress_derivative_is_the_stress_derivative<const D: usize>() {
    let mut rng = Rng::new(2);
    for_each_material::<D>(|name, material| {
        for _ in 0..5 {
            let f = random_f::<D>(&mut rng, 0.3);
            let dp = material.first_piola_derivative(&f);
            let scale = dp.iter().flatten().map(|m| m.amax()).fold(0.0, f64::max);
            let h = 1e-6;
            for k in 0..D {
                for l in 0..D {
                    let mut plus = f;
                    plus[(k, l)] += h;
                    let mut minus = f;
                    minus[(k, l)] -= h;
                    let fd: Matrix<D> =
                        (material.first_piola(&plus) - material.first_piola(&minus)) / (2.0 * h);
                    let err = (dp[k][l] - fd).amax() / scale;
                    assert!(
                        err < TOLERANCE,
                        "{name} {D}D: dP/dF[{k}][{l}] rel. error {err:e}"
                    );
                }
            }
        }
    });
}

/// Central-difference gradient of `term` at `x`, one vector per vertex.
fn finite_difference_gradient<const D: usize>(
    term: &dyn EnergyTerm<D>,
    x: &[Vector<D>],
    h: f64,
) -> Vec<f64> {
    let mut out = Vec::with_capacity(x.len() * D);
    let mut probe = x.to_vec();
    for v in 0..x.len() {
        for k in 0..D {
            probe[v][k] = x[v][k] + h;
            let plus = term.value(&probe);
            probe[v][k] = x[v][k] - h;
            let minus = term.value(&probe);
            probe[v][k] = x[v][k];
            out.push((plus - minus) / (2.0 * h));
        }
    }
    out
}

fn analytic_gradient<const D: usize>(term: &dyn EnergyTerm<D>, x: &[Vector<D>]) -> Vec<f64> {
    let mut gradient = vec![Vector::<D>::zeros(); x.len()];
    term.add_gradient(x, 1.0, &mut gradient);
    gradient
        .iter()
        .flat_map(|g| g.iter().copied().collect::<Vec<_>>())
        .collect()
}

/// Central-difference Hessian of `term` (differences of its analytic gradient).
fn finite_difference_hessian<const D: usize>(
    term: &dyn EnergyTerm<D>,
    x: &[Vector<D>],
    h: f64,
) -> DenseMatrix {
    let n = x.len() * D;
    let mut out = DenseMatrix::zeros(n, n);
    let mut probe = x.to_vec();
    for v in 0..x.len() {
        for k in 0..D {
            probe[v][k] = x[v][k] + h;
            let plus = analytic_gradient(term, &probe);
            probe[v][k] = x[v][k] - h;
            let minus = analytic_gradient(term, &probe);
            probe[v][k] = x[v][k];
            for row in 0..n {
                out[(row, v * D + k)] = (plus[row] - minus[row]) / (2.0 * h);
            }
        }
    }
    out
}

fn assembled_hessian<const D: usize>(
    term: &dyn EnergyTerm<D>,
    mesh: &Mesh<D>,
    x: &[Vector<D>],
) -> DenseMatrix {
    let mut hessian =
        SparseHessian::new(mesh, (0..mesh.vertex_count()).map(Some).collect()).unwrap();
    term.add_hessian(x, 1.0, &mut hessian);
    hessian.to_dense()
}

fn elastic_gradient_matches_finite_differences<const D: usize>() {
    let mut rng = Rng::new(3);
    let mesh = Arc::new(unit_box::<D>());
    for (name, material) in materials() {
        let elasticity = Elasticity::new(mesh.clone(), material);
        let x = perturbed(mesh.rest_positions(), 0.08, &mut rng);
        let analytic = analytic_gradient(&elasticity, &x);
        let fd = finite_difference_gradient(&elasticity, &x, 1e-6);
        let err = max_relative_error(&analytic, &fd);
        assert!(
            err < TOLERANCE,
            "{name} {D}D: elastic gradient rel. error {err:e}"
        );
    }
}

fn element_hessian_matches_finite_differences<const D: usize>() {
    let mut rng = Rng::new(4);
    // One simplex: the global Hessian is the element Hessian.
    let rest: Vec<Vector<D>> = (0..=D)
        .map(|a| {
            if a == 0 {
                Vector::<D>::zeros()
            } else {
                Vector::<D>::from_fn(|k, _| if k == a - 1 { 1.0 } else { 0.0 })
            }
        })
        .collect();
    let mesh = Arc::new(Mesh::new(rest, vec![(0..=D).collect()]).unwrap());
    for (name, material) in materials() {
        let elasticity = Elasticity::new(mesh.clone(), material);
        for _ in 0..5 {
            let x = perturbed(mesh.rest_positions(), 0.15, &mut rng);
            let analytic = elasticity.unprojected_element_hessian(0, &x);
            let fd = finite_difference_hessian(&elasticity, &x, 1e-6);
            let err = (&analytic - &fd).amax() / fd.amax();
            assert!(
                err < TOLERANCE,
                "{name} {D}D: element Hessian rel. error {err:e}"
            );
            assert!(
                (&analytic - analytic.transpose()).amax() <= 1e-12 * analytic.amax(),
                "{name}: Hessian not symmetric"
            );
        }
    }
}

/// `V G^T [dP/dF]_+ G` for element `e`, written out independently of the
/// crate's kernel: `dP/dF` flattened to `D^2 x D^2` (row `(k j)`, column
/// `(l n)`), projected with the dynamic eigen-decomposition, and `G` built
/// from the shape-function gradients. Also returns whether anything was clamped.
fn reference_projected_element_hessian<const D: usize>(
    material: &dyn HyperelasticMaterial<D>,
    mesh: &Mesh<D>,
    e: usize,
    x: &[Vector<D>],
) -> (DenseMatrix, bool) {
    let rest = mesh.rest_elements()[e];
    let dp = material.first_piola_derivative(&mesh.deformation_gradient(e, x));
    let mut a = DenseMatrix::from_fn(D * D, D * D, |row, col| {
        dp[col / D][col % D][(row / D, row % D)]
    });
    let clamped = project_to_psd(&mut a);
    // dF_{kj}/dx_{b,l} = delta_{kl} (g_b)_j.
    let gradient = |b: usize| -> Vector<D> {
        if b == 0 {
            -rest.dm_inv.row_sum().transpose()
        } else {
            rest.dm_inv.row(b - 1).transpose()
        }
    };
    let g = DenseMatrix::from_fn(D * D, D * (D + 1), |row, col| {
        let (k, j, b, l) = (row / D, row % D, col / D, col % D);
        if k == l { gradient(b)[j] } else { 0.0 }
    });
    (g.transpose() * a * g * rest.volume, clamped)
}

fn assembled_hessian_is_the_sum_of_projected_element_hessians<const D: usize>() {
    let mut rng = Rng::new(5);
    let mesh = Arc::new(unit_box::<D>());
    let materials = materials();
    for_each_material::<D>(|name, reference_material| {
        let material = materials.iter().find(|(n, _)| *n == name).unwrap().1;
        let elasticity = Elasticity::new(mesh.clone(), material);
        // Strong compression of some elements makes StVK stress derivatives indefinite.
        let x: Vec<Vector<D>> = perturbed(mesh.rest_positions(), 0.12, &mut rng)
            .iter()
            .map(|p| {
                let mut q = *p;
                q[1] *= 0.6;
                q
            })
            .collect();
        let n = mesh.vertex_count() * D;
        let mut expected = DenseMatrix::zeros(n, n);
        let mut clamped_any = false;
        for (e, simplex) in mesh.simplices().enumerate() {
            let local = elasticity.projected_element_hessian(e, &x);
            let (reference, clamped) =
                reference_projected_element_hessian(reference_material, &mesh, e, &x);
            clamped_any |= clamped;
            let err = (&local - &reference).amax() / reference.amax();
            assert!(
                err < 1e-10,
                "{name} {D}D: element {e}: projected Hessian differs from V G^T [dP/dF]_+ G by {err:e}"
            );
            let min_eigenvalue = local.clone().symmetric_eigenvalues().min();
            assert!(
                min_eigenvalue > -1e-10 * local.amax(),
                "{name} {D}D: element {e}: projected Hessian not PSD ({min_eigenvalue:e})"
            );
            if !clamped {
                // Nothing to project: the exact element Hessian.
                let exact = elasticity.unprojected_element_hessian(e, &x);
                let err = (&local - &exact).amax() / exact.amax();
                assert!(
                    err < 1e-10,
                    "{name} {D}D: element {e}: unclamped projection changed the Hessian by {err:e}"
                );
            }
            for p in 0..local.nrows() {
                for q in 0..local.ncols() {
                    expected[(simplex[p / D] * D + p % D, simplex[q / D] * D + q % D)] +=
                        local[(p, q)];
                }
            }
        }
        let assembled = assembled_hessian(&elasticity, &mesh, &x);
        let err = (&assembled - &expected).amax() / expected.amax();
        assert!(
            err < 1e-12,
            "{name} {D}D: assembly differs from the element sum by {err:e}"
        );
        let min_eigenvalue = assembled.clone().symmetric_eigenvalues().min();
        assert!(
            min_eigenvalue > -1e-10 * assembled.amax(),
            "{name} {D}D: assembled Hessian not PSD ({min_eigenvalue:e})"
        );
        if name == "stvk" {
            assert!(
                clamped_any,
                "the compressed StVK state should exercise the projection"
            );
        }
    });
}

fn inertia_gravity_barrier_match_finite_differences<const D: usize>() {
    let mut rng = Rng::new(6);
    let mesh = unit_box::<D>();
    let masses = mesh.lumped_masses(2.5);
    // Lift the box so that its bottom row sits inside the barrier (0 < gap < a).
    let a = 0.2;
    let x: Vec<Vector<D>> = perturbed(mesh.rest_positions(), 0.02, &mut rng)
        .into_iter()
        .map(|mut p| {
            p[1] += 0.1;
            p
        })
        .collect();
    let mut inertia = Inertia::new(masses.clone());
    inertia.set_prediction(&perturbed(&x, 0.3, &mut rng));
    let gravity = Gravity::new(
        masses.clone(),
        Vector::<D>::from_fn(|k, _| if k == 1 { -9.81 } else { 0.5 }),
    );
    let barrier = GroundBarrier::new(0.0, a, 50.0);
    let inside = x.iter().filter(|p| p[1] < a).count();
    assert!(inside >= 3, "the test state must exercise the barrier");
    let terms: [(&str, &dyn EnergyTerm<D>); 3] = [
        ("inertia", &inertia),
        ("gravity", &gravity),
        ("barrier", &barrier),
    ];
    for (name, term) in terms {
        let analytic = analytic_gradient(term, &x);
        let fd = finite_difference_gradient(term, &x, 1e-6);
        let err = max_relative_error(&analytic, &fd);
        assert!(err < TOLERANCE, "{name} {D}D: gradient rel. error {err:e}");
        let fd_hessian = finite_difference_hessian(term, &x, 1e-6);
        let assembled = assembled_hessian(term, &mesh, &x);
        let err = (&assembled - &fd_hessian).amax() / fd_hessian.amax().max(1e-300);
        if name == "gravity" {
            assert_eq!(assembled.amax(), 0.0, "gravity is linear");
            assert!(fd_hessian.amax() < 1e-6);
        } else {
            assert!(err < TOLERANCE, "{name} {D}D: Hessian rel. error {err:e}");
        }
    }
}

/// The contact barrier of two perturbed boxes, one just above the other
/// (gaps below `d_hat`): its gradient against central differences of its
/// value, and its assembled Hessian symmetric positive semi-definite
/// (it is projected per stencil, so it is not the exact one).
fn contact_barrier_gradient_matches_finite_differences<const D: usize>() {
    let mut rng = Rng::new(17);
    let lower = unit_box::<D>();
    let n = lower.vertex_count();
    let lift = Vector::<D>::from_fn(|k, _| if k == 1 { 1.004 } else { 0.3 });
    let rest: Vec<Vector<D>> = lower
        .rest_positions()
        .iter()
        .copied()
        .chain(lower.rest_positions().iter().map(|p| p + lift))
        .collect();
    let simplices = lower
        .simplices()
        .map(<[usize]>::to_vec)
        .chain(lower.simplices().map(|s| s.iter().map(|v| v + n).collect()))
        .collect();
    let mesh = Mesh::new(rest.clone(), simplices).unwrap();
    let owner: Vec<usize> = (0..2 * n).map(|v| v / n).collect();
    let x = perturbed(&rest, 0.001, &mut rng);
    let settings = ContactSettings {
        activation_distance: 0.01,
        stiffness: Some(1e6),
        self_contact: true,
    };
    let mut term = ContactBarrier::new(
        CollisionMesh::new(&mesh, &owner),
        settings,
        &vec![1.0; 2 * n],
        2.0,
        &x,
    );
    term.begin_iteration(&x);
    assert!(
        term.value(&x) > 0.0,
        "the test state must exercise the barrier"
    );
    let analytic = analytic_gradient(&term, &x);
    let fd = finite_difference_gradient(&term, &x, 1e-8);
    let err = max_relative_error(&analytic, &fd);
    assert!(err < 1e-5, "contact {D}D: gradient rel. error {err:e}");
    let mut pairs = Vec::new();
    term.coupled_pairs(&mut pairs);
    let mut hessian = SparseHessian::new(&mesh, (0..2 * n).map(Some).collect()).unwrap();
    assert!(hessian.include_pairs(pairs).unwrap());
    term.add_hessian(&x, 1.0, &mut hessian);
    let dense = hessian.to_dense();
    let eigen = dense.clone().symmetric_eigen();
    let largest = eigen.eigenvalues.amax();
    assert!(largest > 0.0);
    assert!(eigen.eigenvalues.iter().all(|&l| l >= -1e-9 * largest));
}
