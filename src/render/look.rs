//! [`Look`]: how every frame of a run appears, fixed when the run starts —
//! camera, colours, ground, contact shadow, edges, obstacles and legend —
//! and where a frame can differ from the backdrop (its tile).
//!
//! - Colours: element scalars through viridis over one range for the whole
//!   run (`colour_range`), NaN as a neutral grey, or one flat colour;
//!   computed in sRGB and converted to linear for the shaders.
//! - Ground: in 2D a dark surface line across the view over the hatched
//!   half-plane below it; in 3D an anti-aliased checkered floor whose tile is
//!   a round number near the bodies' size (`nice_tile`), fading into a soft
//!   vertical background gradient far away.
//! - Shadow: in 3D a soft contact shadow under the bodies that fades, widens
//!   and blurs as they rise (`contact_shadow`); it follows every frame.
//! - Edges: thin dark lines, faded out when the median edge is so short on
//!   screen that lines would cover the colours (dense meshes, small images).
//! - Obstacles: one cool grey, apart from the colour map and from the NaN
//!   grey; in 2D a translucent fill with a darker outline, in 3D lit like
//!   the bodies with their edge lines.
//! - Legend: the colour bar with the field's label, drawn on the CPU.
//!
//! Sizes scale with the image height (reference: 720 pixels).

use super::camera::{self, Bounds, Framing, View};
use super::colormap::{srgb_to_linear3, viridis};
use super::legend::Legend;
use super::pipelines::{Globals, LineInstance};
use super::pixel_rect::{PixelRect, projected_rect};
use super::{Camera, Colouring, RenderError, RenderFrame, RenderMesh, RenderSettings};
use image::RgbaImage;
use nalgebra::{Matrix4, Vector3, Vector4};

/// Colour of mesh edges, sRGB.
const EDGE_SRGB: [f32; 3] = [0.08, 0.08, 0.10];
/// Colour of elements whose value is NaN, sRGB.
const NAN_SRGB: [f32; 3] = [0.55, 0.55, 0.55];
/// The colour obstacles are drawn in, sRGB: a cool grey, apart from the
/// colour map and from the grey of NaN values.
pub const OBSTACLE_SRGB: [f32; 3] = [0.64, 0.67, 0.72];
/// The opacity of a 2D obstacle's fill, blended in linear light.
pub const OBSTACLE_FILL_OPACITY: f32 = 0.45;
/// Colour of the 2D obstacles' outline, sRGB.
const OBSTACLE_OUTLINE_SRGB: [f32; 3] = [0.25, 0.27, 0.31];
/// Pixels around the bodies' vertices and edge lines' caps, and around the
/// contact shadow's support, that a tile also holds: the 2D lines' coverage
/// quads reach one pixel further (the fringes under one), the multisampled
/// edge of the shadow's support and rounding.
const TILE_MARGIN_PIXELS: f32 = 2.0;

/// The fixed appearance of one run.
#[derive(Clone)]
pub(super) struct Look {
    colouring: Colouring,
    range: [f32; 2],
    legend: Option<Legend>,
    size: (u32, u32),
    globals: Globals,
    /// The 2D ground's line, drawn behind the bodies.
    ground_line: Option<LineInstance>,
    /// Colour (linear, with alpha) and width in pixels of the mesh edges;
    /// `None` when edges are off or faded out entirely.
    edges: Option<([f32; 4], f32)>,
    /// The same for the obstacles' edges.
    obstacle_edges: Option<([f32; 4], f32)>,
    /// The 3D ground's height, under which the contact shadow follows the bodies.
    shadow_ground: Option<f32>,
}

/// How many line instances of each kind [`Look::lines`] made, in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct LineCounts {
    pub ground: u32,
    pub obstacles: u32,
    pub bodies: u32,
}

