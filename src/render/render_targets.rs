//! [`RenderTargets`]: the colour and depth textures one pass draws into,
//! and [`WholeImageTargets`]: those of the whole image with its readback
//! buffer.
//!
//! A pass with `s > 1` samples draws into an `s`-sample colour target that
//! is resolved into a single-sampled one at the end of the pass; only the
//! resolved image is read, so the samples are never stored. With one
//! sample the pass draws straight into the resolved target. A 3D pass also
//! has a depth target of `s` samples, cleared to the far plane and not
//! stored either.
//!
//! The tiles of a 3D run are drawn into `RenderTargets` of their own
//! (`scene_tile`), and so is its backdrop, in strips. The whole image's
//! targets serve only the 2D backdrop (single-sampled, drawn once per run)
//! and the reference paths that draw a frame whole (see `Renderer`): the
//! renderer makes them when one of those needs them and drops them once
//! the image is read back (the 2D backdrop's resolved texture lives on in
//! the tiles' bind group, which samples it for every frame). At 1280x720
//! with 4x MSAA and depth they would be about 37 MB (colour and depth
//! samples, the resolved image, its readback buffer).

use super::RenderError;
use super::gpu::{Gpu, check_scope};
use super::gpu_resources::{COLOR_FORMAT, DEPTH_FORMAT, padded_row_bytes, readback_buffer};
use super::readback::read_texture;
use image::RgbaImage;

/// Colour (multisampled and resolved) and optional depth targets of one size.
pub(super) struct RenderTargets {
    /// The `s`-sample colour target (`None` with one sample).
    msaa_view: Option<wgpu::TextureView>,
    /// The resolved colour, the one read back.
    pub resolved: wgpu::Texture,
    resolved_view: wgpu::TextureView,
    depth_view: Option<wgpu::TextureView>,
}

impl RenderTargets {
    /// Targets of `size` pixels with `samples` samples, with a depth target
    /// when `depth`; `label` names them in the driver's messages.
    pub fn new(gpu: &Gpu, size: (u32, u32), samples: u32, depth: bool, label: &str) -> Self {
        let device = &gpu.device;
        let texture = |what: &str, format, sample_count, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(&format!("{label} {what}")),
                size: wgpu::Extent3d {
                    width: size.0,
                    height: size.1,
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
        // The targets of `samples` samples are drawn into, never read.
        let attachment = |what: &str, format| {
            texture(
                what,
                format,
                samples,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            )
            .create_view(&Default::default())
        };
        let msaa_view = (samples > 1).then(|| attachment("multisampled colour", COLOR_FORMAT));
        // The 2D backdrop's resolved target is also sampled by every tile
        // drawn over it (`body_tile`).
        let resolved = texture(
            "colour",
            COLOR_FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let resolved_view = resolved.create_view(&Default::default());
        let depth_view = depth.then(|| attachment("depth", DEPTH_FORMAT));
        RenderTargets {
            msaa_view,
            resolved,
            resolved_view,
            depth_view,
        }
    }

    /// The colour attachment of a pass cleared to `clear` (see the module
    /// documentation).
    pub fn colour_attachment(&self, clear: wgpu::Color) -> wgpu::RenderPassColorAttachment<'_> {
        let (view, resolve_target, store) = match &self.msaa_view {
            Some(msaa) => (msaa, Some(&self.resolved_view), wgpu::StoreOp::Discard),
            None => (&self.resolved_view, None, wgpu::StoreOp::Store),
        };
        wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(clear),
                store,
            },
        }
    }

    /// The depth attachment, cleared to the far plane and not stored (none
    /// without a depth target).
    pub fn depth_attachment(&self) -> Option<wgpu::RenderPassDepthStencilAttachment<'_>> {
        self.depth_view
            .as_ref()
            .map(|view| wgpu::RenderPassDepthStencilAttachment {
                view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            })
    }
}

/// The whole image's targets and the buffer it is read back through.
pub(super) struct WholeImageTargets {
    pub targets: RenderTargets,
    samples: u32,
    readback: wgpu::Buffer,
    size: (u32, u32),
}

impl WholeImageTargets {
    /// Targets for an image of `size` pixels with `samples` samples, with a
    /// depth target when `depth`. Fails when the device cannot hold them.
    pub fn new(
        gpu: &Gpu,
        size: (u32, u32),
        samples: u32,
        depth: bool,
    ) -> Result<Self, RenderError> {
        let device = &gpu.device;
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out_of_memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let targets = RenderTargets::new(gpu, size, samples, depth, "whole image");
        let readback = readback_buffer(device, "whole image readback buffer", size);
        check_scope(out_of_memory, "creating render targets")?;
        check_scope(validation, "creating render targets")?;
        Ok(WholeImageTargets {
            targets,
            samples,
            readback,
            size,
        })
    }

    /// How many samples per pixel its passes draw.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Reads the image just drawn back from the GPU.
    pub fn read(&self, gpu: &Gpu) -> Result<RgbaImage, RenderError> {
        let (width, height) = self.size;
        let mut pixels = Vec::with_capacity((width * height * 4) as usize);
        read_texture(
            gpu,
            &self.targets.resolved,
            &self.readback,
            padded_row_bytes(width),
            self.size,
            |_, row| pixels.extend_from_slice(row),
        )?;
        Ok(RgbaImage::from_raw(width, height, pixels)
            .expect("the readback holds width x height pixels"))
    }
}
