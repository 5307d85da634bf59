//! [`TileSlot`]: the target a run's tiles are drawn in, 2D (`body_tile`)
//! or 3D (`scene_tile`), grown as the tiles need, and the buffer each tile
//! is read back through.
//!
//! A tile of `w × h` pixels is drawn at the top left of a target of
//! capacity `Wc × Hc ≥ w × h`. The capacity grows in steps of 64 pixels per
//! side, never beyond the image, and never shrinks, so a run makes a
//! handful of targets at most. The copy of the tile to the readback buffer
//! goes in the tile's own submission: one round trip through the driver
//! per frame.

use super::RenderError;
use super::gpu::{Gpu, check_scope, wait};
use super::gpu_resources::{padded_row_bytes, readback_buffer};
use super::pixel_rect::{Patch, PixelRect};
use super::readback::{encode_texture_copy, read_buffer};

/// Tile targets grow in steps of this many pixels per side.
const CAPACITY_STEP: u32 = 64;

/// The targets `T` of tiles of a `size` image, and their readback buffer.
pub(super) struct TileSlot<T> {
    /// The image size.
    size: (u32, u32),
    grown: Option<Grown<T>>,
}

/// The current targets, their capacity and readback buffer.
struct Grown<T> {
    capacity: (u32, u32),
    target: T,
    readback: wgpu::Buffer,
}

impl<T> TileSlot<T> {
    /// No target yet, for tiles of an image of `size` pixels.
    pub fn new(size: (u32, u32)) -> Self {
        TileSlot { size, grown: None }
    }

    /// Makes the target hold a tile at `rect`: keeps the current one, or
    /// makes a larger one with `make` (given its capacity) when the current
    /// one cannot hold `rect`. Returns the tile transform that draws `rect`
    /// into it (`tile` and `tile_origin` of the uniforms, see `body_tile`).
    pub fn hold(
        &mut self,
        gpu: &Gpu,
        rect: PixelRect,
        make: impl FnOnce(&Gpu, (u32, u32)) -> T,
    ) -> Result<([f32; 4], [f32; 4]), RenderError> {
        let had = self.grown.as_ref().map_or((0, 0), |g| g.capacity);
        if had.0 < rect.width || had.1 < rect.height {
            let grown = |need: u32, had: u32, size: u32| {
                need.max(had).next_multiple_of(CAPACITY_STEP).min(size)
            };
            let capacity = (
                grown(rect.width, had.0, self.size.0),
                grown(rect.height, had.1, self.size.1),
            );
            let validation = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
            let out_of_memory = gpu.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
            let readback = readback_buffer(&gpu.device, "tile readback buffer", capacity);
            self.grown = Some(Grown {
                capacity,
                target: make(gpu, capacity),
                readback,
            });
            check_scope(out_of_memory, "creating a tile target")?;
            check_scope(validation, "creating a tile target")?;
        }
        let capacity = self.grown.as_ref().map_or(had, |g| g.capacity);
        Ok(tile_transform(rect, capacity, self.size.0, self.size.1))
    }

    /// The target made by the last [`TileSlot::hold`].
    pub fn target(&self) -> &T {
        &self
            .grown
            .as_ref()
            .expect("a tile is drawn in a target")
            .target
    }

    /// Ends `encoder`, which drew the tile at `rect` at the top left of
    /// `texture` (one sample per pixel), with the copy of the tile into the
    /// readback buffer, submits it and waits for it: one round trip through
    /// the driver per tile. `scopes` are the error scopes pushed for the
    /// tile, innermost first; an error they caught is reported as `during`.
    pub fn submit_with_readback(
        &self,
        gpu: &Gpu,
        mut encoder: wgpu::CommandEncoder,
        texture: &wgpu::Texture,
        rect: PixelRect,
        scopes: impl IntoIterator<Item = wgpu::ErrorScopeGuard>,
        during: &'static str,
    ) -> Result<(), RenderError> {
        let grown = self.grown.as_ref().expect("a tile is drawn in a target");
        encode_texture_copy(
            &mut encoder,
            texture,
            &grown.readback,
            padded_row_bytes(rect.width),
            (rect.width, rect.height),
        );
        gpu.queue.submit([encoder.finish()]);
        for scope in scopes {
            check_scope(scope, during)?;
        }
        wait(&gpu.device, during)
    }

    /// The tile at `rect` (none when nothing was drawn), copied into the
    /// readback buffer by its submission: waits for the copy and maps it.
    pub fn read_back(
        &self,
        gpu: &Gpu,
        rect: Option<PixelRect>,
    ) -> Result<Option<Patch>, RenderError> {
        let (Some(rect), Some(grown)) = (rect, &self.grown) else {
            return Ok(None);
        };
        let mut pixels = Vec::with_capacity((rect.width * rect.height * 4) as usize);
        read_buffer(
            gpu,
            &grown.readback,
            padded_row_bytes(rect.width),
            (rect.width, rect.height),
            |_, row| pixels.extend_from_slice(row),
        )?;
        Ok(Some(Patch { rect, pixels }))
    }
}

/// `tile` and `tile_origin` of the uniforms for drawing `rect` of a
/// `width × height` image into a target of `capacity` pixels (see `body_tile`).
pub(super) fn tile_transform(
    rect: PixelRect,
    capacity: (u32, u32),
    width: u32,
    height: u32,
) -> ([f32; 4], [f32; 4]) {
    let (w, h) = (f64::from(width), f64::from(height));
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
