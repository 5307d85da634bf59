//! [`SceneTiles`]: a 3D frame drawn as a tile around the body and its
//! contact shadow over the run's fixed backdrop.
//!
//! With the camera fixed for the run, a 3D frame differs from the image
//! without the body only where the body is and where its contact shadow
//! darkens the ground. So, as in 2D (`body_tile`), the backdrop — the
//! background and the ground, no body, no shadow — is drawn once, whole,
//! and each frame draws only a pixel rectangle `R` and reads back only
//! that: the frame is the backdrop with the tile as its patch
//! (`renderer`). On llvmpipe a whole 1280x720 frame cost 64 ms, most of
//! it clearing, shading and resolving four samples of every pixel.
//!
//! `R` is the union of
//!
//! - the body's rectangle (`body_tile::body_rect`: every vertex and the
//!   reach of the edge lines), and
//! - the shadow's: the ground shader darkens by `a (1 − smoothstep(1 − s,
//!   1 + s, r))` with `r` the rounded-rectangle distance
//!   `(q_x³ + q_z³)^(1/3)`, `q = |x − c| / ρ` on the ground, which is exactly
//!   0 where `q_x > 1 + s` or `q_z > 1 + s`. The corners of
//!   `[c_x ± ρ_x (1 + s)] × [c_z ± ρ_z (1 + s)]` on the ground plane,
//!   projected, bound it.
//!
//! Outside `R` the frame's pixels are the backdrop's exactly: no body
//! sample, and a shadow factor of exactly 0. `R` starts on an even pixel,
//! so that the 2×2 pixel quads the ground's `fwidth` is taken over are the
//! whole image's. Inside `R` the tile draws everything the whole image
//! would — background, ground with the shadow, surface, edges — with the
//! same samples and depth tests, through the tile transform `to_tile`
//! (`body_tile` writes it out; it moves positions by rounding errors only).
//! A point behind the eye has no pixel, and the tile is then the whole
//! image.

use super::RenderError;
use super::body_tile::projected_rect;
use super::gpu::Gpu;
use super::gpu_resources::Globals;
use super::layers::{Layers, record_layers};
use super::pixel_rect::{Patch, PixelRect};
use super::render_targets::RenderTargets;
use super::tile_slot::TileSlot;
use nalgebra::Matrix4;

/// Pixels around the shadow's support that the tile also holds (the
/// multisampled edge of the support and rounding).
const SHADOW_MARGIN_PIXELS: f32 = 2.0;

/// The pixels the contact shadow of `globals` can darken in a `width ×
/// height` image (see the module documentation); `None` without one.
pub(super) fn shadow_rect(globals: &Globals, width: u32, height: u32) -> Option<PixelRect> {
    let [strength, softness, ..] = globals.shadow_params;
    if strength <= 0.0 {
        return None;
    }
    let [cx, cz, rx, rz] = globals.shadow;
    let ground = globals.ground[0];
    let reach = 1.0 + softness;
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .map(|(sx, sz)| [cx + sx * rx * reach, ground, cz + sz * rz * reach]);
    projected_rect(
        &Matrix4::from(globals.view_proj),
        corners,
        SHADOW_MARGIN_PIXELS,
        width,
        height,
    )
}

/// The tile of a frame whose body covers `body` and whose shadow covers
/// `shadow`: their union, moved to start on an even pixel.
pub(super) fn scene_rect(body: Option<PixelRect>, shadow: Option<PixelRect>) -> Option<PixelRect> {
    let rect = match (body, shadow) {
        (Some(body), Some(shadow)) => body.union(&shadow),
        (rect, None) | (None, rect) => rect?,
    };
    let (x, y) = (rect.x & !1, rect.y & !1);
    Some(PixelRect::new(
        x,
        y,
        rect.width + (rect.x - x),
        rect.height + (rect.y - y),
    ))
}

/// The tile target a 3D run's frames are drawn in, grown as needed.
pub(super) struct SceneTiles {
    slot: TileSlot<RenderTargets>,
}