impl Look {
    /// The look of a run of `frames` (checked, at least one) of `mesh`. The
    /// automatic camera frames all of `frames`, obstacles included, and the
    /// automatic colour range spans all of them; everything else depends on
    /// the first frame only.
    pub fn new(
        settings: &RenderSettings,
        mesh: &RenderMesh,
        frames: &[RenderFrame],
    ) -> Result<Self, RenderError> {
        let (width, height) = (settings.width, settings.height);
        let dimension = mesh.dimension;

        let range = colour_range(&settings.colouring, frames);
        let legend = match settings.colouring {
            Colouring::Scalar { label, .. } if settings.draw_legend => {
                Legend::new(label, range, width, height)
            }
            _ => None,
        };

        let framed = match settings.camera {
            Camera::Auto => frames,
            _ => &frames[..1],
        };
        let bounds =
            Bounds::of_points(framed.iter().flat_map(|f| f.positions.iter())).ok_or_else(|| {
                RenderError::InvalidInput(
                    "no frame has a finite vertex position to frame the camera on".into(),
                )
            })?;
        let free_width = width - legend.as_ref().map_or(0, |l| l.reserved_width());
        let view = camera::resolve(
            &settings.camera,
            &Framing {
                dimension,
                bounds,
                ground: settings.ground_height,
                width,
                height,
                free_width,
            },
        )?;

        let pixel_scale = height as f32 / 720.0;
        let first = &frames[0].positions;
        let first_bodies = &first[..mesh.body_vertices(first.len())];
        let first_bounds = Bounds::of_points(first_bodies).unwrap_or(bounds);
        let globals = base_globals(
            settings,
            dimension,
            &view,
            &bounds,
            &first_bounds,
            pixel_scale,
        );
        let ground_line = match (dimension, settings.ground_height) {
            (2, Some(ground)) => Some(ground_line(&view, ground, pixel_scale)),
            _ => None,
        };
        let edge_width = pixel_scale.max(1.0);
        let edge_alpha = if dimension == 2 { 0.55 } else { 0.40 };
        // Fade edges out when they are so short on screen that they would
        // cover the colours (dense meshes, small images).
        let edge_px = median_edge_pixels(mesh, &frames[0], &view, width, height);
        let edge_alpha = edge_alpha * ((edge_px - 2.0) / 8.0).clamp(0.0, 1.0);
        let with_alpha = |srgb: [f32; 3], alpha: f32| {
            let c = srgb_to_linear3(srgb);
            [c[0], c[1], c[2], alpha]
        };
        let edges = (settings.draw_edges && edge_alpha > 0.0)
            .then_some((with_alpha(EDGE_SRGB, edge_alpha), edge_width));
        // A 2D obstacle's outline is its shape; a 3D one's edges are drawn
        // like the bodies'.
        let obstacle_edges = if dimension == 2 {
            let width = (1.5 * pixel_scale).max(1.0);
            Some((with_alpha(OBSTACLE_OUTLINE_SRGB, 0.9), width))
        } else {
            edges
        };
        let shadow_ground = settings.ground_height.filter(|_| dimension == 3);

        Ok(Self {
            colouring: settings.colouring,
            range,
            legend,
            size: (width, height),
            globals,
            ground_line,
            edges,
            obstacle_edges,
            shadow_ground,
        })
    }

    /// The colour range, fixed for the run.
    pub fn range(&self) -> [f32; 2] {
        self.range
    }

    /// The uniforms of the current frame.
    pub fn globals(&self) -> &Globals {
        &self.globals
    }

    /// The 2D ground's line, if drawn: the backdrop's only line.
    pub fn ground_line(&self) -> Option<LineInstance> {
        self.ground_line
    }

    /// The linear colour of each of `element_count` elements in `frame`.
    pub fn element_colours(
        &self,
        frame: &RenderFrame,
        element_count: usize,
        colours: &mut Vec<[f32; 3]>,
    ) {
        let [lo, hi] = self.range;
        colours.clear();
        match self.colouring {
            Colouring::Flat(colour) => colours.resize(element_count, colour),
            Colouring::Scalar { .. } => colours.extend(frame.element_values.iter().map(|&v| {
                if v.is_nan() {
                    srgb_to_linear3(NAN_SRGB)
                } else {
                    srgb_to_linear3(viridis((v - lo) / (hi - lo)))
                }
            })),
        }
    }

