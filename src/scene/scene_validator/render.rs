//! `[render]`: the field, colours, resolution and camera, and the image-size
//! limits.

use super::{SceneValidator, VResult};
use crate::energy::ElementField;
use crate::math::Vector;
use crate::render::{Camera, Colouring, RenderSettings};
use crate::scene::raw_scene::{FieldName, RawCamera, RawRender};
use crate::scene::scene_config::{
    DEFAULT_BACKGROUND, DEFAULT_COLOUR, DEFAULT_FOV, DEFAULT_RESOLUTION, FieldChoice,
    MAX_IMAGE_BYTES, MAX_RESOLUTION, image_bytes,
};
use crate::scene::scene_error::{num, nums};

impl SceneValidator<'_, '_> {
    /// An sRGB colour of three values in [0, 1] (`default` when not given).
    pub(super) fn colour(
        &self,
        key: &str,
        v: Option<&Vec<f64>>,
        default: [f64; 3],
    ) -> VResult<[f64; 3]> {
        let Some(v) = v else { return Ok(default) };
        if v.len() != 3 || v.iter().any(|c| !(0.0..=1.0).contains(c)) {
            return Err(self.err(
                key,
                format!(
                    "must be 3 components in [0, 1] (linear RGB), got {}",
                    nums(v)
                ),
            ));
        }
        Ok([v[0], v[1], v[2]])
    }

    /// `[render]`: the field shown, colours, resolution, legend and camera.
    pub(super) fn render<const D: usize>(
        &self,
        raw: &RawRender,
        ground_height: Option<f64>,
    ) -> VResult<(FieldChoice, RenderSettings, RawRender)> {
        let resolution = match &raw.resolution {
            None => DEFAULT_RESOLUTION,
            Some(r) => {
                let ok =
                    r.len() == 2 && r.iter().all(|&p| (1..=MAX_RESOLUTION as i64).contains(&p));
                if !ok {
                    return Err(self.err(
                        "render.resolution",
                        format!("must be [width, height] in pixels, each 1..={MAX_RESOLUTION}, got {r:?}"),
                    ));
                }
                let [width, height] = [r[0] as u32, r[1] as u32];
                if image_bytes(width, height) > MAX_IMAGE_BYTES {
                    return Err(self.err(
                        "render.resolution",
                        format!(
                            "{width}x{height} is too large: an image is read back from the GPU \
                             in one buffer of at most {} MiB (4 bytes per pixel, rows padded \
                             to 256 bytes), this one needs {:.1} MiB",
                            MAX_IMAGE_BYTES >> 20,
                            image_bytes(width, height) as f64 / (1u64 << 20) as f64
                        ),
                    ));
                }
                [width, height]
            }
        };
        let field = match raw.field.unwrap_or_default() {
            FieldName::EnergyDensity => FieldChoice::Scalar(ElementField::EnergyDensity),
            FieldName::VonMises => FieldChoice::Scalar(ElementField::VonMises),
            FieldName::VolumeRatio => FieldChoice::Scalar(ElementField::VolumeRatio),
            FieldName::Flat => FieldChoice::Flat,
        };
        let range = match &raw.range {
            None => None,
            Some(r) => {
                if r.len() != 2 || !r.iter().all(|x| x.is_finite()) || r[0] >= r[1] {
                    return Err(self.err(
                        "render.range",
                        format!("must be [low, high] with low < high, got {}", nums(r)),
                    ));
                }
                self.single_precision("render.range", r, false)?;
                if (r[0] as f32) >= (r[1] as f32) {
                    return Err(self.err(
                        "render.range",
                        format!(
                            "{} is too narrow for the renderer's 32-bit floats: low and high \
                             round to the same value",
                            nums(r)
                        ),
                    ));
                }
                Some([r[0], r[1]])
            }
        };
        let colour = self.colour("render.colour", raw.colour.as_ref(), DEFAULT_COLOUR)?;
        let background = self.colour(
            "render.background",
            raw.background.as_ref(),
            DEFAULT_BACKGROUND,
        )?;
        let (camera, raw_camera) = match &raw.camera {
            None => (Camera::Auto, None),
            Some(c) => {
                let camera = self.camera::<D>(c)?;
                let resolved = match camera {
                    Camera::Perspective { .. } => RawCamera {
                        fov: Some(c.fov.unwrap_or(DEFAULT_FOV)),
                        ..c.clone()
                    },
                    _ => c.clone(),
                };
                (camera, Some(resolved))
            }
        };
        let colouring = match field {
            FieldChoice::Flat => Colouring::Flat(colour.map(|c| c as f32)),
            field => Colouring::Scalar {
                range: range.map(|r| r.map(|x| x as f32)),
                label: field.label(),
            },
        };
        let settings = RenderSettings {
            width: resolution[0],
            height: resolution[1],
            camera,
            colouring,
            background: background.map(|c| c as f32),
            ground_height: ground_height.map(|h| h as f32),
            draw_edges: raw.edges.unwrap_or(true),
            draw_legend: raw.legend.unwrap_or(true),
        };
        let resolved = RawRender {
            resolution: Some(resolution.iter().map(|&p| i64::from(p)).collect()),
            field: Some(raw.field.unwrap_or_default()),
            range: range.map(|r| r.to_vec()),
            colour: Some(colour.to_vec()),
            background: Some(background.to_vec()),
            edges: Some(settings.draw_edges),
            legend: Some(settings.draw_legend),
            camera: raw_camera,
        };
        Ok((field, settings, resolved))
    }

