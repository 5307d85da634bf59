//! Fixed corotated (Stomakhin et al. 2012): `Psi = mu |F - R|^2 + lambda/2 (J - 1)^2`, `R` the rotation of the polar decomposition `F = R S`.
//!
//! `R = U V^T` from the rotation-variant SVD `F = U Sigma V^T` (`U`, `V`
//! rotations; the last singular value carries the sign of `J`), so
//! `|F - R|^2 = sum_i (sigma_i - 1)^2` and, with `cof F = dJ/dF`,
//!
//! ```text
//! P  = 2 mu (F - R) + lambda (J - 1) cof F
//! dP = 2 mu (dF - dR) + lambda (cof F : dF) cof F + lambda (J - 1) d(cof F)[dF]
//! dR = U W V^T,  W_ij = (M_ij - M_ji) / (sigma_i + sigma_j),  M = U^T dF V
//! ```
//!
//! (`W` skew; from `F = R S` with `S` symmetric). `dR` is singular where two
//! signed singular values sum to zero (a flat or inverted element); the sum is
//! kept away from zero there. The energy is finite for every `F` and the
//! material allows inversion (no cap on `J` in the line search: an inverted
//! element is pushed back); the element
//! Hessian's projection onto the PSD cone (in `energy::elasticity`) is the
//! projection this material needs.

use super::{
    HyperelasticMaterial, LameParameters, cofactor_differential, determinant_in_singular_values,
    unit,
};
use crate::math::{
    Matrix, StressDerivative, SvdFrameBlocks, TWIST_PAIRS, Vector, cofactor, determinant,
    rotation_svd,
};

/// The smallest `|sigma_i + sigma_j|` used in `dR`.
const MIN_SINGULAR_SUM: f64 = 1e-12;

/// Fixed corotated elasticity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedCorotated {
    /// Lame parameters.
    pub lame: LameParameters,
}

/// `sigma_i + sigma_j` kept at least `MIN_SINGULAR_SUM` away from zero.
fn guarded_sum(sum: f64) -> f64 {
    if sum.abs() < MIN_SINGULAR_SUM {
        MIN_SINGULAR_SUM.copysign(sum)
    } else {
        sum
    }
}

/// What `P` and `dP/dF` share at one `F`: its rotation-variant SVD, `J`
/// and `cof F`, each computed once.
struct Decomposition<const D: usize> {
    u: Matrix<D>,
    sigma: Vector<D>,
    v: Matrix<D>,
    j: f64,
    cof: Matrix<D>,
}

impl<const D: usize> Decomposition<D> {
    fn of(f: &Matrix<D>) -> Self {
        let (u, sigma, v) = rotation_svd(f);
        Self {
            u,
            sigma,
            v,
            j: determinant(f),
            cof: cofactor(f),
        }
    }
}

impl FixedCorotated {
    /// `P = 2 mu (F - U V^T) + lambda (J - 1) cof F`.
    fn stress<const D: usize>(&self, f: &Matrix<D>, d: &Decomposition<D>) -> Matrix<D> {
        let LameParameters { mu, lambda } = self.lame;
        (f - d.u * d.v.transpose()) * (2.0 * mu) + d.cof * (lambda * (d.j - 1.0))
    }

    /// `dP/dF` (see the module documentation).
    fn stress_derivative<const D: usize>(
        &self,
        f: &Matrix<D>,
        d: &Decomposition<D>,
    ) -> StressDerivative<D> {
        let LameParameters { mu, lambda } = self.lame;
        let Decomposition {
            u,
            sigma,
            v,
            j,
            cof,
        } = d;
        std::array::from_fn(|k| {
            std::array::from_fn(|l| {
                let df = unit::<D>(k, l);
                let m = u.transpose() * df * v;
                let w = Matrix::<D>::from_fn(|i, n| {
                    if i == n {
                        return 0.0;
                    }
                    (m[(i, n)] - m[(n, i)]) / guarded_sum(sigma[i] + sigma[n])
                });
                let dr = u * w * v.transpose();
                (df - dr) * (2.0 * mu)
                    + cof * (lambda * cof[(k, l)])
                    + cofactor_differential(f, &df) * (lambda * (j - 1.0))
            })
        })
    }
}

impl<const D: usize> HyperelasticMaterial<D> for FixedCorotated {
    fn energy_density(&self, f: &Matrix<D>) -> f64 {
        let LameParameters { mu, lambda } = self.lame;
        let (_, sigma, _) = rotation_svd(f);
        let j = determinant(f);
        mu * sigma.iter().map(|s| (s - 1.0).powi(2)).sum::<f64>() + 0.5 * lambda * (j - 1.0).powi(2)
    }

    fn first_piola(&self, f: &Matrix<D>) -> Matrix<D> {
        self.stress(f, &Decomposition::of(f))
    }

    fn first_piola_derivative(&self, f: &Matrix<D>) -> StressDerivative<D> {
        self.stress_derivative(f, &Decomposition::of(f))
    }

    /// One SVD, one `J` and one `cof F` for both.
    fn first_piola_and_derivative(&self, f: &Matrix<D>) -> (Matrix<D>, StressDerivative<D>) {
        let d = Decomposition::of(f);
        (self.stress(f, &d), self.stress_derivative(f, &d))
    }

    /// With `g = dJ/dsigma`, `m_ab = d2J/dsigma_a dsigma_b` (the third
    /// singular value in 3D, 1 in 2D) and `s_ab = sigma_a + sigma_b` (kept
    /// away from zero as in `dR`): the stretch block is
    /// `2 mu I + lambda g g^T + lambda (J - 1) d2J/dsigma2` and the twist
    /// block of `(a, b)` is `[[p, q], [q, p]]` with `p = 2 mu (1 - 1 / s_ab)`
    /// and `q = 2 mu / s_ab - lambda (J - 1) m_ab` (`dR` contributes the
    /// `1 / s_ab`).
    fn stress_derivative_in_svd_frame(&self, sigma: &Vector<D>) -> Option<SvdFrameBlocks<D>> {
        let LameParameters { mu, lambda } = self.lame;
        let (j, g, j_hessian) = determinant_in_singular_values(sigma);
        let stretch = Matrix::<D>::identity() * (2.0 * mu)
            + g * g.transpose() * lambda
            + j_hessian * (lambda * (j - 1.0));
        let mut twist = [[0.0; 3]; 3];
        for (block, &(a, b)) in twist.iter_mut().zip(&TWIST_PAIRS).take(D * (D - 1) / 2) {
            let sum = guarded_sum(sigma[a] + sigma[b]);
            let p = 2.0 * mu * (1.0 - 1.0 / sum);
            *block = [
                p,
                2.0 * mu / sum - lambda * (j - 1.0) * j_hessian[(a, b)],
                p,
            ];
        }
        Some(SvdFrameBlocks { stretch, twist })
    }

    fn forbids_inversion(&self) -> bool {
        false
    }

    /// With `F = diag(F_2D, 1)`, `R = diag(R_2D, 1)` and `(cof F)_zz = J`:
    /// `P_zz = lambda (J - 1) J` and `sigma_zz = P_zz / J = lambda (J - 1)`.
    fn plane_strain_normal_stress(&self, f: &Matrix<D>) -> f64 {
        self.lame.lambda * (determinant(f) - 1.0)
    }
}
