//! The scene file as written: serde structs mirroring the TOML, before validation.
//!
//! Whole numbers are `i64` (what TOML holds) so that the validator, not
//! serde, reports a negative count with its range. Every table denies
//! unknown keys and says "expected a table" rather than its Rust name. Optional keys are `Option`s here; the
//! validator (`scene_validator.rs`) fills in defaults for the typed
//! [`Scene`](super::Scene) and writes the filled-in raw form back
//! ([`Scene::load_resolved`](super::Scene::load_resolved)) so a run can be
//! reproduced exactly.

use crate::integrator::IntegratorKind;
use crate::material::MaterialModel;
use crate::solver::Projection;
use serde::{Deserialize, Serialize};

/// The whole scene file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(crate) struct RawScene {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    pub dimension: i64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh: Option<RawMesh>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<RawMaterial>,
    #[serde(default)]
    pub time: RawTime,
    #[serde(default)]
    pub solver: RawSolver,
    #[serde(default)]
    pub effects: RawEffects,
    #[serde(default)]
    pub render: RawRender,
    /// `[[bodies]]`, instead of `[mesh]` and `[material]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bodies: Option<Vec<RawBody>>,
    /// `[[obstacles]]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub obstacles: Option<Vec<RawObstacle>>,
}

/// One `[[obstacles]]` entry: its mesh, friction and rigid path.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(crate) struct RawObstacle {
    pub mesh: RawMesh,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angular_velocity: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub until: Option<f64>,
}

/// One `[[bodies]]` entry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(crate) struct RawBody {
    pub mesh: RawMesh,
    pub material: RawMaterial,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pinned: Option<RawPinned>,
}

/// The names a key of enum type accepts, for messages (`` `stvk` or `neo-hookean` ``).
/// Material models and integrators are listed from their own enums.
pub(crate) fn choices(key: &str) -> Option<String> {
    let listed = |names: &[&str]| match names {
        [] => String::new(),
        [one] => format!("`{one}`"),
        [init @ .., last] => {
            let init: Vec<String> = init.iter().map(|n| format!("`{n}`")).collect();
            format!("{} or `{last}`", init.join(", "))
        }
    };
    Some(match key {
        "mesh.generator" => listed(&["box", "file"]),
        "material.model" => listed(&MaterialModel::ALL.map(MaterialModel::name)),
        "time.integrator" => listed(&IntegratorKind::ALL.map(IntegratorKind::name)),
        "solver.method" => listed(&["newton", "gradient-descent"]),
        "solver.projection" => listed(&["always", "on-demand"]),
        "render.field" => listed(&["energy-density", "von-mises", "volume-ratio", "flat"]),
        _ => return None,
    })
}

/// Mesh generators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum Generator {
    /// An axis-aligned box split into simplices.
    #[default]
    Box,
    /// A mesh read from a file (`mesh.path`).
    File,
}

/// `[mesh]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(crate) struct RawMesh {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub generator: Option<Generator>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cells: Option<Vec<i64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub offset: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotate: Option<RawRotate>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub translate: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orient: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub merge_tolerance: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file_size: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file_checksum: Option<String>,
}

/// `mesh.rotate`: one angle in 2D (about the axis out of the plane), three in
/// 3D (about x, y, z), in degrees.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(
    untagged,
    expecting = "expected a number of degrees (2D) or an array of three (3D)"
)]
pub(crate) enum RawRotate {
    /// A 2D rotation.
    Angle(f64),
    /// A 3D rotation about x, then y, then z.
    Angles(Vec<f64>),
}

/// `[material]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(crate) struct RawMaterial {
    pub model: MaterialModel,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub young: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub poisson: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mu: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lambda: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
}

/// `[time]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(crate) struct RawTime {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fps: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub substeps: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frames: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub integrator: Option<IntegratorKind>,
}

/// Solver methods.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum Method {
    /// Newton's method (`solver.projection` says which Hessian).
    #[default]
    Newton,
    /// Fixed-step gradient descent.
    GradientDescent,
}

/// Which Hessian Newton factorises (`solver.projection`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum ProjectionName {
    /// The projected Hessian at every iteration.
    Always,
    /// The unprojected Hessian first, the projected one when needed.
    OnDemand,
}

impl From<ProjectionName> for Projection {
    fn from(name: ProjectionName) -> Self {
        match name {
            ProjectionName::Always => Projection::Always,
            ProjectionName::OnDemand => Projection::OnDemand,
        }
    }
}

impl From<Projection> for ProjectionName {
    fn from(projection: Projection) -> Self {
        match projection {
            Projection::Always => ProjectionName::Always,
            Projection::OnDemand => ProjectionName::OnDemand,
        }
    }
}

/// `[solver]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(crate) struct RawSolver {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub method: Option<Method>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_iterations: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub projection: Option<ProjectionName>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_subdivisions: Option<i64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction_velocity: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction_iterations: Option<i64>,
}