    /// `[render.camera]`: orthographic in 2D, perspective in 3D.
    pub(super) fn camera<const D: usize>(&self, raw: &RawCamera) -> VResult<Camera> {
        let f32s = |v: Vector<D>| -> Vec<f32> { v.iter().map(|&x| x as f32).collect() };
        if D == 2 {
            for (key, present) in [
                ("eye", raw.eye.is_some()),
                ("target", raw.target.is_some()),
                ("fov", raw.fov.is_some()),
            ] {
                if present {
                    return Err(self.err(
                        &format!("render.camera.{key}"),
                        "is a 3D camera key; a 2D camera takes `center` and `height`",
                    ));
                }
            }
            let center = raw
                .center
                .as_ref()
                .ok_or_else(|| self.err("render.camera.center", "is required for a 2D camera"))?;
            let center = self.vector::<D>("render.camera.center", center)?;
            self.single_precision("render.camera.center", center.as_slice(), false)?;
            let center = f32s(center);
            let height = raw
                .height
                .ok_or_else(|| self.err("render.camera.height", "is required for a 2D camera"))?;
            let height = self.positive("render.camera.height", height)?;
            self.single_precision("render.camera.height", &[height], true)?;
            Ok(Camera::Orthographic {
                center: [center[0], center[1]],
                height: height as f32,
            })
        } else {
            for (key, present) in [
                ("center", raw.center.is_some()),
                ("height", raw.height.is_some()),
            ] {
                if present {
                    return Err(self.err(
                        &format!("render.camera.{key}"),
                        "is a 2D camera key; a 3D camera takes `eye`, `target` and `fov`",
                    ));
                }
            }
            let eye = raw
                .eye
                .as_ref()
                .ok_or_else(|| self.err("render.camera.eye", "is required for a 3D camera"))?;
            let eye = self.vector::<D>("render.camera.eye", eye)?;
            self.single_precision("render.camera.eye", eye.as_slice(), false)?;
            let eye = f32s(eye);
            let target = raw
                .target
                .as_ref()
                .ok_or_else(|| self.err("render.camera.target", "is required for a 3D camera"))?;
            let target = self.vector::<D>("render.camera.target", target)?;
            self.single_precision("render.camera.target", target.as_slice(), false)?;
            let target = f32s(target);
            if eye == target {
                return Err(self.err("render.camera.target", "must differ from `eye`"));
            }
            let distance = (0..3)
                .map(|k| f64::from(eye[k]) - f64::from(target[k]))
                .map(|d| d * d)
                .sum::<f64>()
                .sqrt();
            if !((distance as f32).is_finite()) {
                return Err(self.err(
                    "render.camera.target",
                    format!(
                        "is {} from `eye`, out of the renderer's range: images are drawn in \
                         32-bit floats, which hold magnitudes up to 3.4e38",
                        num(distance)
                    ),
                ));
            }
            let fov = raw.fov.unwrap_or(DEFAULT_FOV);
            if !(fov > 0.0 && fov < 180.0) {
                return Err(self.err(
                    "render.camera.fov",
                    format!("must lie in (0, 180) degrees, got {}", num(fov)),
                ));
            }
            Ok(Camera::Perspective {
                eye: [eye[0], eye[1], eye[2]],
                target: [target[0], target[1], target[2]],
                fov_degrees: fov as f32,
            })
        }
    }
}
