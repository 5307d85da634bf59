//! The per-element fields that colour frames and fill the VTK cell data:
//! strain-energy density, volume ratio and von Mises stress, against closed
//! forms and against 3D. A 2D body is plane strain, so its von Mises stress
//! must equal the 3D one of the same body extruded with `F_zz = 1`.

use crate::support;

use crate::support::{Rng, lame, materials, neo_hookean, random_f, relative_error, stvk, unit_box};
use elasto::energy::Elasticity;
use elasto::energy::ElementField;
use elasto::material::{HyperelasticMaterial, Material};
use elasto::math::{Matrix, Vector, determinant};
use std::sync::Arc;

/// The value of `field` for a mesh deformed homogeneously by `f`, one per element.
fn homogeneous_field<const D: usize>(
    material: Material,
    f: &Matrix<D>,
    field: ElementField,
) -> Vec<f64> {
    let mesh = unit_box::<D>();
    let x: Vec<Vector<D>> = mesh.rest_positions().iter().map(|p| f * p).collect();
    Elasticity::new(Arc::new(mesh), material).element_field(&x, field)
}

/// A 2D deformation gradient extruded into 3D with `F_zz = 1`.
fn plane_strain_extrusion(f: &Matrix<2>) -> Matrix<3> {
    Matrix::<3>::from_fn(|r, c| match (r, c) {
        (2, 2) => 1.0,
        (2, _) | (_, 2) => 0.0,
        _ => f[(r, c)],
    })
}

fn assert_all_close(values: &[f64], expected: f64, tolerance: f64, what: &str) {
    for (e, v) in values.iter().enumerate() {
        assert!(
            relative_error(*v, expected, 1e-12) < tolerance,
            "{what}: element {e} has {v}, expected {expected}"
        );
    }
}

#[test]
fn plane_strain_von_mises_equals_the_extruded_3d_body() {
    let mut rng = Rng::new(17);
    for (_, material) in materials() {
        for _ in 0..20 {
            let f2 = random_f::<2>(&mut rng, 0.3);
            let f3 = plane_strain_extrusion(&f2);
            let in_2d = homogeneous_field(material, &f2, ElementField::VonMises);
            let in_3d = homogeneous_field(material, &f3, ElementField::VonMises);
            assert_all_close(&in_2d, in_3d[0], 1e-10, &format!("{material:?} F = {f2:?}"));
            // The energies agree too: 2D is the 3D energy restricted to the plane.
            let psi_2d = homogeneous_field(material, &f2, ElementField::EnergyDensity);
            let psi_3d = homogeneous_field(material, &f3, ElementField::EnergyDensity);
            assert_all_close(&psi_2d, psi_3d[0], 1e-10, "energy density");
        }
    }
}

/// `sigma_zz` from the material is the zz entry of the 3D Cauchy stress of the extrusion.
#[test]
fn plane_strain_normal_stress_is_the_3d_cauchy_zz() {
    let mut rng = Rng::new(5);
    for (_, material) in materials() {
        for _ in 0..20 {
            let f2 = random_f::<2>(&mut rng, 0.3);
            let f3 = plane_strain_extrusion(&f2);
            let (zz, p3) = match material {
                Material::StVenantKirchhoff(m) => (
                    m.plane_strain_normal_stress(&f2),
                    HyperelasticMaterial::<3>::first_piola(&m, &f3),
                ),
                Material::NeoHookean(m) => (
                    m.plane_strain_normal_stress(&f2),
                    HyperelasticMaterial::<3>::first_piola(&m, &f3),
                ),
                Material::StableNeoHookean(m) => (
                    m.plane_strain_normal_stress(&f2),
                    HyperelasticMaterial::<3>::first_piola(&m, &f3),
                ),
                Material::FixedCorotated(m) => (
                    m.plane_strain_normal_stress(&f2),
                    HyperelasticMaterial::<3>::first_piola(&m, &f3),
                ),
            };
            let sigma = p3 * f3.transpose() / f3.determinant();
            assert!(
                relative_error(zz, sigma[(2, 2)], 1e-9) < 1e-10,
                "{material:?}: {zz} vs {}",
                sigma[(2, 2)]
            );
        }
    }
}

/// Uniform scaling in 3D is a pure pressure: no deviatoric stress.
#[test]
fn a_3d_pressure_has_no_von_mises_stress() {
    for material in [stvk(), neo_hookean()] {
        for scale in [0.8, 1.1] {
            let f = Matrix::<3>::identity() * scale;
            let values = homogeneous_field(material, &f, ElementField::VonMises);
            let stiffness = lame().mu;
            assert!(
                values.iter().all(|v| v.abs() < 1e-9 * stiffness),
                "{material:?} at scale {scale}: {values:?}"
            );
        }
    }
}

/// Uniform scaling by `a` in plane strain: `sigma_xx = sigma_yy` and a
/// different `sigma_zz`, so von Mises is `|sigma_xx - sigma_zz|`; for
/// St. Venant-Kirchhoff with `e = (a^2 - 1) / 2`:
/// `sigma_xx = (2 mu + 2 lambda) e`, `sigma_zz = 2 lambda e / a^2`.
#[test]
fn a_2d_plane_strain_dilation_has_the_closed_form_von_mises() {
    let lame = lame();
    for a in [0.9_f64, 1.05, 1.2] {
        let e = 0.5 * (a * a - 1.0);
        let sigma_xx = (2.0 * lame.mu + 2.0 * lame.lambda) * e;
        let sigma_zz = 2.0 * lame.lambda * e / (a * a);
        let expected = (sigma_xx - sigma_zz).abs();
        let values = homogeneous_field(
            stvk(),
            &(Matrix::<2>::identity() * a),
            ElementField::VonMises,
        );
        assert_all_close(&values, expected, 1e-10, &format!("scale {a}"));
    }
}

/// Small simple shear `gamma`: shear stress `mu gamma`, von Mises `sqrt(3) mu gamma`.
fn small_shear_has_the_linear_elastic_von_mises<const D: usize>() {
    let gamma = 1e-5;
    let mut f = Matrix::<D>::identity();
    f[(0, 1)] = gamma;
    let expected = 3f64.sqrt() * lame().mu * gamma;
    for material in [stvk(), neo_hookean()] {
        let values = homogeneous_field(material, &f, ElementField::VonMises);
        assert_all_close(&values, expected, 1e-4, &format!("{D}D {material:?}"));
    }
}

/// `J = det F` in every element, also for a non-uniform deformation.
fn volume_ratio_is_the_determinant<const D: usize>() {
    let mesh = unit_box::<D>();
    let mut rng = Rng::new(3);
    let x = support::perturbed(mesh.rest_positions(), 0.05, &mut rng);
    let values = Elasticity::new(Arc::new(mesh.clone()), stvk())
        .element_field(&x, ElementField::VolumeRatio);
    for (e, value) in values.iter().enumerate() {
        let expected = determinant(&mesh.deformation_gradient(e, &x));
        assert!((value - expected).abs() < 1e-12, "element {e}");
    }
}

both_dimensions! {
    small_shear_has_the_linear_elastic_von_mises => small_shear_von_mises_2d, small_shear_von_mises_3d;
    volume_ratio_is_the_determinant => volume_ratio_2d, volume_ratio_3d;
}