    /// The obstacles' colour (linear, with the 2D fill's opacity).
    pub fn obstacle_colour(&self) -> [f32; 4] {
        let [r, g, b] = srgb_to_linear3(OBSTACLE_SRGB);
        // 3D surfaces are lit and opaque; the 2D fill is neither.
        let lit = self.globals.light[3] > 0.0;
        let alpha = if lit { 1.0 } else { OBSTACLE_FILL_OPACITY };
        [r, g, b, alpha]
    }

    /// The line segments of a frame at `positions`: the ground line, then
    /// the obstacles' edges and the bodies' edges, each when drawn.
    pub fn lines(
        &self,
        mesh: &RenderMesh,
        positions: &[[f32; 3]],
        lines: &mut Vec<LineInstance>,
    ) -> LineCounts {
        lines.clear();
        lines.extend(self.ground_line);
        let ground = lines.len();
        let mut segments = |edges: &[[u32; 2]], style: Option<([f32; 4], f32)>| {
            let Some((colour, width)) = style else {
                return 0;
            };
            lines.extend(edges.iter().map(|&[a, b]| LineInstance {
                start: positions[a as usize],
                end: positions[b as usize],
                colour,
                width,
            }));
            edges.len() as u32
        };
        let obstacles = segments(&mesh.obstacle_edges, self.obstacle_edges);
        let bodies = segments(&mesh.edges, self.edges);
        LineCounts {
            ground: ground as u32,
            obstacles,
            bodies,
        }
    }

    /// The colour a pass starts from: the top of the background.
    pub fn clear_colour(&self) -> wgpu::Color {
        let sky = self.globals.sky_top;
        wgpu::Color {
            r: sky[0] as f64,
            g: sky[1] as f64,
            b: sky[2] as f64,
            a: 1.0,
        }
    }

    /// Whether the background is a gradient, drawn as a layer (a plain one
    /// is the clear colour).
    pub fn has_gradient(&self) -> bool {
        self.globals.sky_top != self.globals.sky_bottom
    }

    /// Moves the 3D contact shadow under the bodies at `positions`.
    pub fn follow_bodies(&mut self, positions: &[[f32; 3]]) {
        if let (Some(ground), Some(bounds)) = (self.shadow_ground, Bounds::of_points(positions)) {
            let (shadow, params) = contact_shadow(&bounds, ground);
            self.globals.shadow = shadow;
            self.globals.shadow_params = params;
        }
    }

    /// The pixels a frame at `positions` (bodies and obstacles) can differ
    /// from the backdrop in, from an even pixel: every vertex with the reach
    /// of the edge lines (their square caps and the pixel the 2D coverage
    /// quads add), and in 3D the contact shadow's support (see
    /// [`Look::shadow_rect`]). `None` when nothing of it is in the image.
    pub fn tile_rect(&self, positions: &[[f32; 3]]) -> Option<PixelRect> {
        let (width, height) = self.size;
        let widest = [
            self.edges,
            self.obstacle_edges,
            self.ground_line.map(|l| (l.colour, l.width)),
        ]
        .into_iter()
        .flatten()
        .map(|(_, width)| width)
        .fold(0.0, f32::max);
        // A square cap reaches half the width along and across the line.
        let reach = widest * std::f32::consts::FRAC_1_SQRT_2 + TILE_MARGIN_PIXELS;
        let view_proj = Matrix4::from(self.globals.view_proj);
        let points = positions.iter().copied();
        let bodies = projected_rect(&view_proj, points, reach, width, height);
        let rect = match (bodies, self.shadow_rect()) {
            (Some(bodies), Some(shadow)) => bodies.union(&shadow),
            (rect, None) | (None, rect) => rect?,
        };
        Some(rect.grown_to_even_pixel())
    }

