//! Camera framing: from [`Camera`] and the bounds of the whole run to one
//! view-projection matrix used for every frame.
//!
//! Conventions: right-handed world, y up; clip space as in wgpu (depth in
//! `[0, 1]`). nalgebra's projections target OpenGL's `[-1, 1]` depth, so every
//! projection is followed by [`OPENGL_TO_WGPU`].
//!
//! - 2D automatic: the bounding rectangle of all frames (and the ground line),
//!   grown by a margin of 8% of its larger side, widened or heightened to the
//!   image aspect ratio, seen by an orthographic camera.
//! - 3D automatic: a perspective camera with a 30° vertical field of view,
//!   looking slightly down (about 20°) from the front right at the centre of
//!   the bounding box of all frames, pulled back until all eight corners of the
//!   box fall inside the view with a margin. Since the box holds the body in
//!   every frame, the body never leaves the picture.
//!
//! - Fixed cameras (from the scene) take their depth range from the first
//!   frame alone, so a run with one can be drawn while it is simulated.
//!
//! When a legend reserves a column on the right, automatic cameras frame the
//! remaining area: the projection is computed for that area's aspect ratio and
//! then squeezed into its part of the image.

use super::{Camera, RenderError};
use nalgebra::{Matrix4, Orthographic3, Perspective3, Point3, Vector3};

/// Maps OpenGL clip depth `[-w, w]` to wgpu's `[0, w]`.
#[rustfmt::skip]
const OPENGL_TO_WGPU: Matrix4<f32> = Matrix4::new(
    1.0, 0.0, 0.0, 0.0,
    0.0, 1.0, 0.0, 0.0,
    0.0, 0.0, 0.5, 0.5,
    0.0, 0.0, 0.0, 1.0,
);

/// Margin around the automatic 2D framing, as a fraction of the larger side.
const MARGIN_2D: f32 = 0.08;
/// Vertical field of view of the automatic 3D camera, in degrees.
const AUTO_FOV_DEGREES: f32 = 30.0;
/// Direction from the target to the automatic 3D eye (front right, above).
const AUTO_EYE_DIRECTION: [f32; 3] = [0.5, 0.42, 1.0];

/// Axis-aligned bounds of every position of every frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Bounds {
    /// Smallest coordinates.
    pub min: Vector3<f32>,
    /// Largest coordinates.
    pub max: Vector3<f32>,
}

impl Bounds {
    /// Bounds of a set of points (finite ones only); `None` when there are none.
    pub fn of_points<'a>(points: impl IntoIterator<Item = &'a [f32; 3]>) -> Option<Self> {
        let mut bounds: Option<Self> = None;
        for p in points {
            if !p.iter().all(|c| c.is_finite()) {
                continue;
            }
            let v = Vector3::from(*p);
            bounds = Some(match bounds {
                None => Self { min: v, max: v },
                Some(b) => Self {
                    min: b.min.inf(&v),
                    max: b.max.sup(&v),
                },
            });
        }
        bounds
    }

    /// Centre of the box.
    pub fn center(&self) -> Vector3<f32> {
        (self.min + self.max) * 0.5
    }

    /// Half the diagonal, at least a tiny positive length.
    pub fn radius(&self) -> f32 {
        ((self.max - self.min).norm() * 0.5).max(1e-6)
    }

    fn corners(&self) -> [Vector3<f32>; 8] {
        std::array::from_fn(|i| {
            Vector3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            )
        })
    }
}

/// A camera resolved for one run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct View {
    /// World to wgpu clip space.
    pub view_proj: Matrix4<f32>,
    /// Eye position with w = 1 (perspective), or with w = 0 (orthographic)
    /// the direction towards the viewer, as long as the visible height.
    pub eye: [f32; 4],
    /// Distance from the eye to the point looked at, in scene units (the
    /// visible height for orthographic views).
    pub distance: f32,
    /// The point looked at.
    pub target: Vector3<f32>,
}

