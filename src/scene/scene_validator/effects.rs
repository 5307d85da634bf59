//! `[effects]`: gravity, the ground, contact and its friction, pinned regions.

use super::{MAX_BARRIER_WIDTH_TO_SCENE, SceneValidator, VResult, bounding_box_diagonal};
use crate::math::UP_AXIS;
use crate::scene::raw_scene::{RawContact, RawEffects, RawGround, RawPinnedList};
use crate::scene::scene_config::{BodyConfig, DEFAULT_BARRIER_WIDTH, MeshConfig};
use crate::scene::scene_error::{approx, num};
use crate::sim::{Contact, Effects, Ground};

impl SceneValidator<'_, '_> {
    /// A friction coefficient: 0 or more, finite.
    pub(super) fn friction_coefficient(&self, key: &str, mu: Option<f64>) -> VResult<f64> {
        match mu {
            None => Ok(0.0),
            Some(mu) if mu >= 0.0 && mu.is_finite() => Ok(mu),
            Some(mu) => Err(self.err(
                key,
                format!("must be 0 or more and finite, got {}", num(mu)),
            )),
        }
    }

    /// `[effects]`: gravity, the ground, contact and the pinned regions, each
    /// only when the scene asks for it.
    pub(super) fn effects<const D: usize>(
        &self,
        raw: &RawEffects,
        bodies: &[BodyConfig<D>],
    ) -> VResult<(Effects<D>, RawEffects)> {
        let mut effects = Effects::<D>::default();
        let mut resolved = RawEffects::default();
        if let Some(g) = &raw.gravity {
            effects.gravity =
                Some(self.vector::<D>("effects.gravity.acceleration", &g.acceleration)?);
            resolved.gravity = Some(g.clone());
        }
        if let Some(g) = &raw.ground {
            let height = g.height.unwrap_or(0.0);
            if !height.is_finite() {
                return Err(self.err(
                    "effects.ground.height",
                    format!("must be finite, got {}", num(height)),
                ));
            }
            self.single_precision("effects.ground.height", &[height], false)?;
            let a = self.positive("effects.ground.a", g.a.unwrap_or(DEFAULT_BARRIER_WIDTH))?;
            if !(1e-150..=1e150).contains(&a) {
                return Err(self.err(
                    "effects.ground.a",
                    format!(
                        "must lie in [1e-150, 1e150]: the barrier squares it, and its square \
                         must be a normal double; got {}",
                        num(a)
                    ),
                ));
            }
            let kappa = match g.kappa {
                Some(k) => Some(self.positive("effects.ground.kappa", k)?),
                None => None,
            };
            let (bottom, key) = bodies
                .iter()
                .map(|b| match &b.mesh {
                    MeshConfig::Box(m) => {
                        (m.offset[UP_AXIS], format!("{}mesh.offset", b.key_prefix))
                    }
                    MeshConfig::File(f) => (
                        f.mesh
                            .rest_positions()
                            .iter()
                            .map(|x| x[UP_AXIS])
                            .fold(f64::INFINITY, f64::min),
                        format!("{}mesh.translate", b.key_prefix),
                    ),
                })
                .fold((f64::INFINITY, String::new()), |low, b| {
                    if b.0 < low.0 { b } else { low }
                });
            if bottom <= height {
                return Err(self.err(
                    &key,
                    format!(
                        "the mesh starts at height {}, on or below the ground at {} \
                         (effects.ground.height); raise {key}[{UP_AXIS}]",
                        num(bottom),
                        num(height)
                    ),
                ));
            }
            // The barrier acts within `a` of the ground; far beyond the
            // scene's own lengths it pushes every vertex from the start with
            // a stiffness scaled to `a` (the default rule floors it by
            // `M a² / s²`), and the first step is lost to round-off.
            let scale = bounding_box_diagonal(bodies) + (bottom - height);
            if a > MAX_BARRIER_WIDTH_TO_SCENE * scale {
                return Err(self.err(
                    "effects.ground.a",
                    format!(
                        "{} is more than {} times the scene's size {} (the bodies' bounding box \
                         diagonal plus the gap they start at above the ground): the barrier \
                         would push every vertex from the start with a force that crushes the \
                         bodies and loses the first step to round-off; at most {} here (the \
                         default is {})",
                        num(a),
                        num(MAX_BARRIER_WIDTH_TO_SCENE),
                        approx(scale),
                        approx(MAX_BARRIER_WIDTH_TO_SCENE * scale),
                        num(DEFAULT_BARRIER_WIDTH)
                    ),
                ));
            }
            let friction = self.friction_coefficient("effects.ground.friction", g.friction)?;
            effects.ground = Some(Ground {
                height,
                activation_distance: a,
                stiffness: kappa,
                friction,
            });
            resolved.ground = Some(RawGround {
                height: Some(height),
                a: Some(a),
                kappa,
                friction: (friction > 0.0).then_some(friction),
            });
        }
        if let Some(c) = &raw.contact {
            let distance = match c.distance {
                Some(d) => self.positive("effects.contact.distance", d)?,
                None => 1e-3 * bounding_box_diagonal(bodies),
            };
            if !(1e-150..=1e150).contains(&distance) {
                return Err(self.err(
                    "effects.contact.distance",
                    format!(
                        "must lie in [1e-150, 1e150]: the barrier works on its square squared, \
                         which must be a normal double; got {}",
                        num(distance)
                    ),
                ));
            }
            let kappa = match c.kappa {
                Some(k) => Some(self.positive("effects.contact.kappa", k)?),
                None => None,
            };
            let self_contact = c.self_contact.unwrap_or(true);
            let friction = self.friction_coefficient("effects.contact.friction", c.friction)?;
            effects.contact = Some(Contact {
                distance: Some(distance),
                stiffness: kappa,
                self_contact,
                friction,
            });
            resolved.contact = Some(RawContact {
                distance: Some(distance),
                kappa,
                self_contact: Some(self_contact),
                friction: (friction > 0.0).then_some(friction),
            });
        }
        if let Some(list) = &raw.pinned {
            if list.regions.is_empty() {
                return Err(self.err(
                    "effects.pinned",
                    "is an empty array: give at least one [[effects.pinned]] region, or remove it",
                ));
            }
            for (i, p) in list.regions.iter().enumerate() {
                let key = if list.single_table {
                    "effects.pinned".to_owned()
                } else {
                    format!("effects.pinned[{i}]")
                };
                let region = self.pin_region::<D>(&key, p)?;
                // A vertex is pinned when it lies in the box (inclusive) at rest.
                let (mut catches, mut holds_all) = (false, true);
                for body in bodies {
                    let (c, h) = body.mesh.vertices_in(&region);
                    catches |= c;
                    holds_all &= h;
                }
                if !catches {
                    return Err(self.err(
                        &key,
                        "the region from `min` to `max` contains no mesh vertex at rest; widen it to catch the vertices to hold",
                    ));
                }
                if holds_all {
                    return Err(self.err(
                        &key,
                        "the region from `min` to `max` holds every mesh vertex: nothing could move; \
                         narrow it to the vertices to hold",
                    ));
                }
                effects.pinned.push(region);
            }
            resolved.pinned = Some(RawPinnedList {
                regions: list.regions.clone(),
                single_table: false,
            });
        }
        Ok((effects, resolved))
    }
}
