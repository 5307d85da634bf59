//! Compressible Neo-Hookean: `Psi = mu/2 (tr(F^T F) - D) - mu ln J + lambda/2 (ln J)^2`, `J = det F`.
//!
//! `P = mu (F - F^{-T}) + lambda ln J F^{-T}`,
//! `dP = mu dF + (mu - lambda ln J) F^{-T} dF^T F^{-T} + lambda tr(F^{-1} dF) F^{-T}`.
//! Stable under compression; the energy is `+inf` for `J <= 0` and the line
//! search never accepts such a state.

use super::{HyperelasticMaterial, LameParameters};
use crate::math::{
    Matrix, StressDerivative, SvdFrameBlocks, TWIST_PAIRS, Vector, cofactor, determinant,
};

/// `(F^{-T}, ln J)` from the cofactor, `F^{-T} = cof F / J` (one closed-form
/// determinant, no elimination); `None` unless `J > 0`.
fn inverse_transpose_and_log_det<const D: usize>(f: &Matrix<D>) -> Option<(Matrix<D>, f64)> {
    let j = determinant(f);
    (j > 0.0).then(|| (cofactor(f) / j, j.ln()))
}

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
        let Some((h, ln_j)) = inverse_transpose_and_log_det(f) else {
            return Matrix::<D>::from_element(f64::NAN);
        };
        let LameParameters { mu, lambda } = self.lame;
        (f - h) * mu + h * (lambda * ln_j)
    }

    fn first_piola_derivative(&self, f: &Matrix<D>) -> StressDerivative<D> {
        self.first_piola_and_derivative(f).1
    }

    /// With `H = F^{-T}`, entry `(i, j)` of `dP/dF_kl` is
    /// `mu d_ik d_jl + (mu - lambda ln J) H_il H_kj + lambda H_kl H_ij`
    /// (the three terms of `dP` above with `dF = e_k e_l^T`).
    fn first_piola_and_derivative(&self, f: &Matrix<D>) -> (Matrix<D>, StressDerivative<D>) {
        let Some((h, ln_j)) = inverse_transpose_and_log_det(f) else {
            let nan = Matrix::<D>::from_element(f64::NAN);
            return (nan, [[nan; D]; D]);
        };
        let LameParameters { mu, lambda } = self.lame;
        let p = (f - h) * mu + h * (lambda * ln_j);
        let c = mu - lambda * ln_j;
        let dp = std::array::from_fn(|k| {
            std::array::from_fn(|l| {
                let mut block = Matrix::<D>::from_fn(|r, s| {
                    c * h[(r, l)] * h[(k, s)] + lambda * h[(k, l)] * h[(r, s)]
                });
                block[(k, l)] += mu;
                block
            })
        });
        (p, dp)
    }

    /// At `F = diag(sigma)`, `H = diag(1 / sigma)`: the stretch block is
    /// `mu I + (mu - lambda ln J) diag(1 / sigma_a^2) + lambda h h^T` with
    /// `h_a = 1 / sigma_a`, and the twist block of the pair `(a, b)` is
    /// `[[mu, c], [c, mu]]` with `c = (mu - lambda ln J) / (sigma_a sigma_b)`
    /// (eigenvalues `mu +- c`: 0 and `2 mu` at rest, one negative under
    /// compression). `None` for an inverted `F`, where the energy is infinite.
    fn stress_derivative_in_svd_frame(&self, sigma: &Vector<D>) -> Option<SvdFrameBlocks<D>> {
        let j: f64 = sigma.iter().product();
        if !(j > 0.0) {
            return None;
        }
        let LameParameters { mu, lambda } = self.lame;
        let c = mu - lambda * j.ln();
        let h = sigma.map(|s| 1.0 / s);
        let mut stretch = h * h.transpose() * lambda;
        for a in 0..D {
            stretch[(a, a)] += mu + c * h[a] * h[a];
        }
        let mut twist = [[0.0; 3]; 3];
        for (block, &(a, b)) in twist.iter_mut().zip(&TWIST_PAIRS).take(D * (D - 1) / 2) {
            *block = [mu, c * h[a] * h[b], mu];
        }
        Some(SvdFrameBlocks { stretch, twist })
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
