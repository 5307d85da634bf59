//! [`BodyTiles`]: a 2D frame drawn as a small tile around the body over the
//! run's fixed backdrop.
//!
//! In 2D everything but the body — background, ground, ground line — is the
//! same in every frame, and the body often covers a small part of the image.
//! On a software rasteriser most of a frame's time went to clearing and
//! resolving the whole multisampled image (7 ms at 1280x720 on llvmpipe,
//! of the default scene's 9 ms per frame). So the backdrop is drawn once,
//! whole, and each frame draws only the pixel rectangle
//! `R = [x0, x1) × [y0, y1)` around the body into a tile target of capacity
//! `Wc × Hc ≥ |R|` (grown as needed, by 64 pixels), with one sample per
//! pixel (`body_coverage` anti-aliases in the shaders), and reads back only
//! that: the frame is the backdrop with the tile as its patch
//! (`renderer`).
//!
//! The tile shows the same pixels as the whole image: a whole-image clip
//! position `c` (pixel `p = ((c_x / c_w + 1) W / 2, (1 − c_y / c_w) H / 2)`
//! in a `W × H` image) goes to `c' = (s ∘ c_xy + o c_w, c_z, c_w)` with
//!
//! ```text
//! s = (W / Wc, H / Hc),   o = ((W − 2 x0) / Wc − 1, 1 − (H − 2 y0) / Hc),
//! ```
//!
//! which is pixel `p − (x0, y0)` of the tile target (`to_tile` in
//! `shaders/globals.wgsl`; the whole image uses `s = 1, o = 0`, which leaves
//! every position bit for bit unchanged). The tile's pass, scissored to `R`
//! (the only part read back), starts with the backdrop's own pixels, read
//! from the backdrop texture by a shader (`shaders/backdrop.wgsl`), so the
//! body's anti-aliased edges blend with the same background. A texture to
//! texture copy would be simpler but costs more on wgpu's GL backend: it
//! copies with `glCopyTexSubImage2D`, which llvmpipe does as a blit, a
//! round trip through its rasteriser of its own before the tile's. The
//! extra multiply-add moves positions by rounding errors, so an edge pixel's
//! coverage may round to the next level, in a few pixels. `R` holds every
//! vertex and every edge line's square caps with a margin of two pixels.

use super::RenderError;
use super::gpu::{Gpu, check_scope};
use super::gpu_resources::{COLOR_FORMAT, Globals, GpuResources};
use super::pixel_rect::{Patch, PixelRect};
use super::tile_slot::TileSlot;
#[cfg(test)]
use super::tile_slot::tile_transform;
use nalgebra::{Matrix4, Vector4};

/// Pixels around the body's vertices and edge lines' caps that the tile
/// also holds: the lines' coverage quads reach one pixel further (and the
/// fringes under one pixel), so two leave room for rounding.
const MARGIN_PIXELS: f32 = 2.0;

/// The pixels a frame's body can touch in a `width × height` image: every
/// vertex at `positions`, projected by `view_proj`, with the reach of an
/// edge line `line_width` pixels wide (its square caps and the pixel its
/// coverage quad adds) and a margin. `None` when the body is entirely
/// outside the image; the whole image when a position does not project to
/// a finite pixel in front of the eye.
pub(super) fn body_rect(
    view_proj: &Matrix4<f32>,
    positions: &[[f32; 3]],
    line_width: f32,
    width: u32,
    height: u32,
) -> Option<PixelRect> {
    // A square cap reaches half the width along and across the line.
    let reach = line_width * std::f32::consts::FRAC_1_SQRT_2 + MARGIN_PIXELS;
    projected_rect(view_proj, positions.iter().copied(), reach, width, height)
}

/// The pixel rectangle holding the projections of `points` by `view_proj`,
/// `reach` pixels further all round, clamped to the `width × height` image:
/// `None` when it is entirely outside, the whole image when a point does not
/// project to a finite pixel in front of the eye (clip `w > 0`).
pub(super) fn projected_rect(
    view_proj: &Matrix4<f32>,
    points: impl IntoIterator<Item = [f32; 3]>,
    reach: f32,
    width: u32,
    height: u32,
) -> Option<PixelRect> {
    let (w, h) = (width as f32, height as f32);
    let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
    for point in points {
        let clip = view_proj * Vector4::new(point[0], point[1], point[2], 1.0);
        let p = [
            (clip.x / clip.w + 1.0) * 0.5 * w,
            (1.0 - clip.y / clip.w) * 0.5 * h,
        ];
        if !(clip.w > 0.0 && p.iter().all(|c| c.is_finite())) {
            return Some(PixelRect::new(0, 0, width, height));
        }
        for axis in 0..2 {
            lo[axis] = lo[axis].min(p[axis] - reach);
            hi[axis] = hi[axis].max(p[axis] + reach);
        }
    }
    if lo[0] > hi[0] {
        return None;
    }
    let clamp = |c: f32, size: u32| c.clamp(0.0, size as f32) as u32;
    let (x0, x1) = (clamp(lo[0].floor(), width), clamp(hi[0].ceil(), width));
    let (y0, y1) = (clamp(lo[1].floor(), height), clamp(hi[1].ceil(), height));
    (x1 > x0 && y1 > y0).then_some(PixelRect::new(x0, y0, x1 - x0, y1 - y0))
}

