//! The bodies: `[mesh]` and `[material]` of a one-body scene or `[[bodies]]`,
//! each body's material, pinned regions and their rigid paths.

use super::{SceneValidator, VResult};
use crate::material::{LameParameters, YoungPoisson};
use crate::math::{Vector, Vector3};
use crate::scene::raw_scene::{RawBody, RawMaterial, RawMesh, RawPinned, RawScene};
use crate::scene::scene_config::{BodyConfig, DEFAULT_DENSITY, MaterialConfig};
use crate::scene::scene_error::{num, nums};
use crate::sim::{PinMotion, PinRegion};

impl SceneValidator<'_, '_> {
    /// The bodies: `[mesh]` and `[material]` (one body), or `[[bodies]]`.
    #[allow(clippy::type_complexity)]
    pub(super) fn bodies<const D: usize>(
        &self,
        raw: &RawScene,
    ) -> VResult<(
        Vec<BodyConfig<D>>,
        Option<RawMesh>,
        Option<RawMaterial>,
        Option<Vec<RawBody>>,
    )> {
        match (&raw.mesh, &raw.material, &raw.bodies) {
            (Some(mesh), Some(material), None) => {
                let (body, raw_mesh, raw_material) = self.body::<D>(mesh, material)?;
                Ok((vec![body], Some(raw_mesh), Some(raw_material), None))
            }
            (None, None, Some(list)) => {
                if list.is_empty() {
                    return Err(self.err("bodies", "needs at least one [[bodies]] entry"));
                }
                let mut bodies = Vec::with_capacity(list.len());
                let mut resolved = Vec::with_capacity(list.len());
                for (i, entry) in list.iter().enumerate() {
                    let prefix = format!("bodies[{i}].");
                    let v = self.under(prefix.clone());
                    let (mut body, mesh, material) = v.body::<D>(&entry.mesh, &entry.material)?;
                    if let Some(p) = &entry.pinned {
                        let region = v.pin_region::<D>("pinned", p)?;
                        if !body.mesh.vertices_in(&region).0 {
                            return Err(v.err(
                                "pinned",
                                "the region from `min` to `max` contains no vertex of this body \
                                 at rest; widen it to catch the vertices to hold",
                            ));
                        }
                        body.pinned = Some(region);
                    }
                    body.key_prefix = prefix;
                    bodies.push(body);
                    resolved.push(RawBody {
                        mesh,
                        material,
                        pinned: entry.pinned.clone(),
                    });
                }
                Ok((bodies, None, None, Some(resolved)))
            }
            (_, _, Some(_)) => {
                let key = if raw.mesh.is_some() {
                    "mesh"
                } else {
                    "material"
                };
                Err(self.err(
                    key,
                    "cannot be given with [[bodies]]: a scene is one body ([mesh] and \
                     [material]) or several ([[bodies]], each with its own mesh and material), \
                     not both",
                ))
            }
            (None, _, None) => Err(self.err(
                "mesh",
                "is required: give [mesh] and [material] for one body, or [[bodies]]",
            )),
            (Some(_), None, None) => Err(self.err(
                "material",
                "is required: give [mesh] and [material] for one body, or [[bodies]]",
            )),
        }
    }

    /// One body from its mesh and material tables (keys under `self.prefix`).
    pub(super) fn body<const D: usize>(
        &self,
        raw_mesh: &RawMesh,
        raw_material: &RawMaterial,
    ) -> VResult<(BodyConfig<D>, RawMesh, RawMaterial)> {
        let (mesh, initial_velocity, raw_mesh) = self.mesh::<D>(raw_mesh)?;
        let (material, raw_material) = self.material(raw_material)?;
        self.mass(&mesh, material.density)?;
        Ok((
            BodyConfig {
                mesh,
                initial_velocity,
                material,
                pinned: None,
                key_prefix: String::new(),
            },
            raw_mesh,
            raw_material,
        ))
    }

    /// A pinned box `min`..`max` at `key` (`effects.pinned[i]`, `pinned`)
    /// and its motion (`velocity`, `angular_velocity`, `axis`, `center`,
    /// `until`, `release`).
    pub(super) fn pin_region<const D: usize>(
        &self,
        key: &str,
        p: &RawPinned,
    ) -> VResult<PinRegion<D>> {
        let min = self.vector::<D>(&format!("{key}.min"), &p.min)?;
        let max = self.vector::<D>(&format!("{key}.max"), &p.max)?;
        if let Some(axis) = (0..D).find(|&a| min[a] > max[a]) {
            return Err(self.err(
                &format!("{key}.max"),
                format!(
                    "is below {key}.min along axis {axis} ({} < {})",
                    num(max[axis]),
                    num(min[axis])
                ),
            ));
        }
        let region = PinRegion::new(min, max);
        let motion = self.motion::<D>(&format!("{key}."), p, region.box_center())?;
        Ok(region.moving(motion))
    }

