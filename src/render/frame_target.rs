//! [`FrameTarget`]: where a run's frames are drawn — one tile of the image
//! at a time — and the ring of buffers they are read back through.
//!
//! With the camera fixed for the run, a frame differs from the image
//! without the bodies (the backdrop) only around them (and in 3D their
//! contact shadow). So a frame draws only that pixel rectangle
//! `R = [x0, x1) × [y0, y1)` and reads back only that, and the image is the
//! backdrop with `R` pasted in (`renderer`). On llvmpipe a whole 1280x720
//! 3D frame cost 64 ms, most of it clearing, shading and resolving four
//! samples of every pixel. The backdrop itself is drawn the same way, in
//! strips of rows.
//!
//! **The tile.** `R` is drawn at the top left of a target of capacity
//! `Wc × Hc ≥ |R|` (grown in steps of 64 pixels per side, never beyond the
//! image, so a run makes a handful of targets), in one pass scissored to
//! `R`. The pass draws everything the whole image shows there, with the
//! same samples and depth tests, through the tile transform: a whole-image
//! clip position `c` (pixel `p = ((c_x / c_w + 1) W / 2, (1 − c_y / c_w) H
//! / 2)` in a `W × H` image) goes to `c' = (s ∘ c_xy + o c_w, c_z, c_w)` with
//!
//! ```text
//! s = (W / Wc, H / Hc),   o = ((W − 2 x0) / Wc − 1, 1 − (H − 2 y0) / Hc),
//! ```
//!
//! which is pixel `p − (x0, y0)` of the target (`to_tile` in
//! `shaders/globals.wgsl`; the whole image uses `s = 1, o = 0`, which leaves
//! every position bit for bit unchanged). The extra multiply-add moves
//! positions by rounding errors, so a sample lying exactly on an edge may
//! fall the other way, in a few pixels. `R` starts on an even pixel, so
//! that the 2×2 pixel quads derivatives are taken over (the 3D ground's
//! `fwidth`, the 2D coverage) are the whole image's.
//!
//! **The readback.** The copy of the tile into a staging buffer goes in the
//! tile's own submission, and the buffer's mapping is started at once; the
//! caller collects it later ([`FrameTarget::receive`]), so that frame `N`
//! is read while frame `N + 1` is drawn. The staging buffers form a ring of
//! [`FRAMES_IN_FLIGHT`]; a buffer is drawn into again only once received.
//! Rows are padded to `COPY_BYTES_PER_ROW_ALIGNMENT` in the buffer.

use super::RenderError;
use super::gpu::{Gpu, check_scope};
use super::pipelines::{COLOR_FORMAT, DEPTH_FORMAT, Globals};
use super::pixel_rect::{Patch, PixelRect};
use std::sync::mpsc;

/// How many frames can be drawn and not yet read back: the staging
/// buffers of the ring.
pub const FRAMES_IN_FLIGHT: usize = 2;

/// Tile targets grow in steps of this many pixels per side.
const CAPACITY_STEP: u32 = 64;

/// The tile target and the staging ring of one renderer.
pub(super) struct FrameTarget {
    /// The whole image's size.
    size: (u32, u32),
    samples: u32,
    depth: bool,
    textures: Option<Textures>,
    ring: [Staging; FRAMES_IN_FLIGHT],
    /// The ring slot the next tile is read through.
    next: usize,
}

/// The tile's textures: `samples`-sample colour (and depth) drawn into,
/// resolved into one sample per pixel, the texture copied out.
struct Textures {
    capacity: (u32, u32),
    multisampled: Option<wgpu::TextureView>,
    resolved: wgpu::Texture,
    resolved_view: wgpu::TextureView,
    depth: Option<wgpu::TextureView>,
}

/// One staging buffer of the ring and the tile on its way into it.
#[derive(Default)]
struct Staging {
    buffer: Option<wgpu::Buffer>,
    pending: Option<Pending>,
}

struct Pending {
    rect: PixelRect,
    submission: wgpu::SubmissionIndex,
    mapped: mpsc::Receiver<Result<(), wgpu::BufferAsyncError>>,
}

impl FrameTarget {
    /// A target for tiles of a `size` image with `samples` samples per
    /// pixel and, when `depth`, a depth target; no texture is made yet.
    pub fn new(size: (u32, u32), samples: u32, depth: bool) -> Self {
        FrameTarget {
            size,
            samples,
            depth,
            textures: None,
            ring: Default::default(),
            next: 0,
        }
    }

