//! The one place that maps a scene's `material.model` to the material types and back.

use super::raw_scene::Model;
use crate::material::{LameParameters, Material, NeoHookean, StVenantKirchhoff, YoungPoisson};

/// The material of `model` with the validated stiffness `lame`.
pub(crate) fn build_material(model: Model, lame: LameParameters) -> Material {
    match model {
        Model::Stvk => Material::StVenantKirchhoff(StVenantKirchhoff { lame }),
        Model::NeoHookean => Material::NeoHookean(NeoHookean { lame }),
    }
}

/// The scene-file name of a material's model (`stvk` or `neo-hookean`).
pub(crate) fn model_name(material: &Material) -> &'static str {
    match material {
        Material::StVenantKirchhoff(_) => "stvk",
        Material::NeoHookean(_) => "neo-hookean",
    }
}

/// The material of [`MaterialConfig::default`](super::MaterialConfig): the
/// report's St. Venant-Kirchhoff with E = 300, nu = 0.3.
pub(crate) fn default_material() -> Material {
    build_material(
        Model::Stvk,
        YoungPoisson {
            young: 300.0,
            poisson: 0.3,
        }
        .into(),
    )
}