    /// The pixels the 3D contact shadow can darken: the ground shader
    /// darkens by `a (1 − smoothstep(1 − s, 1 + s, r))` with `r` the
    /// rounded-rectangle distance `(q_x³ + q_z³)^(1/3)`, `q = |x − c| / ρ`
    /// on the ground, which is exactly 0 where `q_x > 1 + s` or
    /// `q_z > 1 + s`. The corners of `[c_x ± ρ_x (1 + s)] × [c_z ± ρ_z
    /// (1 + s)]` on the ground plane, projected, bound it. `None` without a
    /// shadow.
    fn shadow_rect(&self) -> Option<PixelRect> {
        let g = &self.globals;
        let [strength, softness, ..] = g.shadow_params;
        if self.shadow_ground.is_none() || strength <= 0.0 {
            return None;
        }
        let [cx, cz, rx, rz] = g.shadow;
        let reach = 1.0 + softness;
        let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .map(|(sx, sz)| [cx + sx * rx * reach, g.ground[0], cz + sz * rz * reach]);
        let view_proj = Matrix4::from(g.view_proj);
        let (width, height) = self.size;
        projected_rect(&view_proj, corners, TILE_MARGIN_PIXELS, width, height)
    }

    /// The pixels [`Look::draw_overlay`] can change, if any.
    pub fn overlay_footprint(&self) -> Option<PixelRect> {
        let (width, height) = self.size;
        self.legend
            .as_ref()
            .map(|legend| legend.footprint(width, height))
    }

    /// Draws what is drawn on the CPU over the rendered image: the legend.
    pub fn draw_overlay(&self, image: &mut RgbaImage) {
        if let Some(legend) = &self.legend {
            legend.draw(image);
        }
    }
}

/// The fixed colour range: the given one, or the min/max of all finite
/// values over all frames. A constant value `c` gets `[c, c + max(|c|, 1)]`,
/// so it shows as the low end of the map. Without scalars: `[0, 1]`.
fn colour_range(colouring: &Colouring, frames: &[RenderFrame]) -> [f32; 2] {
    match *colouring {
        Colouring::Scalar {
            range: Some(range), ..
        } => range,
        Colouring::Scalar { range: None, .. } => {
            let (lo, hi) = frames
                .iter()
                .flat_map(|f| f.element_values.iter().copied())
                .filter(|v| v.is_finite())
                .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), v| {
                    (lo.min(v), hi.max(v))
                });
            if lo > hi {
                [0.0, 1.0]
            } else if lo == hi {
                [lo, lo + lo.abs().max(1.0)]
            } else {
                [lo, hi]
            }
        }
        Colouring::Flat(_) => [0.0, 1.0],
    }
}

/// The uniforms of a run: camera, light, background and ground, and in 3D
/// the contact shadow under the first frame.
fn base_globals(
    settings: &RenderSettings,
    dimension: usize,
    view: &View,
    bounds: &Bounds,
    first_bounds: &Bounds,
    pixel_scale: f32,
) -> Globals {
    let (width, height) = (settings.width as f32, settings.height as f32);
    let background = settings.background;
    let vec4 = |c: [f32; 3]| [c[0], c[1], c[2], 1.0];
    let linear = |srgb: [f32; 3]| vec4(srgb_to_linear3(srgb));
    let ground = settings.ground_height.unwrap_or(0.0);
    let view_proj: [[f32; 4]; 4] = view.view_proj.into();
    if dimension == 2 {
        let ground_ndc = view.view_proj * Vector4::new(view.target.x, ground, 0.0, 1.0);
        let ground_row = (0.5 - 0.5 * ground_ndc.y / ground_ndc.w) * height;
        Globals {
            view_proj,
            eye: view.eye,
            light: [0.0, 1.0, 0.0, 0.0],
            viewport: [width, height, pixel_scale, 0.0],
            ground: [ground, 1.0, 0.0, 0.0],
            ground_center: [0.0, 0.0, 0.0, ground_row],
            shadow: [0.0; 4],
            shadow_params: [0.0; 4],
            sky_top: vec4(background),
            sky_bottom: vec4(background),
            ground_light: linear([0.86, 0.845, 0.82]),
            ground_dark: linear([0.42, 0.41, 0.39]),
            tile: Globals::WHOLE_IMAGE,
            tile_origin: [0.0; 4],
        }
    } else {
        let light = Vector3::new(-0.45, 1.0, 0.65).normalize();
        let size = first_bounds.radius();
        let (shadow, shadow_params) = contact_shadow(first_bounds, ground);
        let reach = view.distance + bounds.radius();
        Globals {
            view_proj,
            eye: view.eye,
            light: [light.x, light.y, light.z, 1.0],
            // Edges are pulled 0.15% of their distance towards the eye.
            viewport: [width, height, pixel_scale, 0.0015],
            ground: [ground, nice_tile(size), reach, 4.0 * reach],
            ground_center: [view.target.x, view.target.z, 12.0 * reach, 0.0],
            shadow,
            shadow_params,
            sky_top: vec4(background),
            sky_bottom: vec4(background.map(|c| c * 0.80)),
            ground_light: linear([0.85, 0.85, 0.86]),
            ground_dark: linear([0.78, 0.78, 0.80]),
            tile: Globals::WHOLE_IMAGE,
            tile_origin: [0.0; 4],
        }
    }
}