/// What the camera must show.
pub(crate) struct Framing {
    /// 2 or 3.
    pub dimension: usize,
    /// Bounds of all frames (automatic camera) or of the first (fixed camera).
    pub bounds: Bounds,
    /// Ground height, if drawn.
    pub ground: Option<f32>,
    /// Image size in pixels.
    pub width: u32,
    /// Image size in pixels.
    pub height: u32,
    /// Width in pixels, from the left, that automatic cameras frame into.
    pub free_width: u32,
}

/// Resolves `camera` for `framing`.
pub(crate) fn resolve(camera: &Camera, framing: &Framing) -> Result<View, RenderError> {
    let aspect = framing.width as f32 / framing.height as f32;
    match *camera {
        Camera::Auto => {
            let (aspect, squeeze) = free_area(framing);
            let view = match framing.dimension {
                2 => auto_2d(framing, aspect),
                _ => auto_3d(framing, aspect),
            };
            Ok(squeeze_view(view, squeeze))
        }
        Camera::Orthographic { center, height } => {
            let valid = height > 0.0 && height.is_finite() && center.iter().all(|c| c.is_finite());
            if !valid {
                return Err(RenderError::InvalidInput(format!(
                    "orthographic camera needs a finite centre and a positive height, got centre \
                     {center:?} and height {height}"
                )));
            }
            let b = framing.bounds;
            let depth = (b.max.z - b.min.z).max(0.0) + b.radius() + 1.0;
            let eye_z = b.max.z + depth;
            let half = Vector3::new(0.5 * height * aspect, 0.5 * height, 0.0);
            let proj = Orthographic3::new(
                -half.x,
                half.x,
                -half.y,
                half.y,
                0.0,
                2.0 * depth + (b.max.z - b.min.z),
            );
            let eye = Point3::new(center[0], center[1], eye_z);
            let target = Point3::new(center[0], center[1], eye_z - depth);
            let view = look_at(&eye, &target);
            Ok(View {
                view_proj: OPENGL_TO_WGPU * proj.to_homogeneous() * view,
                eye: [0.0, 0.0, height, 0.0],
                distance: height,
                target: target.coords,
            })
        }
        Camera::Perspective {
            eye,
            target,
            fov_degrees,
        } => {
            let eye = Point3::from(eye);
            let target = Point3::from(target);
            let distance = (target - eye).norm();
            let valid =
                fov_degrees > 0.0 && fov_degrees < 180.0 && distance > 0.0 && distance.is_finite();
            if !valid {
                return Err(RenderError::InvalidInput(format!(
                    "perspective camera needs distinct finite eye and target and a field of view \
                     between 0 and 180 degrees, got eye {:?}, target {:?}, fov {fov_degrees}",
                    eye.coords.as_slice(),
                    target.coords.as_slice()
                )));
            }
            let reach = (framing.bounds.center() - eye.coords).norm() + framing.bounds.radius();
            let proj = perspective(aspect, fov_degrees, distance, reach);
            Ok(View {
                view_proj: proj * look_at(&eye, &target),
                eye: [eye.x, eye.y, eye.z, 1.0],
                distance,
                target: target.coords,
            })
        }
    }
}

/// Aspect ratio of the free area and the squeeze `(scale, offset)` that maps
/// the full clip-space width onto it.
fn free_area(framing: &Framing) -> (f32, (f32, f32)) {
    let free = framing.free_width.clamp(1, framing.width) as f32;
    let scale = free / framing.width as f32;
    (free / framing.height as f32, (scale, scale - 1.0))
}

fn squeeze_view(mut view: View, (scale, offset): (f32, f32)) -> View {
    let mut squeeze = Matrix4::identity();
    squeeze[(0, 0)] = scale;
    squeeze[(0, 3)] = offset;
    view.view_proj = squeeze * view.view_proj;
    view
}

