//! Hyperelastic materials: energy density, first Piola-Kirchhoff stress and its derivative.
//!
//! A hyperelastic material is a strain-energy density `Psi(F)` per unit rest
//! volume. Its first Piola-Kirchhoff stress is `P = dPsi/dF` and the element
//! Hessian needs the fourth-order tensor `dP/dF`.
//!
//! **St. Venant-Kirchhoff** (the report's model): with Green strain
//! `E = (F^T F - I) / 2`,
//! `Psi = mu E:E + lambda/2 tr(E)^2`, `S = 2 mu E + lambda tr(E) I`, `P = F S`,
//! `dP = dF S + F dS` with `dE = (dF^T F + F^T dF) / 2`.
//!
//! **Neo-Hookean** (stable under compression, infinite energy at inversion):
//! `Psi = mu/2 (tr(F^T F) - D) - mu ln J + lambda/2 (ln J)^2`, `J = det F`,
//! `P = mu (F - F^{-T}) + lambda ln J F^{-T}`,
//! `dP = mu dF + (mu - lambda ln J) F^{-T} dF^T F^{-T} + lambda tr(F^{-1} dF) F^{-T}`.
//! For `J <= 0` the energy is `+inf`; the line search never accepts such a state.
//!
//! **Parameters.** Lame `(mu, lambda)` or Young/Poisson `(E, nu)` with the 3D
//! relations `mu = E / (2 (1 + nu))`, `lambda = E nu / ((1 + nu)(1 - 2 nu))`.
//! A 2D body is read as plane strain: the same formulas, the out-of-plane
//! strain held at zero.

use crate::math::{Matrix, StressDerivative, determinant, inverse};
use serde::{Deserialize, Serialize};

/// Lame parameters, in pascals (or the scene's unit of stress).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LameParameters {
    /// Shear modulus `mu`.
    pub mu: f64,
    /// First Lame parameter `lambda`.
    pub lambda: f64,
}

/// Young's modulus and Poisson's ratio.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct YoungPoisson {
    /// Young's modulus `E` (> 0).
    pub young: f64,
    /// Poisson's ratio `nu`, in (-1, 0.5).
    pub poisson: f64,
}

impl From<YoungPoisson> for LameParameters {
    fn from(p: YoungPoisson) -> Self {
        let (e, nu) = (p.young, p.poisson);
        Self {
            mu: e / (2.0 * (1.0 + nu)),
            lambda: e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
        }
    }
}

impl From<LameParameters> for YoungPoisson {
    fn from(p: LameParameters) -> Self {
        let (mu, lambda) = (p.mu, p.lambda);
        Self {
            young: mu * (3.0 * lambda + 2.0 * mu) / (lambda + mu),
            poisson: lambda / (2.0 * (lambda + mu)),
        }
    }
}

/// A hyperelastic material in `D` dimensions.
pub trait HyperelasticMaterial<const D: usize>: Send + Sync {
    /// Strain-energy density `Psi(F)` per unit rest volume (`+inf` where undefined).
    fn energy_density(&self, f: &Matrix<D>) -> f64;
    /// First Piola-Kirchhoff stress `P = dPsi/dF`.
    fn first_piola(&self, f: &Matrix<D>) -> Matrix<D>;
    /// `dP/dF`, as `D x D` blocks: `result[k][l] = dP/dF_kl`.
    fn first_piola_derivative(&self, f: &Matrix<D>) -> StressDerivative<D>;
    /// Whether the energy is infinite for `det F <= 0` (the line search must
    /// then keep every element uninverted).
    fn forbids_inversion(&self) -> bool;
    /// The out-of-plane Cauchy stress `sigma_zz` of a 2D body read as plane
    /// strain. Every 2D energy here is its 3D form restricted to
    /// `F = [[F_2D, 0], [0, 1]]`, so the in-plane stresses agree with 3D and
    /// `sigma_zz` is the stress that holds `F_zz = 1`. Meaningful for `D = 2`.
    fn plane_strain_normal_stress(&self, f: &Matrix<D>) -> f64;
}

/// St. Venant-Kirchhoff: `S = 2 mu E + lambda tr(E) I`, `P = F S`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StVenantKirchhoff {
    /// Lame parameters.
    pub lame: LameParameters,
}

/// Compressible Neo-Hookean (the form of Smith et al., log-barrier in `J`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NeoHookean {
    /// Lame parameters.
    pub lame: LameParameters,
}

fn unit<const D: usize>(k: usize, l: usize) -> Matrix<D> {
    let mut m = Matrix::<D>::zeros();
    m[(k, l)] = 1.0;
    m
}