/// The tile target, one sample per pixel.
struct TileTarget {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
}

impl TileTarget {
    fn new(gpu: &Gpu, capacity: (u32, u32)) -> Self {
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("tile target"),
            size: wgpu::Extent3d {
                width: capacity.0,
                height: capacity.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: COLOR_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        TileTarget { texture, view }
    }
}

/// What a tile is drawn with, besides the tile target: the renderer's
/// buffers, already filled for the frame.
pub(super) struct TileInputs<'a> {
    pub resources: &'a GpuResources,
    pub globals: &'a Globals,
    /// The number of body vertices (three per triangle).
    pub body_vertices: u32,
    pub fringes: u32,
    /// The instance range of the body's edge lines.
    pub body_lines: std::ops::Range<u32>,
}

/// The fixed backdrop of a 2D run, on the GPU, and the tile target its
/// frames are drawn in.
pub(super) struct BodyTiles {
    /// The backdrop texture, which each tile starts from and the fringes'
    /// inner halves read.
    backdrop_bind_group: wgpu::BindGroup,
    slot: TileSlot<TileTarget>,
}

impl BodyTiles {
    /// Tiles over the backdrop drawn in `backdrop` (the whole image without
    /// the body, single-sampled), which each tile starts from. The texture
    /// is sampled where it was drawn: no copy of it is made.
    pub fn new(
        gpu: &Gpu,
        resources: &GpuResources,
        backdrop: &wgpu::Texture,
    ) -> Result<Self, RenderError> {
        let Some(tile) = &resources.tile else {
            return Err(RenderError::Gpu {
                during: "preparing the 2D backdrop",
                message: "the renderer has no tile pipelines (3D mesh)".into(),
            });
        };
        let device = &gpu.device;
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let view = backdrop.create_view(&Default::default());
        let backdrop_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("backdrop bind group"),
            layout: &tile.backdrop_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&view),
            }],
        });
        check_scope(validation, "preparing the 2D backdrop")?;
        Ok(BodyTiles {
            backdrop_bind_group,
            slot: TileSlot::new((backdrop.width(), backdrop.height())),
        })
    }

    /// Draws the body's tile and waits for it; returns the tile's place, or
    /// `None` when the body is outside the image (the frame is the backdrop).
    pub fn draw(
        &mut self,
        gpu: &Gpu,
        inputs: &TileInputs<'_>,
        rect: Option<PixelRect>,
    ) -> Result<Option<PixelRect>, RenderError> {
        let Some(rect) = rect else {
            return Ok(None);
        };
        let transform = self.slot.hold(gpu, rect, TileTarget::new)?;
        let target = self.slot.target();
        let r = inputs.resources;
        let tile = r.tile.as_ref().expect("checked in BodyTiles::new");

        let mut globals = *inputs.globals;
        (globals.tile, globals.tile_origin) = transform;
        gpu.queue
            .write_buffer(&r.uniforms, 0, bytemuck::bytes_of(&globals));

        let device = &gpu.device;
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("tile encoder"),
        });
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("tile pass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target.view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        // The backdrop covers the scissored rectangle: the
                        // clear colour never shows in what is read back.
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            // Only the tile's rectangle is read back: the rest of the
            // target is never shaded.
            pass.set_scissor_rect(0, 0, rect.width, rect.height);
            pass.set_bind_group(0, &r.bind_group, &[]);
            pass.set_bind_group(1, &self.backdrop_bind_group, &[]);
            pass.set_pipeline(&tile.backdrop);
            pass.draw(0..3, 0..1);
            if inputs.body_vertices > 0 {
                pass.set_pipeline(&tile.surface);
                pass.set_vertex_buffer(0, tile.body_vertices.slice(..));
                pass.draw(0..inputs.body_vertices, 0..1);
            }
            if inputs.fringes > 0 {
                pass.set_pipeline(&tile.fringe);
                pass.set_vertex_buffer(0, tile.fringe_instances.slice(..));
                pass.draw(0..6, 0..inputs.fringes);
            }
            if !inputs.body_lines.is_empty() {
                pass.set_pipeline(&tile.line);
                pass.set_vertex_buffer(0, r.line_instances.slice(..));
                pass.draw(0..6, inputs.body_lines.clone());
            }
        }
        self.slot.submit_with_readback(
            gpu,
            encoder,
            &target.texture,
            rect,
            [validation],
            "drawing a tile",
        )?;
        Ok(Some(rect))
    }

    /// The tile just drawn at `rect` (none when the body is outside the
    /// image), copied to the readback buffer by the same submission.
    pub fn read_back(
        &self,
        gpu: &Gpu,
        rect: Option<PixelRect>,
    ) -> Result<Option<Patch>, RenderError> {
        self.slot.read_back(gpu, rect)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pixel of a whole-image clip position `c` in an image of `size`.
    fn pixel_of(c: Vector4<f32>, size: (f32, f32)) -> [f32; 2] {
        [
            (c.x / c.w + 1.0) * 0.5 * size.0,
            (1.0 - c.y / c.w) * 0.5 * size.1,
        ]
    }

    #[test]
    fn the_tile_transform_moves_every_pixel_by_the_tile_origin() {
        let rect = PixelRect {
            x: 517,
            y: 203,
            width: 90,
            height: 70,
        };
        let (width, height) = (1280, 720);
        let capacity = (128, 128);
        let (tile, origin) = tile_transform(rect, capacity, width, height);
        assert_eq!(origin, [517.0, 203.0, 0.0, 0.0]);
        for (px, py, w) in [
            (517.0, 203.0, 1.0),
            (560.25, 240.5, 2.5),
            (606.0, 272.75, 0.5),
        ] {
            // The whole-image clip position of pixel (px, py), at clip w.
            let clip = Vector4::new(
                (px / width as f32 * 2.0 - 1.0) * w,
                (1.0 - py / height as f32 * 2.0) * w,
                0.3,
                w,
            );
            let moved = Vector4::new(
                clip.x * tile[0] + tile[2] * clip.w,
                clip.y * tile[1] + tile[3] * clip.w,
                clip.z,
                clip.w,
            );
            let [tx, ty] = pixel_of(moved, (capacity.0 as f32, capacity.1 as f32));
            assert!((tx - (px - 517.0)).abs() < 1e-3, "x: {tx} for {px}");
            assert!((ty - (py - 203.0)).abs() < 1e-3, "y: {ty} for {py}");
        }
        // The whole image as its own tile is the identity.
        let whole = PixelRect {
            x: 0,
            y: 0,
            width,
            height,
        };
        let (tile, _) = tile_transform(whole, (width, height), width, height);
        assert_eq!(tile, Globals::WHOLE_IMAGE);
    }

    #[test]
    fn the_body_rect_holds_vertices_and_line_caps_with_a_margin() {
        // Clip = world: pixel x = (x + 1) 50, y = (1 - y) 25 in a 100 x 50 image.
        let identity = Matrix4::identity();
        let body = [[-0.5, 0.0, 0.0], [0.0, 0.5, 0.0], [0.25, -0.25, 0.0]];
        // Vertices span pixels x in [25, 62.5], y in [12.5, 31.25].
        let rect = body_rect(&identity, &body, 0.0, 100, 50).unwrap();
        assert_eq!(rect, PixelRect::new(23, 10, 65 - 23, 34 - 10));
        // Lines 4 pixels wide reach 2 sqrt 2 further, plus the margin.
        let rect = body_rect(&identity, &body, 4.0, 100, 50).unwrap();
        assert_eq!((rect.x, rect.y), (20, 7));
        assert_eq!((rect.x + rect.width, rect.y + rect.height), (68, 37));
        // Clamped to the image, and nothing when all of it is outside.
        let wide = [[-3.0, -3.0, 0.0], [0.0, 0.0, 0.0]];
        let rect = body_rect(&identity, &wide, 0.0, 100, 50).unwrap();
        assert_eq!((rect.x, rect.y, rect.width, rect.height), (0, 23, 52, 27));
        let outside = [[5.0, 5.0, 0.0], [6.0, 7.0, 0.0]];
        assert_eq!(body_rect(&identity, &outside, 0.0, 100, 50), None);
        assert_eq!(body_rect(&identity, &[], 0.0, 100, 50), None);
        // A position that projects nowhere gives the whole image.
        let broken = [[f32::NAN, 0.0, 0.0], [0.0, 0.0, 0.0]];
        let rect = body_rect(&identity, &broken, 0.0, 100, 50).unwrap();
        assert_eq!((rect.x, rect.y, rect.width, rect.height), (0, 0, 100, 50));
        // So does one behind the eye: with clip w = z, a point at z = −1
        // would project, mirrored, to a finite pixel.
        let mut w_is_z = identity;
        w_is_z[(3, 3)] = 0.0;
        w_is_z[(3, 2)] = 1.0;
        let in_front = [[0.2, 0.1, 1.0], [0.3, 0.2, 1.0]];
        assert!(body_rect(&w_is_z, &in_front, 0.0, 100, 50).unwrap().width < 100);
        let behind = [[0.2, 0.1, 1.0], [0.3, 0.2, -1.0]];
        let rect = body_rect(&w_is_z, &behind, 0.0, 100, 50).unwrap();
        assert_eq!((rect.x, rect.y, rect.width, rect.height), (0, 0, 100, 50));
    }
}