fn auto_2d(framing: &Framing, aspect: f32) -> View {
    let b = framing.bounds;
    let (mut lo, mut hi) = (b.min.xy(), b.max.xy());
    if let Some(ground) = framing.ground {
        lo.y = lo.y.min(ground);
        hi.y = hi.y.max(ground);
    }
    let extent = (hi - lo).max().max(1e-6);
    lo -= nalgebra::Vector2::repeat(MARGIN_2D * extent);
    hi += nalgebra::Vector2::repeat(MARGIN_2D * extent);
    if let Some(ground) = framing.ground {
        // Always show a band of ground below the surface line.
        lo.y = lo.y.min(ground - 0.6 * MARGIN_2D * extent);
    }
    let (mut w, mut h) = (hi.x - lo.x, hi.y - lo.y);
    if w / h < aspect {
        w = h * aspect;
    } else {
        h = w / aspect;
    }
    let c = (lo + hi) * 0.5;
    let proj = Orthographic3::new(
        c.x - 0.5 * w,
        c.x + 0.5 * w,
        c.y - 0.5 * h,
        c.y + 0.5 * h,
        -1.0,
        1.0,
    );
    View {
        view_proj: OPENGL_TO_WGPU * proj.to_homogeneous(),
        eye: [0.0, 0.0, h, 0.0],
        distance: h,
        target: Vector3::new(c.x, c.y, 0.0),
    }
}

fn auto_3d(framing: &Framing, aspect: f32) -> View {
    let b = framing.bounds;
    let target = b.center();
    let radius = b.radius();
    let back = Vector3::from(AUTO_EYE_DIRECTION).normalize();
    let right = Vector3::y().cross(&back).normalize();
    let up = back.cross(&right);
    let tan_y = (0.5 * AUTO_FOV_DEGREES.to_radians()).tan();
    let tan_x = tan_y * aspect;
    // A corner at (x, y) across and z towards the eye, seen from distance d,
    // is inside the view when |x| <= (d - z) tan_x and |y| <= (d - z) tan_y.
    let mut distance: f32 = 0.0;
    for corner in b.corners() {
        let p = corner - target;
        let (x, y, z) = (p.dot(&right), p.dot(&up), p.dot(&back));
        distance = distance.max(x.abs() / tan_x + z).max(y.abs() / tan_y + z);
    }
    let distance = (distance * 1.12).max(radius * 1.2);
    let eye = Point3::from(target + back * distance);
    let proj = perspective(aspect, AUTO_FOV_DEGREES, distance, distance + radius);
    View {
        view_proj: proj * look_at(&eye, &Point3::from(target)),
        eye: [eye.x, eye.y, eye.z, 1.0],
        distance,
        target,
    }
}

/// A perspective projection whose depth range holds the scene (up to
/// `reach` from the eye) and the ground plane around it.
fn perspective(aspect: f32, fov_degrees: f32, distance: f32, reach: f32) -> Matrix4<f32> {
    let near = (0.02 * distance).min(0.5 * reach).max(1e-5);
    let far = 60.0 * reach.max(distance);
    OPENGL_TO_WGPU * Perspective3::new(aspect, fov_degrees.to_radians(), near, far).to_homogeneous()
}

