//! Hyperelastic materials: the material trait, one file per material, and the one place where scene names map to materials.
//!
//! A hyperelastic material is a strain-energy density `Psi(F)` per unit rest
//! volume. Its first Piola-Kirchhoff stress is `P = dPsi/dF` and the element
//! Hessian needs the fourth-order tensor `dP/dF`
//! ([`HyperelasticMaterial`]). Each material's file writes its own formulas
//! out.
//!
//! # Adding a material
//!
//! 1. A new file with a parameter struct implementing [`HyperelasticMaterial`]
//!    for every `D` (energy, stress, stress derivative, whether it forbids
//!    inversion, the plane-strain `sigma_zz`).
//! 2. In this file: one arm in [`Material`], one in [`MaterialModel`] (its
//!    scene name), and one in each of the `match`es below and in
//!    `with_material!` (the static dispatch the elasticity term uses).
//! 3. An entry in the `materials()` list of `tests/integration/derivatives.rs`, which
//!    checks `P` and `dP/dF` (and the element gradient and Hessian) against
//!    central finite differences in 2D and 3D.
//!
//! The trait asks for no particular parameters: a material whose constants
//! are not a Lame pair fits as well, and [`Material::parameters`] reports
//! whatever constants a material has.

mod fixed_corotated;
mod lame_parameters;
mod neo_hookean;
mod st_venant_kirchhoff;
mod stable_neo_hookean;

pub use fixed_corotated::FixedCorotated;
pub use lame_parameters::{LameParameters, YoungPoisson};
pub use neo_hookean::NeoHookean;
pub use st_venant_kirchhoff::{STVK_BARRIER_VOLUME_RATIO, StVenantKirchhoff};
pub use stable_neo_hookean::StableNeoHookean;

use crate::math::{Matrix, StressDerivative, SvdFrameBlocks, Vector, cofactor};
use serde::{Deserialize, Serialize};

/// A hyperelastic material in `D` dimensions.
pub trait HyperelasticMaterial<const D: usize>: Send + Sync {
    /// Strain-energy density `Psi(F)` per unit rest volume (`+inf` where undefined).
    fn energy_density(&self, f: &Matrix<D>) -> f64;
    /// First Piola-Kirchhoff stress `P = dPsi/dF`.
    fn first_piola(&self, f: &Matrix<D>) -> Matrix<D>;
    /// `dP/dF`, as `D x D` blocks: `result[k][l] = dP/dF_kl`.
    fn first_piola_derivative(&self, f: &Matrix<D>) -> StressDerivative<D>;
    /// `P` and `dP/dF` together (the element kernel's one call per element);
    /// a material may share the work of the two (an inverse, a logarithm).
    fn first_piola_and_derivative(&self, f: &Matrix<D>) -> (Matrix<D>, StressDerivative<D>) {
        (self.first_piola(f), self.first_piola_derivative(f))
    }
    /// The blocks of `dP/dF` in the SVD frame of `F = U diag(sigma) V^T`
    /// (`U`, `V` rotations; `dP/dF` of an isotropic material at the diagonal
    /// `diag(sigma)`, Smith et al. 2019) in closed form, for the element
    /// kernel's PSD projection. `None`, the default, has the kernel rotate
    /// `dP/dF` into the frame instead (the same blocks, at about a thousand
    /// multiplications in 3D); `tests/integration/derivatives.rs` checks that the two
    /// agree for every material that has them.
    fn stress_derivative_in_svd_frame(&self, _sigma: &Vector<D>) -> Option<SvdFrameBlocks<D>> {
        None
    }
    /// Whether the energy is infinite for `det F <= 0`: the material's
    /// inversion policy. A material that forbids inversion (Neo-Hookean's
    /// `ln J`, StVK's volume barrier) has the line search filter every step
    /// so that no element loses more than a fixed fraction of its volume in
    /// one step (`Elasticity::max_step`, IPC's relative filter); one that
    /// allows it (stable Neo-Hookean, fixed corotated: finite, smooth energy
    /// through `J = 0`) has no cap at all, and its energy, stress and
    /// projected Hessian are valid for inverted elements, which it pushes
    /// back.
    fn forbids_inversion(&self) -> bool;
    /// The out-of-plane Cauchy stress `sigma_zz` of a 2D body read as plane
    /// strain. Every 2D energy here is its 3D form restricted to
    /// `F = [[F_2D, 0], [0, 1]]`, so the in-plane stresses agree with 3D and
    /// `sigma_zz` is the stress that holds `F_zz = 1`. Meaningful for `D = 2`.
    fn plane_strain_normal_stress(&self, f: &Matrix<D>) -> f64;
}

/// The unit matrix `e_k e_l^T`, the direction of `dF` in `dP/dF_kl`.
fn unit<const D: usize>(k: usize, l: usize) -> Matrix<D> {
    let mut m = Matrix::<D>::zeros();
    m[(k, l)] = 1.0;
    m
}

/// The derivatives of `J = prod_c sigma_c` in the singular values, for the
/// materials' SVD-frame blocks: `J`, the gradient `g_a = prod_{c != a}
/// sigma_c` and the Hessian, `prod_{c != a, b} sigma_c` off the diagonal (the
/// third value in 3D, 1 in 2D) and 0 on it.
fn determinant_in_singular_values<const D: usize>(
    sigma: &Vector<D>,
) -> (f64, Vector<D>, Matrix<D>) {
    let product_without = |a: usize, b: usize| -> f64 {
        (0..D)
            .filter(|&c| c != a && c != b)
            .map(|c| sigma[c])
            .product()
    };
    (
        sigma.iter().product(),
        Vector::<D>::from_fn(|a, _| product_without(a, a)),
        Matrix::<D>::from_fn(|a, b| if a == b { 0.0 } else { product_without(a, b) }),
    )
}