impl SceneTiles {
    /// Tiles for frames of `size` pixels.
    pub fn new(size: (u32, u32)) -> Self {
        SceneTiles {
            slot: TileSlot::new(size),
        }
    }

    /// Draws `layers` at `rect` with `globals` (the frame's, for the whole
    /// image), cleared to `clear`, copies the tile to the readback buffer in
    /// the same submission and waits; returns `rect`, or `None` when nothing
    /// of the frame differs from the backdrop.
    pub fn draw(
        &mut self,
        gpu: &Gpu,
        layers: &Layers<'_>,
        globals: &Globals,
        clear: wgpu::Color,
        rect: Option<PixelRect>,
    ) -> Result<Option<PixelRect>, RenderError> {
        let Some(rect) = rect else {
            return Ok(None);
        };
        let transform = self.slot.hold(gpu, rect, |gpu, capacity| {
            RenderTargets::new(gpu, capacity, gpu.sample_count, true, "3D tile")
        })?;
        let target = self.slot.target();
        let mut globals = *globals;
        (globals.tile, globals.tile_origin) = transform;
        let r = layers.resources;
        gpu.queue
            .write_buffer(&r.uniforms, 0, bytemuck::bytes_of(&globals));

        let device = &gpu.device;
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out_of_memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("3D tile encoder"),
        });
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("3D tile pass"),
                color_attachments: &[Some(target.colour_attachment(clear))],
                depth_stencil_attachment: target.depth_attachment(),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            // Only the tile's rectangle is read back.
            pass.set_scissor_rect(0, 0, rect.width, rect.height);
            record_layers(&mut pass, layers);
        }
        self.slot.submit_with_readback(
            gpu,
            encoder,
            &target.resolved,
            rect,
            [out_of_memory, validation],
            "drawing a 3D tile",
        )?;
        Ok(Some(rect))
    }

    /// The tile just drawn at `rect`, copied to the readback buffer by the
    /// same submission (`None` when nothing was drawn).
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

    #[test]
    fn the_scene_rect_holds_body_and_shadow_from_an_even_pixel() {
        let body = PixelRect::new(101, 50, 20, 30);
        let shadow = PixelRect::new(90, 77, 60, 10);
        assert_eq!(
            scene_rect(Some(body), Some(shadow)),
            Some(PixelRect::new(90, 50, 60, 37))
        );
        // Odd origins move down by one pixel, keeping the far edges.
        assert_eq!(
            scene_rect(Some(body), None),
            Some(PixelRect::new(100, 50, 21, 30))
        );
        assert_eq!(
            scene_rect(None, Some(PixelRect::new(3, 7, 5, 5))),
            Some(PixelRect::new(2, 6, 6, 6))
        );
        assert_eq!(scene_rect(None, None), None);
    }

    #[test]
    fn the_shadow_rect_bounds_the_support_of_the_shadow_on_the_ground() {
        // Clip = world with y up and z ignored: pixel x = (x + 1) 50,
        // y = (1 − y) 50 in a 100 x 100 image; the ground at y = −0.5 is
        // pixel row 75.
        let mut globals = Globals {
            view_proj: Matrix4::<f32>::identity().into(),
            ..bytemuck::Zeroable::zeroed()
        };
        globals.ground[0] = -0.5;
        globals.shadow = [0.2, 0.0, 0.2, 0.1];
        globals.shadow_params = [0.4, 0.5, 0.0, 0.0];
        // x in 0.2 ± 0.2 * 1.5 = [-0.1, 0.5]: pixels [45, 75], with the margin [43, 77].
        let rect = shadow_rect(&globals, 100, 100).unwrap();
        assert_eq!((rect.x, rect.x + rect.width), (43, 77));
        assert_eq!((rect.y, rect.y + rect.height), (73, 77));
        // No strength, no shadow.
        globals.shadow_params[0] = 0.0;
        assert_eq!(shadow_rect(&globals, 100, 100), None);
    }
}