fn look_at(eye: &Point3<f32>, target: &Point3<f32>) -> Matrix4<f32> {
    let forward = (target - eye).normalize();
    // Looking straight up or down: y cannot be "up", use -z instead.
    let up = if forward.y.abs() > 0.999 {
        -Vector3::z()
    } else {
        Vector3::y()
    };
    Matrix4::look_at_rh(eye, target, &up)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn clip(view: &View, p: [f32; 3]) -> Vector3<f32> {
        let c = view.view_proj * nalgebra::Vector4::new(p[0], p[1], p[2], 1.0);
        Vector3::new(c.x / c.w, c.y / c.w, c.z / c.w)
    }

    fn framing(dimension: usize, min: [f32; 3], max: [f32; 3], free_width: u32) -> Framing {
        Framing {
            dimension,
            bounds: Bounds {
                min: min.into(),
                max: max.into(),
            },
            ground: None,
            width: 200,
            height: 100,
            free_width,
        }
    }

    #[test]
    fn auto_2d_centres_and_keeps_aspect() {
        let f = framing(2, [0.0, 0.0, 0.0], [1.0, 1.0, 0.0], 200);
        let view = resolve(&Camera::Auto, &f).unwrap();
        let centre = clip(&view, [0.5, 0.5, 0.0]);
        assert!(centre.x.abs() < 1e-6 && centre.y.abs() < 1e-6);
        // The unit square is limited by height: 1 + 2 * 8% margin fills 2 NDC units.
        let top = clip(&view, [0.5, 1.0, 0.0]);
        assert!((top.y - 1.0 / 1.16).abs() < 1e-5, "{top:?}");
        // Square pixels: the right edge is half as far in NDC x (image is 2:1).
        let right = clip(&view, [1.0, 0.5, 0.0]);
        assert!((right.x - 0.5 / 1.16).abs() < 1e-5, "{right:?}");
        assert!((centre.z - 0.5).abs() < 1e-6, "2D depth sits mid-range");
    }

    #[test]
    fn auto_2d_includes_ground_with_a_band_below() {
        let mut f = framing(2, [0.0, 2.0, 0.0], [1.0, 3.0, 0.0], 200);
        f.ground = Some(0.0);
        let view = resolve(&Camera::Auto, &f).unwrap();
        let ground = clip(&view, [0.5, 0.0, 0.0]);
        assert!(ground.y > -0.99 && ground.y < -0.8, "{ground:?}");
        assert!(clip(&view, [0.5, 3.0, 0.0]).y < 1.0);
    }

    #[test]
    fn legend_column_shifts_the_framing_left() {
        let f = framing(2, [0.0, 0.0, 0.0], [1.0, 1.0, 0.0], 150);
        let view = resolve(&Camera::Auto, &f).unwrap();
        let centre = clip(&view, [0.5, 0.5, 0.0]);
        // The free area is x in [-1, 0.5] NDC, centred at -0.25.
        assert!((centre.x + 0.25).abs() < 1e-6, "{centre:?}");
    }

    #[test]
    fn auto_3d_keeps_every_corner_inside_with_depth_in_range() {
        let f = framing(3, [-1.0, 0.0, -0.5], [1.0, 4.0, 0.5], 200);
        let view = resolve(&Camera::Auto, &f).unwrap();
        for corner in f.bounds.corners() {
            let c = clip(&view, corner.into());
            assert!(
                c.x.abs() < 1.0 && c.y.abs() < 1.0,
                "corner {corner:?} at {c:?}"
            );
            assert!(c.z > 0.0 && c.z < 1.0, "depth {c:?}");
        }
        // Looking down: the eye is above the target.
        assert!(view.eye[1] > view.target.y);
        // Tight: some corner comes close to the edge.
        let widest = f
            .bounds
            .corners()
            .iter()
            .map(|&p| {
                let c = clip(&view, p.into());
                c.x.abs().max(c.y.abs())
            })
            .fold(0.0, f32::max);
        assert!(widest > 0.8, "framing too loose: {widest}");
    }

    #[test]
    fn bad_explicit_cameras_are_errors() {
        let f = framing(3, [0.0; 3], [1.0; 3], 200);
        let flat = Camera::Perspective {
            eye: [1.0; 3],
            target: [1.0; 3],
            fov_degrees: 40.0,
        };
        assert!(matches!(
            resolve(&flat, &f),
            Err(RenderError::InvalidInput(_))
        ));
        let wide = Camera::Perspective {
            eye: [0.0, 0.0, 5.0],
            target: [0.0; 3],
            fov_degrees: 180.0,
        };
        assert!(matches!(
            resolve(&wide, &f),
            Err(RenderError::InvalidInput(_))
        ));
        let ortho = Camera::Orthographic {
            center: [0.0, 0.0],
            height: 0.0,
        };
        assert!(matches!(
            resolve(&ortho, &f),
            Err(RenderError::InvalidInput(_))
        ));
    }

    #[test]
    fn explicit_orthographic_shows_the_given_height() {
        let f = framing(2, [0.0; 3], [1.0, 1.0, 0.0], 200);
        let view = resolve(
            &Camera::Orthographic {
                center: [1.0, 2.0],
                height: 4.0,
            },
            &f,
        )
        .unwrap();
        let top = clip(&view, [1.0, 4.0, 0.0]);
        assert!((top.y - 1.0).abs() < 1e-5 && top.x.abs() < 1e-5, "{top:?}");
        let right = clip(&view, [5.0, 2.0, 0.0]);
        assert!((right.x - 1.0).abs() < 1e-5, "{right:?}");
    }
}