/// A checker tile of 1, 2 or 5 times a power of ten, at most the body's
/// bounding radius (half a unit cube's side for a unit cube).
fn nice_tile(body_radius: f32) -> f32 {
    let target = body_radius.max(1e-6);
    let power = 10f32.powf(target.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * power)
        .find(|&t| t <= target)
        .unwrap_or(power)
}

/// The soft contact shadow under a body with these bounds: centre and radii
/// on the ground, then strength and softness. It fades, widens and blurs as
/// the body rises, so its height above the ground reads at a glance.
fn contact_shadow(bounds: &Bounds, ground: f32) -> ([f32; 4], [f32; 4]) {
    let half = (bounds.max - bounds.min) * 0.5;
    let centre = bounds.center();
    let size = half.x.max(half.z).max(1e-6);
    let height = (bounds.min.y - ground).max(0.0);
    let rise = height / size;
    let strength = 0.42 / (1.0 + 0.5 * rise);
    let softness = (0.18 + 0.25 * rise).min(0.95);
    let grow = 1.12 + 0.1 * rise;
    (
        [
            centre.x,
            centre.z,
            half.x.max(0.05 * size) * grow,
            half.z.max(0.05 * size) * grow,
        ],
        [strength, softness, 0.0, 0.0],
    )
}

/// The 2D ground's surface line across the whole view.
fn ground_line(view: &View, ground: f32, pixel_scale: f32) -> LineInstance {
    let inverse = view
        .view_proj
        .try_inverse()
        .unwrap_or_else(nalgebra::Matrix4::identity);
    let world_x = |ndc_x: f32| {
        let p = inverse * Vector4::new(ndc_x, 0.0, 0.5, 1.0);
        p.x / p.w
    };
    let c = srgb_to_linear3([0.22, 0.22, 0.24]);
    LineInstance {
        start: [world_x(-1.2), ground, 0.0],
        end: [world_x(1.2), ground, 0.0],
        colour: [c[0], c[1], c[2], 1.0],
        width: (2.2 * pixel_scale).max(1.5),
    }
}

