//! Compressible Neo-Hookean: `Psi = mu/2 (tr(F^T F) - D) - mu ln J + lambda/2 (ln J)^2`, `J = det F`.
//!
//! `P = mu (F - F^{-T}) + lambda ln J F^{-T}`,
//! `dP = mu dF + (mu - lambda ln J) F^{-T} dF^T F^{-T} + lambda tr(F^{-1} dF) F^{-T}`.
//! Stable under compression; the energy is `+inf` for `J <= 0` and the line
//! search never accepts such a state.

use super::{HyperelasticMaterial, LameParameters, unit};
use crate::math::{Matrix, StressDerivative, determinant, inverse};

/// Compressible Neo-Hookean (the form of Smith et al., log-barrier in `J`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NeoHookean {
    /// Lame parameters.
    pub lame: LameParameters,
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