impl StVenantKirchhoff {
    fn green_strain<const D: usize>(f: &Matrix<D>) -> Matrix<D> {
        (f.transpose() * f - Matrix::<D>::identity()) * 0.5
    }

    fn second_piola<const D: usize>(&self, e: &Matrix<D>) -> Matrix<D> {
        e * (2.0 * self.lame.mu) + Matrix::<D>::identity() * (self.lame.lambda * e.trace())
    }
}

impl<const D: usize> HyperelasticMaterial<D> for StVenantKirchhoff {
    fn energy_density(&self, f: &Matrix<D>) -> f64 {
        let e = Self::green_strain(f);
        self.lame.mu * e.norm_squared() + 0.5 * self.lame.lambda * e.trace().powi(2)
    }

    fn first_piola(&self, f: &Matrix<D>) -> Matrix<D> {
        f * self.second_piola(&Self::green_strain(f))
    }

    fn first_piola_derivative(&self, f: &Matrix<D>) -> StressDerivative<D> {
        let s = self.second_piola(&Self::green_strain(f));
        std::array::from_fn(|k| {
            std::array::from_fn(|l| {
                let df = unit::<D>(k, l);
                let de = (df.transpose() * f + f.transpose() * df) * 0.5;
                df * s + f * self.second_piola(&de)
            })
        })
    }

    fn forbids_inversion(&self) -> bool {
        false
    }

    /// `S_zz = lambda tr(E)` (as `E_zz = 0`) and `sigma_zz = F_zz S_zz F_zz / J = S_zz / J`.
    fn plane_strain_normal_stress(&self, f: &Matrix<D>) -> f64 {
        self.lame.lambda * Self::green_strain(f).trace() / determinant(f)
    }
}

impl<const D: usize> HyperelasticMaterial<D> for NeoHookean {
    fn energy_density(&self, f: &Matrix<D>) -> f64 {
        let j = determinant(f);
        if !(j > 0.0) {
            return f64::INFINITY;
        }
        let ln_j = j.ln();
        let LameParameters { mu, lambda } = self.lame;
        0.5 * mu * (f.norm_squared() - D as f64) - mu * ln_j + 0.5 * lambda * ln_j * ln_j
    }

    fn first_piola(&self, f: &Matrix<D>) -> Matrix<D> {
        let j = determinant(f);
        let Some(f_inv) = inverse(f).filter(|_| j > 0.0) else {
            return Matrix::<D>::from_element(f64::NAN);
        };
        let f_inv_t = f_inv.transpose();
        let LameParameters { mu, lambda } = self.lame;
        (f - f_inv_t) * mu + f_inv_t * (lambda * j.ln())
    }

    fn first_piola_derivative(&self, f: &Matrix<D>) -> StressDerivative<D> {
        let j = determinant(f);
        let Some(f_inv) = inverse(f).filter(|_| j > 0.0) else {
            return [[Matrix::<D>::from_element(f64::NAN); D]; D];
        };
        let f_inv_t = f_inv.transpose();
        let LameParameters { mu, lambda } = self.lame;
        let ln_j = j.ln();
        std::array::from_fn(|k| {
            std::array::from_fn(|l| {
                let df = unit::<D>(k, l);
                df * mu
                    + f_inv_t * df.transpose() * f_inv_t * (mu - lambda * ln_j)
                    + f_inv_t * (lambda * (f_inv * df).trace())
            })
        })
    }

    fn forbids_inversion(&self) -> bool {
        true
    }

    /// `P_zz = mu (F_zz - F^-T_zz) + lambda ln J F^-T_zz = lambda ln J` (as
    /// `F_zz = 1`) and `sigma_zz = P_zz F_zz / J = lambda ln J / J`.
    fn plane_strain_normal_stress(&self, f: &Matrix<D>) -> f64 {
        let j = determinant(f);
        if !(j > 0.0) {
            return f64::NAN;
        }
        self.lame.lambda * j.ln() / j
    }
}

/// The materials a scene can choose, as one closed set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Material {
    /// St. Venant-Kirchhoff.
    StVenantKirchhoff(StVenantKirchhoff),
    /// Neo-Hookean.
    NeoHookean(NeoHookean),
}

impl Material {
    /// The material's Lame parameters.
    pub fn lame(&self) -> LameParameters {
        match self {
            Material::StVenantKirchhoff(m) => m.lame,
            Material::NeoHookean(m) => m.lame,
        }
    }
}