/// Median on-screen length of the mesh edges in the first frame, in pixels.
fn median_edge_pixels(
    mesh: &RenderMesh,
    frame: &RenderFrame,
    view: &View,
    width: u32,
    height: u32,
) -> f32 {
    let project = |p: [f32; 3]| {
        let c = view.view_proj * Vector4::new(p[0], p[1], p[2], 1.0);
        nalgebra::Vector2::new(
            c.x / c.w * 0.5 * width as f32,
            c.y / c.w * 0.5 * height as f32,
        )
    };
    let mut lengths: Vec<f32> = mesh
        .edges
        .iter()
        .map(|&[a, b]| {
            (project(frame.positions[a as usize]) - project(frame.positions[b as usize])).norm()
        })
        .filter(|l| l.is_finite())
        .collect();
    if lengths.is_empty() {
        return f32::INFINITY;
    }
    let middle = lengths.len() / 2;
    *lengths.select_nth_unstable_by(middle, f32::total_cmp).1
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(values: &[f32]) -> RenderFrame {
        RenderFrame {
            positions: vec![[0.0; 3]; 3],
            element_values: values.to_vec(),
        }
    }

    #[test]
    fn automatic_range_spans_all_frames_and_skips_non_finite() {
        let scalar = Colouring::Scalar {
            range: None,
            label: "",
        };
        let frames = [
            frame(&[1.0, f32::NAN]),
            frame(&[-2.0, 5.0]),
            frame(&[f32::INFINITY, 0.0]),
        ];
        assert_eq!(colour_range(&scalar, &frames), [-2.0, 5.0]);
        assert_eq!(colour_range(&scalar, &[frame(&[3.0, 3.0])]), [3.0, 6.0]);
        assert_eq!(colour_range(&scalar, &[frame(&[0.0])]), [0.0, 1.0]);
        let fixed = Colouring::Scalar {
            range: Some([0.5, 0.75]),
            label: "",
        };
        assert_eq!(colour_range(&fixed, &frames), [0.5, 0.75]);
    }

    #[test]
    fn tiles_are_round_numbers() {
        assert_eq!(nice_tile(0.87), 0.5);
        assert_eq!(nice_tile(0.3), 0.2);
        assert_eq!(nice_tile(9.0), 5.0);
    }

    #[test]
    fn the_shadow_rect_bounds_the_support_of_the_shadow_on_the_ground() {
        // Clip = world with y up and z ignored: pixel x = (x + 1) 50,
        // y = (1 − y) 50 in a 100 x 100 image; the ground at y = −0.5 is
        // pixel row 75.
        let mut look = Look {
            colouring: Colouring::Flat([0.5; 3]),
            range: [0.0, 1.0],
            legend: None,
            size: (100, 100),
            globals: Globals {
                view_proj: Matrix4::<f32>::identity().into(),
                ..bytemuck::Zeroable::zeroed()
            },
            ground_line: None,
            edges: None,
            obstacle_edges: None,
            shadow_ground: Some(-0.5),
        };
        look.globals.ground[0] = -0.5;
        look.globals.shadow = [0.2, 0.0, 0.2, 0.1];
        look.globals.shadow_params = [0.4, 0.5, 0.0, 0.0];
        // x in 0.2 ± 0.2 * 1.5 = [-0.1, 0.5]: pixels [45, 75], with the margin [43, 77].
        let rect = look.shadow_rect().unwrap();
        assert_eq!((rect.x, rect.x + rect.width), (43, 77));
        assert_eq!((rect.y, rect.y + rect.height), (73, 77));
        // The tile holds the bodies and the shadow, from an even pixel.
        let tile = look.tile_rect(&[[-0.5, 0.5, 0.0]]).unwrap();
        assert_eq!((tile.x, tile.y), (22, 22));
        assert_eq!((tile.x + tile.width, tile.y + tile.height), (77, 77));
        // No strength, no shadow.
        look.globals.shadow_params[0] = 0.0;
        assert_eq!(look.shadow_rect(), None);
        assert_eq!(look.tile_rect(&[[5.0, 5.0, 0.0]]), None);
    }

    #[test]
    fn shadow_fades_with_height() {
        let at = |y: f32| Bounds {
            min: Vector3::new(-1.0, y, -1.0),
            max: Vector3::new(1.0, y + 2.0, 1.0),
        };
        let (_, resting) = contact_shadow(&at(0.0), 0.0);
        let (_, hovering) = contact_shadow(&at(1.0), 0.0);
        let (_, far) = contact_shadow(&at(40.0), 0.0);
        assert!(resting[0] > hovering[0] && hovering[0] > far[0] && far[0] > 0.0);
        assert!(far[0] < 0.1 * resting[0], "{far:?}");
        assert!(hovering[1] > resting[1]);
    }
}