    /// A rigid path from the motion keys of `p` under `key` (`velocity`,
    /// `angular_velocity`, `axis`, `center`, defaulting to `center`,
    /// `until`, `release`); `key` ends with a dot or is empty.
    pub(super) fn motion<const D: usize>(
        &self,
        key: &str,
        p: &RawPinned,
        center: Vector<D>,
    ) -> VResult<PinMotion<D>> {
        // The full key in messages (with `bodies[1].` or `obstacles[0].`).
        let at = format!("{}{key}", self.prefix);
        let mut motion = PinMotion::<D> {
            center,
            ..PinMotion::default()
        };
        if let Some(v) = &p.velocity {
            motion.velocity = self.vector::<D>(&format!("{key}velocity"), v)?;
        }
        if let Some(w) = p.angular_velocity {
            if !w.is_finite() {
                return Err(self.err(
                    &format!("{key}angular_velocity"),
                    format!("must be finite (rad/s), got {}", num(w)),
                ));
            }
            motion.angular_velocity = w;
        }
        let rotates = p.angular_velocity.is_some();
        for (name, given) in [("axis", p.axis.is_some()), ("center", p.center.is_some())] {
            if given && !rotates {
                return Err(self.err(
                    &format!("{key}{name}"),
                    format!("has no effect without {at}angular_velocity; give the angular velocity (rad/s) or remove it"),
                ));
            }
        }
        match (&p.axis, D) {
            (Some(_), 2) => {
                return Err(self.err(
                    &format!("{key}axis"),
                    "is a 3D key: in 2D a motion rotates in the plane \
                     (counter-clockwise for angular_velocity > 0); remove it",
                ));
            }
            (Some(a), _) => {
                let axis = self.vector::<3>(&format!("{key}axis"), a)?;
                let norm = axis.norm();
                if !(norm > 0.0 && norm.is_finite()) {
                    return Err(self.err(
                        &format!("{key}axis"),
                        format!("must be a non-zero direction, got {}", nums(a)),
                    ));
                }
                motion.axis = axis / norm;
            }
            (None, 3) if rotates => {
                return Err(self.err(
                    &format!("{key}axis"),
                    format!("is required in 3D with {at}angular_velocity: the direction to rotate about, e.g. [1, 0, 0]"),
                ));
            }
            (None, _) => motion.axis = Vector3::z(),
        }
        if let Some(c) = &p.center {
            motion.center = self.vector::<D>(&format!("{key}center"), c)?;
        }
        if let Some(until) = p.until {
            if !(until >= 0.0 && until.is_finite()) {
                return Err(self.err(
                    &format!("{key}until"),
                    format!("must be a finite time >= 0 (s), got {}", num(until)),
                ));
            }
            if p.velocity.is_none() && !rotates {
                return Err(self.err(
                    &format!("{key}until"),
                    format!("has no effect on a path that does not move; give {at}velocity or {at}angular_velocity, or remove it"),
                ));
            }
            motion.until = Some(until);
        }
        if let Some(release) = p.release {
            if !(release > 0.0 && release.is_finite()) {
                return Err(self.err(
                    &format!("{key}release"),
                    format!("must be a finite time > 0 (s), got {}", num(release)),
                ));
            }
            motion.release = Some(release);
        }
        Ok(motion)
    }

    /// `[material]` (or a body's `material`): the model, Young's modulus and
    /// Poisson's ratio (or Lamé's parameters) and the density.
    pub(super) fn material(&self, raw: &RawMaterial) -> VResult<(MaterialConfig, RawMaterial)> {
        let lame = match (raw.young, raw.poisson, raw.mu, raw.lambda) {
            (Some(young), Some(poisson), None, None) => {
                self.positive("material.young", young)?;
                if !(poisson > -1.0 && poisson < 0.5) {
                    return Err(self.err(
                        "material.poisson",
                        format!("must lie in (-1, 0.5), got {}", num(poisson)),
                    ));
                }
                let lame = LameParameters::from(YoungPoisson { young, poisson });
                if !(lame.mu.is_finite() && lame.lambda.is_finite()) {
                    return Err(self.err(
                        "material.young",
                        format!(
                            "{} with poisson = {} gives Lamé parameters outside double \
                             precision (mu = {}, lambda = {})",
                            num(young),
                            num(poisson),
                            num(lame.mu),
                            num(lame.lambda)
                        ),
                    ));
                }
                lame
            }
            (None, None, Some(mu), Some(lambda)) => {
                self.positive("material.mu", mu)?;
                if !(lambda.is_finite() && 3.0 * lambda + 2.0 * mu > 0.0) {
                    return Err(self.err(
                        "material.lambda",
                        format!(
                            "must be finite with 3 lambda + 2 mu > 0 (a positive bulk modulus), got {}",
                            num(lambda)
                        ),
                    ));
                }
                LameParameters { mu, lambda }
            }
            (young, poisson, mu, lambda) => {
                let (elastic, lame) = (
                    young.is_some() || poisson.is_some(),
                    mu.is_some() || lambda.is_some(),
                );
                let (key, reason) = match (elastic, lame) {
                    (true, true) => (
                        if mu.is_some() { "material.mu" } else { "material.lambda" },
                        "give either `young` and `poisson`, or `mu` and `lambda`, not both".to_owned(),
                    ),
                    (false, false) => (
                        "material",
                        "the stiffness is missing: give `young` and `poisson`, or `mu` and `lambda`".to_owned(),
                    ),
                    _ => {
                        let pairs = [("young", young, "poisson", poisson), ("poisson", poisson, "young", young)]
                            .into_iter()
                            .chain([("mu", mu, "lambda", lambda), ("lambda", lambda, "mu", mu)]);
                        let (given, missing) = pairs
                            .into_iter()
                            .find(|(_, a, _, b)| a.is_some() && b.is_none())
                            .map(|(g, _, m, _)| (g, m))
                            .expect("exactly one key of a pair is given");
                        return Err(self.err(
                            &format!("material.{missing}"),
                            format!("is required together with `{given}`"),
                        ));
                    }
                };
                return Err(self.err(key, reason));
            }
        };
        let density = self.positive("material.density", raw.density.unwrap_or(DEFAULT_DENSITY))?;
        let material = raw.model.with_lame(lame);
        let resolved = RawMaterial {
            density: Some(density),
            ..raw.clone()
        };
        Ok((MaterialConfig { material, density }, resolved))
    }
}
