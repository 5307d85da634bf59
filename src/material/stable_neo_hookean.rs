//! Stable Neo-Hookean (Smith, de Goes, Kim 2018): `Psi = mu/2 (tr(F^T F) - D) - mu (J - 1) + lambda'/2 (J - 1)^2`, `lambda' = lambda + mu`, defined for every `F`.
//!
//! This is the paper's rest-stable form `mu/2 (I_C - D) + lambda'/2 (J - alpha)^2`
//! with `alpha = 1 + mu / lambda'`, less its constant value at rest (so that
//! `Psi(I) = 0`), without the optional `-mu/2 ln(I_C + 1)` term. Its
//! linearisation at rest is `mu (dF + dF^T) + (lambda' - mu) tr(dF) I`, so the
//! paper's reparametrisation `lambda' = lambda + mu` (and `mu' = mu`) makes it
//! agree with linear elasticity of the scene's Lame pair `(mu, lambda)`.
//!
//! With the cofactor `cof F = dJ/dF` (`= J F^{-T}` where `F` is invertible):
//!
//! ```text
//! P  = mu F + (lambda' (J - 1) - mu) cof F
//! dP = mu dF + lambda' (cof F : dF) cof F + (lambda' (J - 1) - mu) d(cof F)[dF]
//! ```
//!
//! No logarithm and no division: the energy is finite for flat and inverted
//! elements and pushes them back: the material allows inversion, so the
//! line search puts no cap on `J` (an element may pass through `J = 0` in
//! a hard impact and recover).

use super::{
    HyperelasticMaterial, LameParameters, cofactor_differential, determinant_in_singular_values,
    unit,
};
use crate::math::{
    Matrix, StressDerivative, SvdFrameBlocks, TWIST_PAIRS, Vector, cofactor, determinant,
};

/// Stable Neo-Hookean; `lame` is the scene's pair, `lambda + mu` is used inside.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StableNeoHookean {
    /// Lame parameters (of the linear elasticity the material reduces to at rest).
    pub lame: LameParameters,
}

impl StableNeoHookean {
    /// `(mu, lambda')` with `lambda' = lambda + mu`.
    fn constants(&self) -> (f64, f64) {
        (self.lame.mu, self.lame.lambda + self.lame.mu)
    }
}

impl<const D: usize> HyperelasticMaterial<D> for StableNeoHookean {
    fn energy_density(&self, f: &Matrix<D>) -> f64 {
        let (mu, lambda) = self.constants();
        let j = determinant(f);
        0.5 * mu * (f.norm_squared() - D as f64) - mu * (j - 1.0) + 0.5 * lambda * (j - 1.0).powi(2)
    }

    fn first_piola(&self, f: &Matrix<D>) -> Matrix<D> {
        let (mu, lambda) = self.constants();
        let j = determinant(f);
        f * mu + cofactor(f) * (lambda * (j - 1.0) - mu)
    }

    fn first_piola_derivative(&self, f: &Matrix<D>) -> StressDerivative<D> {
        let (mu, lambda) = self.constants();
        let j = determinant(f);
        let cof = cofactor(f);
        std::array::from_fn(|k| {
            std::array::from_fn(|l| {
                let df = unit::<D>(k, l);
                df * mu
                    + cof * (lambda * cof[(k, l)])
                    + cofactor_differential(f, &df) * (lambda * (j - 1.0) - mu)
            })
        })
    }

    /// With `g = dJ/dsigma` and `k = lambda' (J - 1) - mu`: the stretch
    /// block is `mu I + lambda' g g^T + k d2J/dsigma2`, and the twist block
    /// of `(a, b)` is `[[mu, -k m], [-k m, mu]]` with `m = d2J/dsigma_a
    /// dsigma_b` (the third singular value in 3D, 1 in 2D). Signed `sigma`
    /// (inverted elements) included.
    fn stress_derivative_in_svd_frame(&self, sigma: &Vector<D>) -> Option<SvdFrameBlocks<D>> {
        let (mu, lambda) = self.constants();
        let (j, g, j_hessian) = determinant_in_singular_values(sigma);
        let k = lambda * (j - 1.0) - mu;
        let stretch = Matrix::<D>::identity() * mu + g * g.transpose() * lambda + j_hessian * k;
        let mut twist = [[0.0; 3]; 3];
        for (block, &(a, b)) in twist.iter_mut().zip(&TWIST_PAIRS).take(D * (D - 1) / 2) {
            *block = [mu, -k * j_hessian[(a, b)], mu];
        }
        Some(SvdFrameBlocks { stretch, twist })
    }

    fn forbids_inversion(&self) -> bool {
        false
    }

    /// With `F_zz = 1`, `(cof F)_zz = J`: `P_zz = mu + (lambda' (J - 1) - mu) J`
    /// and `sigma_zz = P_zz / J = mu / J - mu + lambda' (J - 1)`.
    fn plane_strain_normal_stress(&self, f: &Matrix<D>) -> f64 {
        let (mu, lambda) = self.constants();
        let j = determinant(f);
        mu / j - mu + lambda * (j - 1.0)
    }
}