/// The differential of the cofactor, `d(cof F)[dF]`: linear in `dF` (in 2D
/// the cofactor itself is linear, `cof(dF)`; in 3D each entry is a 2 x 2
/// minor, so its differential is the sum of two minors mixing `F` and `dF`).
fn cofactor_differential<const D: usize>(f: &Matrix<D>, df: &Matrix<D>) -> Matrix<D> {
    match D {
        1 => Matrix::<D>::zeros(),
        2 => cofactor(df),
        3 => Matrix::<D>::from_fn(|i, j| {
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
            f[(i1, j1)] * df[(i2, j2)] + df[(i1, j1)] * f[(i2, j2)]
                - f[(i2, j1)] * df[(i1, j2)]
                - df[(i2, j1)] * f[(i1, j2)]
        }),
        _ => unimplemented!("cofactor differential of a {D} x {D} matrix"),
    }
}

/// The materials a scene can choose, as one closed set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Material {
    /// St. Venant-Kirchhoff.
    StVenantKirchhoff(StVenantKirchhoff),
    /// Neo-Hookean.
    NeoHookean(NeoHookean),
    /// Stable Neo-Hookean.
    StableNeoHookean(StableNeoHookean),
    /// Fixed corotated.
    FixedCorotated(FixedCorotated),
}

/// A material model by its scene-file name (`material.model`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MaterialModel {
    /// `stvk`: St. Venant-Kirchhoff.
    #[serde(rename = "stvk")]
    StVenantKirchhoff,
    /// `neo-hookean`: Neo-Hookean.
    NeoHookean,
    /// `stable-neo-hookean`: Stable Neo-Hookean (Smith, de Goes, Kim 2018).
    StableNeoHookean,
    /// `fixed-corotated`: fixed corotated (Stomakhin et al. 2012).
    FixedCorotated,
}

impl MaterialModel {
    /// Every model, in the order docs/scene-reference.md lists them.
    pub const ALL: [MaterialModel; 4] = [
        MaterialModel::StVenantKirchhoff,
        MaterialModel::NeoHookean,
        MaterialModel::StableNeoHookean,
        MaterialModel::FixedCorotated,
    ];

    /// The scene-file name.
    pub fn name(self) -> &'static str {
        match self {
            MaterialModel::StVenantKirchhoff => "stvk",
            MaterialModel::NeoHookean => "neo-hookean",
            MaterialModel::StableNeoHookean => "stable-neo-hookean",
            MaterialModel::FixedCorotated => "fixed-corotated",
        }
    }

    /// The material of this model with Lame parameters `lame`.
    pub fn with_lame(self, lame: LameParameters) -> Material {
        match self {
            MaterialModel::StVenantKirchhoff => {
                Material::StVenantKirchhoff(StVenantKirchhoff { lame })
            }
            MaterialModel::NeoHookean => Material::NeoHookean(NeoHookean { lame }),
            MaterialModel::StableNeoHookean => {
                Material::StableNeoHookean(StableNeoHookean { lame })
            }
            MaterialModel::FixedCorotated => Material::FixedCorotated(FixedCorotated { lame }),
        }
    }
}

impl Material {
    /// The model this material is an instance of.
    pub fn model(&self) -> MaterialModel {
        match self {
            Material::StVenantKirchhoff(_) => MaterialModel::StVenantKirchhoff,
            Material::NeoHookean(_) => MaterialModel::NeoHookean,
            Material::StableNeoHookean(_) => MaterialModel::StableNeoHookean,
            Material::FixedCorotated(_) => MaterialModel::FixedCorotated,
        }
    }

    /// Whether the material forbids inversion (its energy is infinite at
    /// `det F <= 0`): [`HyperelasticMaterial::forbids_inversion`].
    pub fn forbids_inversion(&self) -> bool {
        with_material!(self, m => HyperelasticMaterial::<3>::forbids_inversion(m))
    }

    /// The constant called `name` (e.g. `mu`), if the material has one.
    pub fn parameter(&self, name: &str) -> Option<f64> {
        self.parameters()
            .into_iter()
            .find(|(n, _)| *n == name)
            .map(|(_, value)| value)
    }

    /// The material's constants as `(name, value)` pairs, for summaries.
    pub fn parameters(&self) -> Vec<(&'static str, f64)> {
        match self {
            Material::StVenantKirchhoff(StVenantKirchhoff { lame })
            | Material::NeoHookean(NeoHookean { lame })
            | Material::StableNeoHookean(StableNeoHookean { lame })
            | Material::FixedCorotated(FixedCorotated { lame }) => {
                vec![("mu", lame.mu), ("lambda", lame.lambda)]
            }
        }
    }
}

/// Calls `$body` with `$m` bound to the concrete material inside a
/// [`Material`] (static dispatch: the hot loops stay monomorphic).
macro_rules! with_material {
    ($material:expr, $m:ident => $body:expr) => {
        match $material {
            $crate::material::Material::StVenantKirchhoff($m) => $body,
            $crate::material::Material::NeoHookean($m) => $body,
            $crate::material::Material::StableNeoHookean($m) => $body,
            $crate::material::Material::FixedCorotated($m) => $body,
        }
    };
}
pub(crate) use with_material;