    /// Drops the textures: the next tile makes them at its own size (after
    /// the backdrop's strips, which are as wide as the image).
    pub fn shrink(&mut self) {
        self.textures = None;
    }

    /// The capacity of the tile textures, if they are made.
    pub fn capacity(&self) -> Option<(u32, u32)> {
        self.textures.as_ref().map(|t| t.capacity)
    }

    /// Draws the tile `rect`: uploads `globals` with the tile's transform
    /// into `uniforms`, records the pass with `record` (scissored to the
    /// tile, cleared to `clear`), copies the tile into the ring's next
    /// buffer in the same submission and starts mapping it. Returns the
    /// ring slot to [`FrameTarget::receive`] it from. Fails when that slot
    /// still holds a tile not received.
    pub fn draw(
        &mut self,
        gpu: &Gpu,
        uniforms: &wgpu::Buffer,
        globals: &Globals,
        clear: wgpu::Color,
        rect: PixelRect,
        record: impl FnOnce(&mut wgpu::RenderPass<'_>),
    ) -> Result<usize, RenderError> {
        let slot = self.next;
        if self.ring[slot].pending.is_some() {
            return Err(RenderError::InvalidInput(format!(
                "more than {FRAMES_IN_FLIGHT} frames drawn and not read back"
            )));
        }
        let device = &gpu.device;
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out_of_memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        self.hold(gpu, rect);
        let textures = self.textures.as_ref().expect("just made");
        let staging = &mut self.ring[slot];
        let row_bytes = padded_row_bytes(rect.width);
        let bytes = u64::from(row_bytes) * u64::from(rect.height);
        if staging.buffer.as_ref().is_none_or(|b| b.size() < bytes) {
            let (width, height) = textures.capacity;
            staging.buffer = Some(device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("tile staging buffer"),
                size: u64::from(padded_row_bytes(width)) * u64::from(height),
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        let buffer = staging.buffer.as_ref().expect("just made");

        let mut globals = *globals;
        (globals.tile, globals.tile_origin) = tile_transform(rect, textures.capacity, self.size);
        gpu.queue
            .write_buffer(uniforms, 0, bytemuck::bytes_of(&globals));
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("tile encoder"),
        });
        {
            let (view, resolve_target, store) = match &textures.multisampled {
                Some(samples) => (
                    samples,
                    Some(&textures.resolved_view),
                    wgpu::StoreOp::Discard,
                ),
                None => (&textures.resolved_view, None, wgpu::StoreOp::Store),
            };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("tile pass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(clear),
                        store,
                    },
                })],
                depth_stencil_attachment: textures.depth.as_ref().map(|view| {
                    wgpu::RenderPassDepthStencilAttachment {
                        view,
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(1.0),
                            store: wgpu::StoreOp::Discard,
                        }),
                        stencil_ops: None,
                    }
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            // Only the tile's rectangle is read back: the rest of the
            // target is never shaded.
            pass.set_scissor_rect(0, 0, rect.width, rect.height);
            record(&mut pass);
        }
        encoder.copy_texture_to_buffer(
            textures.resolved.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row_bytes),
                    rows_per_image: Some(rect.height),
                },
            },
            wgpu::Extent3d {
                width: rect.width,
                height: rect.height,
                depth_or_array_layers: 1,
            },
        );
        let submission = gpu.queue.submit([encoder.finish()]);
        check_scope(out_of_memory, "drawing a frame")?;
        check_scope(validation, "drawing a frame")?;
        let (sender, mapped) = mpsc::channel();
        buffer.map_async(wgpu::MapMode::Read, ..bytes, move |result| {
            let _ = sender.send(result);
        });
        staging.pending = Some(Pending {
            rect,
            submission,
            mapped,
        });
        self.next = (slot + 1) % FRAMES_IN_FLIGHT;
        Ok(slot)
    }

    /// The pixels of the tile drawn through ring slot `slot`: waits for its
    /// submission and mapping, and copies its rows without their padding.
    pub fn receive(&mut self, gpu: &Gpu, slot: usize) -> Result<Patch, RenderError> {
        let staging = &mut self.ring[slot];
        let pending = staging.pending.take().ok_or_else(|| {
            RenderError::InvalidInput(format!("no frame is on its way through slot {slot}"))
        })?;
        let buffer = staging.buffer.as_ref().expect("drawn through it");
        let failed = |message: String| RenderError::Gpu {
            during: "reading a frame back",
            message,
        };
        gpu.device
            .poll(wgpu::PollType::Wait {
                submission_index: Some(pending.submission),
                timeout: None,
            })
            .map_err(|e| failed(e.to_string()))?;
        pending
            .mapped
            .recv()
            .map_err(|_| failed("the map callback never ran".into()))?
            .map_err(|e| failed(e.to_string()))?;
        let rect = pending.rect;
        let row_bytes = padded_row_bytes(rect.width) as usize;
        let mut pixels = Vec::with_capacity((rect.width * rect.height * 4) as usize);
        {
            let bytes = row_bytes as u64 * u64::from(rect.height);
            let mapped = buffer
                .get_mapped_range(..bytes)
                .map_err(|e| failed(e.to_string()))?;
            for row in mapped.chunks_exact(row_bytes) {
                pixels.extend_from_slice(&row[..rect.width as usize * 4]);
            }
        }
        buffer.unmap();
        Ok(Patch { rect, pixels })
    }

    /// Makes the textures hold a tile at `rect`: keeps them, or makes larger
    /// ones when they cannot.
    fn hold(&mut self, gpu: &Gpu, rect: PixelRect) {
        let had = self.capacity().unwrap_or((0, 0));
        if had.0 >= rect.width && had.1 >= rect.height {
            return;
        }
        let grown = |need: u32, had: u32, size: u32| {
            need.max(had).next_multiple_of(CAPACITY_STEP).min(size)
        };
        let capacity = (
            grown(rect.width, had.0, self.size.0),
            grown(rect.height, had.1, self.size.1),
        );
        let texture = |what: &str, format, sample_count, usage| {
            gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(what),
                size: wgpu::Extent3d {
                    width: capacity.0,
                    height: capacity.1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        // The targets of `samples` samples are drawn into, never stored.
        let samples = self.samples;
        let attachment = |what: &str, format| {
            texture(
                what,
                format,
                samples,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            )
            .create_view(&Default::default())
        };
        let resolved = texture(
            "tile colour",
            COLOR_FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        // The old textures go first: both need not fit at once.
        self.textures = None;
        self.textures = Some(Textures {
            capacity,
            multisampled: (samples > 1).then(|| attachment("tile samples", COLOR_FORMAT)),
            resolved_view: resolved.create_view(&Default::default()),
            resolved,
            depth: self.depth.then(|| attachment("tile depth", DEPTH_FORMAT)),
        });
    }
}

/// Bytes per row of an RGBA8 image `width` pixels wide copied to a buffer:
/// rows start at multiples of `COPY_BYTES_PER_ROW_ALIGNMENT`.
fn padded_row_bytes(width: u32) -> u32 {
    (width * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
}

/// `tile` and `tile_origin` of the uniforms for drawing `rect` of an image
/// of `size` into a target of `capacity` pixels (see the module
/// documentation).
fn tile_transform(rect: PixelRect, capacity: (u32, u32), size: (u32, u32)) -> ([f32; 4], [f32; 4]) {
    let (w, h) = (f64::from(size.0), f64::from(size.1));
    let (wc, hc) = (f64::from(capacity.0), f64::from(capacity.1));
    let (x0, y0) = (f64::from(rect.x), f64::from(rect.y));
    let tile = [
        w / wc,
        h / hc,
        (w - 2.0 * x0) / wc - 1.0,
        1.0 - (h - 2.0 * y0) / hc,
    ];
    (tile.map(|c| c as f32), [x0 as f32, y0 as f32, 0.0, 0.0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector4;

    #[test]
    fn the_tile_transform_moves_every_pixel_by_the_tile_origin() {
        let rect = PixelRect::new(517, 203, 90, 70);
        let (width, height) = (1280, 720);
        let capacity = (128, 128);
        let (tile, origin) = tile_transform(rect, capacity, (width, height));
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
            let tx = (moved.x / moved.w + 1.0) * 0.5 * capacity.0 as f32;
            let ty = (1.0 - moved.y / moved.w) * 0.5 * capacity.1 as f32;
            assert!((tx - (px - 517.0)).abs() < 1e-3, "x: {tx} for {px}");
            assert!((ty - (py - 203.0)).abs() < 1e-3, "y: {ty} for {py}");
        }
        // The whole image as its own tile is the identity.
        let whole = PixelRect::new(0, 0, width, height);
        let (tile, _) = tile_transform(whole, (width, height), (width, height));
        assert_eq!(tile, Globals::WHOLE_IMAGE);
    }
}
