//! Material parameters of isotropic linear-elastic origin: Lame `(mu, lambda)` and Young/Poisson `(E, nu)`.
//!
//! The 3D relations `mu = E / (2 (1 + nu))`, `lambda = E nu / ((1 + nu)(1 - 2 nu))`
//! and back `E = mu (3 lambda + 2 mu) / (lambda + mu)`, `nu = lambda / (2 (lambda + mu))`.
//! A 2D body is read as plane strain: the same formulas, the out-of-plane
//! strain held at zero.

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
