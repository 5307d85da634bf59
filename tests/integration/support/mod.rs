//! Shared helpers for the simulation-core tests.
#![allow(dead_code, unused_macros)]

/// Stamps out a 2D and a 3D `#[test]` from one generic check `fn check<const D: usize>()`.
macro_rules! both_dimensions {
    ($($check:ident => $name2:ident, $name3:ident;)*) => {$(
        #[test]
        fn $name2() {
            $check::<2>();
        }
        #[test]
        fn $name3() {
            $check::<3>();
        }
    )*};
}

use elasto::material::{
    FixedCorotated, LameParameters, Material, NeoHookean, StVenantKirchhoff, StableNeoHookean,
    YoungPoisson,
};
use elasto::math::{Matrix, Vector, Vector2};
use elasto::mesh::Mesh;
use elasto::sim::{Effects, Ground, Simulation, SimulationSettings};

/// A tiny deterministic generator (xorshift), so tests need no extra crate.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    /// Uniform in [-1, 1).
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

pub fn lame() -> LameParameters {
    YoungPoisson {
        young: 100.0,
        poisson: 0.3,
    }
    .into()
}

pub fn stvk() -> Material {
    Material::StVenantKirchhoff(StVenantKirchhoff { lame: lame() })
}

pub fn neo_hookean() -> Material {
    Material::NeoHookean(NeoHookean { lame: lame() })
}

/// Every material, by its scene-file name, with the test Lame parameters.
pub fn materials() -> [(&'static str, Material); 4] {
    let lame = lame();
    [
        ("stvk", stvk()),
        ("neo-hookean", neo_hookean()),
        (
            "stable-neo-hookean",
            Material::StableNeoHookean(StableNeoHookean { lame }),
        ),
        (
            "fixed-corotated",
            Material::FixedCorotated(FixedCorotated { lame }),
        ),
    ]
}

/// The report's example: a 1 x 1 St. Venant-Kirchhoff box (E = 300,
/// nu = 0.3, density 1) of 5 x 5 cells released at rest with its bottom
/// `release_height` above the ground at 0, under gravity 1 downwards, with
/// the ground barrier of width `a` and the default stiffness.
pub fn report_drop(release_height: f64, a: f64, settings: SimulationSettings) -> Simulation<2> {
    let mesh = Mesh::axis_aligned_box(
        Vector2::new(0.0, release_height),
        Vector2::new(1.0, release_height + 1.0),
        [5, 5],
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
            activation_distance: a,
            stiffness: None,
            friction: 0.0,
        }),
        contact: None,
        pinned: Vec::new(),
        obstacles: Vec::new(),
    };
    Simulation::new(
        mesh,
        Material::StVenantKirchhoff(StVenantKirchhoff { lame }),
        1.0,
        effects,
        settings,
        Vector2::zeros(),
    )
    .unwrap()
}

/// A unit box with 2 cells per axis.
pub fn unit_box<const D: usize>() -> Mesh<D> {
    Mesh::axis_aligned_box(Vector::<D>::zeros(), Vector::<D>::from_element(1.0), [2; D]).unwrap()
}

/// Rest positions perturbed by up to `amplitude` per component (keeps elements uninverted for small amplitudes).
pub fn perturbed<const D: usize>(x: &[Vector<D>], amplitude: f64, rng: &mut Rng) -> Vec<Vector<D>> {
    x.iter()
        .map(|p| p + Vector::<D>::from_fn(|_, _| amplitude * rng.next()))
        .collect()
}

/// A random deformation gradient near identity with positive determinant.
pub fn random_f<const D: usize>(rng: &mut Rng, amplitude: f64) -> Matrix<D> {
    Matrix::<D>::identity() + Matrix::<D>::from_fn(|_, _| amplitude * rng.next())
}

/// Relative error `|a - b| / max(|b|, floor)`.
pub fn relative_error(a: f64, b: f64, floor: f64) -> f64 {
    (a - b).abs() / b.abs().max(floor)
}

/// Max-norm relative error of two equal-length slices, relative to the max entry of `reference`.
pub fn max_relative_error(actual: &[f64], reference: &[f64]) -> f64 {
    let scale = reference
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(1e-300);
    actual
        .iter()
        .zip(reference)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
        / scale
}

/// The least-squares parabola `x = c0 + c1 t + c2 t^2` through the points
/// `(time[i], x[i])` with `time[i] >= from`: `[c0, c1, c2]`.
pub fn fitted_parabola(time: &[f64], x: &[f64], from: f64) -> [f64; 3] {
    let points: Vec<(f64, f64)> = time
        .iter()
        .zip(x)
        .filter(|(t, _)| **t >= from)
        .map(|(t, x)| (*t, *x))
        .collect();
    // The normal equations of the 3-parameter fit.
    let moment = |k: i32| points.iter().map(|(t, _)| t.powi(k)).sum::<f64>();
    let weighted = |k: i32| points.iter().map(|(t, x)| x * t.powi(k)).sum::<f64>();
    let a = nalgebra::Matrix3::new(
        moment(0),
        moment(1),
        moment(2),
        moment(1),
        moment(2),
        moment(3),
        moment(2),
        moment(3),
        moment(4),
    );
    let b = nalgebra::Vector3::new(weighted(0), weighted(1), weighted(2));
    let c = a.lu().solve(&b).expect("distinct times");
    [c[0], c[1], c[2]]
}
