//! Per-element scalars of the elastic state, for colouring and analysis.

/// A per-element scalar for colouring and analysis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ElementField {
    /// Strain-energy density `Psi(F)`.
    #[default]
    EnergyDensity,
    /// Von Mises equivalent of the Cauchy stress.
    VonMises,
    /// Volume ratio `J = det F`.
    VolumeRatio,
}
