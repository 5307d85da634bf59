//! St. Venant-Kirchhoff, the report's model: `Psi = mu E:E + lambda/2 tr(E)^2` with Green strain `E = (F^T F - I) / 2`.
//!
//! `S = 2 mu E + lambda tr(E) I`, `P = F S`, and
//! `dP = dF S + F dS` with `dE = (dF^T F + F^T dF) / 2`.
//! The energy is finite for every `F`, inverted ones included, and it has no
//! barrier against flattening: a strongly compressed element can pass through
//! `det F = 0` at finite energy.

use super::{HyperelasticMaterial, LameParameters, unit};
use crate::math::{Matrix, StressDerivative};

/// St. Venant-Kirchhoff: `S = 2 mu E + lambda tr(E) I`, `P = F S`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StVenantKirchhoff {
    /// Lame parameters.
    pub lame: LameParameters,
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
        self.lame.lambda * Self::green_strain(f).trace() / crate::math::determinant(f)
    }
}
