//! St. Venant-Kirchhoff, the report's model: `Psi = mu E:E + lambda/2 tr(E)^2` with Green strain `E = (F^T F - I) / 2`.
//!
//! `S = 2 mu E + lambda tr(E) I`, `P = F S`, and
//! `dP = dF S + F dS` with `dE = (dF^T F + F^T dF) / 2`.
//! The energy is finite for every `F`, inverted ones included, and it has no
//! barrier against flattening: a strongly compressed element can pass through
//! `det F = 0` at finite energy.

use super::{HyperelasticMaterial, LameParameters, unit};
use crate::math::{Matrix, StressDerivative, SvdFrameBlocks, TWIST_PAIRS, Vector};

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

    /// At `F = diag(sigma)`, `S_aa = mu (sigma_a^2 - 1) + lambda/2 sum_c
    /// (sigma_c^2 - 1)`: the stretch block is
    /// `diag(S_aa + 2 mu sigma_a^2) + lambda sigma sigma^T`, and the twist
    /// block of `(a, b)` is `[[p, q], [q, p]]` with
    /// `p = mu (sigma_a^2 + sigma_b^2 - 1) + lambda/2 sum_c (sigma_c^2 - 1)`
    /// and `q = mu sigma_a sigma_b`.
    fn stress_derivative_in_svd_frame(&self, sigma: &Vector<D>) -> Option<SvdFrameBlocks<D>> {
        let LameParameters { mu, lambda } = self.lame;
        let volumetric = 0.5 * lambda * sigma.iter().map(|s| s * s - 1.0).sum::<f64>();
        let mut stretch = sigma * sigma.transpose() * lambda;
        for a in 0..D {
            let s_aa = mu * (sigma[a] * sigma[a] - 1.0) + volumetric;
            stretch[(a, a)] += s_aa + 2.0 * mu * sigma[a] * sigma[a];
        }
        let mut twist = [[0.0; 3]; 3];
        for (block, &(a, b)) in twist.iter_mut().zip(&TWIST_PAIRS).take(D * (D - 1) / 2) {
            let p = mu * (sigma[a] * sigma[a] + sigma[b] * sigma[b] - 1.0) + volumetric;
            *block = [p, mu * sigma[a] * sigma[b], p];
        }
        Some(SvdFrameBlocks { stretch, twist })
    }

    fn forbids_inversion(&self) -> bool {
        false
    }

    /// `S_zz = lambda tr(E)` (as `E_zz = 0`) and `sigma_zz = F_zz S_zz F_zz / J = S_zz / J`.
    fn plane_strain_normal_stress(&self, f: &Matrix<D>) -> f64 {
        self.lame.lambda * Self::green_strain(f).trace() / crate::math::determinant(f)
    }
}