/// `[effects]`: each sub-table present is an effect that exists.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(crate) struct RawEffects {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gravity: Option<RawGravity>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ground: Option<RawGround>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact: Option<RawContact>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pinned: Option<RawPinnedList>,
}

/// `[effects.contact]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(crate) struct RawContact {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub distance: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kappa: Option<f64>,
    #[serde(default, rename = "self", skip_serializing_if = "Option::is_none")]
    pub self_contact: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
}

/// `[effects.gravity]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(crate) struct RawGravity {
    pub acceleration: Vec<f64>,
}

/// `[effects.ground]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(crate) struct RawGround {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub a: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kappa: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
}

/// One `[[effects.pinned]]` region (or `bodies.pinned`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(crate) struct RawPinned {
    pub min: Vec<f64>,
    pub max: Vec<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angular_velocity: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub until: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub release: Option<f64>,
}

/// `[[effects.pinned]]`: an array of regions, or (the older form) one
/// `[effects.pinned]` table, read as an array of one. Written back as an
/// array.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct RawPinnedList {
    pub regions: Vec<RawPinned>,
    /// Whether the file gave one table (`[effects.pinned]`): its keys are then
    /// named `effects.pinned.min`, not `effects.pinned[0].min`.
    pub single_table: bool,
}

impl Serialize for RawPinnedList {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.regions.serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for RawPinnedList {
    fn deserialize<De: serde::Deserializer<'de>>(deserializer: De) -> Result<Self, De::Error> {
        struct Regions;
        impl<'de> serde::de::Visitor<'de> for Regions {
            type Value = RawPinnedList;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("an array of tables ([[effects.pinned]]) or a table")
            }
            fn visit_map<M: serde::de::MapAccess<'de>>(
                self,
                map: M,
            ) -> Result<Self::Value, M::Error> {
                let region =
                    RawPinned::deserialize(serde::de::value::MapAccessDeserializer::new(map))?;
                Ok(RawPinnedList {
                    regions: vec![region],
                    single_table: true,
                })
            }
            fn visit_seq<S: serde::de::SeqAccess<'de>>(
                self,
                seq: S,
            ) -> Result<Self::Value, S::Error> {
                let regions = Vec::<RawPinned>::deserialize(
                    serde::de::value::SeqAccessDeserializer::new(seq),
                )?;
                Ok(RawPinnedList {
                    regions,
                    single_table: false,
                })
            }
        }
        deserializer.deserialize_any(Regions)
    }
}

/// Colouring fields.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum FieldName {
    /// Strain-energy density.
    #[default]
    EnergyDensity,
    /// Von Mises stress.
    VonMises,
    /// Volume ratio `J`.
    VolumeRatio,
    /// One flat colour.
    Flat,
}

/// `[render]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(crate) struct RawRender {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resolution: Option<Vec<i64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub field: Option<FieldName>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub colour: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub background: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub edges: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub legend: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera: Option<RawCamera>,
}

/// `[render.camera]`: 2D keys (`center`, `height`) or 3D keys (`eye`, `target`, `fov`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(crate) struct RawCamera {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eye: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fov: Option<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(key: &str) -> Vec<String> {
        choices(key)
            .unwrap()
            .as_str()
            .split('`')
            .skip(1)
            .step_by(2)
            .map(str::to_owned)
            .collect()
    }

    /// The names listed in messages are exactly the ones serde accepts.
    #[test]
    fn listed_choices_are_the_accepted_names() {
        fn accepts<T: serde::de::DeserializeOwned>(name: &str) -> bool {
            toml::Value::String(name.to_owned()).try_into::<T>().is_ok()
        }
        for name in names("mesh.generator") {
            assert!(accepts::<Generator>(&name), "{name}");
        }
        assert_eq!(
            names("material.model"),
            [
                "stvk",
                "neo-hookean",
                "stable-neo-hookean",
                "fixed-corotated"
            ]
        );
        for name in names("material.model") {
            assert!(accepts::<MaterialModel>(&name), "{name}");
        }
        assert_eq!(
            names("time.integrator"),
            ["backward-euler", "bdf2", "newmark"]
        );
        for name in names("time.integrator") {
            assert!(accepts::<IntegratorKind>(&name), "{name}");
        }
        assert_eq!(names("solver.method").len(), 2);
        for name in names("solver.method") {
            assert!(accepts::<Method>(&name), "{name}");
        }
        assert_eq!(names("solver.projection").len(), 2);
        for name in names("solver.projection") {
            assert!(accepts::<ProjectionName>(&name), "{name}");
        }
        assert_eq!(names("render.field").len(), 4);
        for name in names("render.field") {
            assert!(accepts::<FieldName>(&name), "{name}");
        }
        assert!(!accepts::<MaterialModel>("rubber"));
        assert_eq!(choices("material.young"), None);
    }
}
