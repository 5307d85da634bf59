//! [`Renderer`]: draws the frames of one run into images — the frame
//! lifecycle.
//!
//! A renderer is made once per run: the input checks ([`FrameShape`]), the
//! run's appearance ([`Look`]: camera, colours, ground, shadow, edges,
//! legend), the GPU objects ([`GpuResources`]), the backdrop (the whole
//! image without the body) and the base every frame is a patch over (the
//! backdrop with the legend) are all fixed then. Each
//! frame then reads as one straight line: check it, fill the vertex
//! buffers, draw the tile around what changed, read it back, stamp the
//! legend where the tile meets it (drawn once on the CPU).
//!
//! - **3D** ([`SceneTiles`]): the backdrop is the whole image without the
//!   body and its contact shadow, drawn in strips of 64 rows into a 4x MSAA
//!   target with a depth target, resolved to `Rgba8UnormSrgb`. Each frame
//!   draws the same layers in the tile around the body and its shadow: the
//!   opaque layers nearest first (surface, ground, background, then edges),
//!   so that hidden samples are rejected before they are shaded, with depth
//!   tests that give the painter's image (see `DepthTest`).
//! - **2D** ([`BodyTiles`]): the backdrop (background, ground, ground line)
//!   is drawn once, single-sampled, painted back to front. Each frame then
//!   draws only the pixel rectangle around the body, in a small
//!   single-sampled target that starts from the backdrop: the surface, the
//!   fringes along its boundary and the edges, anti-aliased in their
//!   shaders (`body_coverage`).
//!
//! In both, the copy of the tile to the readback buffer goes in the same
//! submission, with rows padded to `COPY_BYTES_PER_ROW_ALIGNMENT`, and the
//! tile read back is the frame's patch over the base.
//! [`Renderer::render_multisampled`] draws a frame in one multisampled pass
//! over the whole image instead, the reference the tiles are tested against.
//!
//! Colours are computed on the CPU (viridis in sRGB, converted to linear);
//! shaders work in linear light and the sRGB target encodes on write, so an
//! unlit 2D pixel reads back as the colour map's own sRGB value.

use super::body_coverage::{BodyTopology, BodyVertex, FringeInstance};
use super::body_tile::{BodyTiles, TileInputs, body_rect};
use super::frame_shape::FrameShape;
use super::gpu::{Gpu, check_scope, shared_gpu, wait};
use super::gpu_resources::{GpuResources, LineInstance, SurfaceVertex};
use super::layers::{Layers, record_layers};
use super::look::Look;
use super::pixel_rect::{Patch, PixelRect};
use super::render_targets::WholeImageTargets;
use super::scene_tile::{SceneTiles, scene_rect, shadow_rect};
use super::{RenderError, RenderFrame, RenderMesh, RenderSettings};
use image::RgbaImage;
use nalgebra::{Matrix4, Vector3};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Rows per strip of the 3D backdrop. Even, so that every strip starts on
/// an even row, as the whole image's 2x2 pixel quads do (see `scene_tile`).
const BACKDROP_STRIP_ROWS: u32 = 64;

/// How long the stages of one [`Renderer::render_timed`] call took.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FrameTimings {
    /// Building and uploading vertices, encoding and drawing, until the GPU is done.
    pub draw: Duration,
    /// Copying the image to a buffer, mapping it and stripping the row padding.
    pub readback: Duration,
    /// Drawing the legend on the CPU.
    pub overlay: Duration,
}

/// Draws frames of one mesh with fixed settings, camera and colour range.
pub struct Renderer {
    gpu: Arc<Gpu>,
    settings: RenderSettings,
    mesh: RenderMesh,
    shape: FrameShape,
    look: Look,
    resources: GpuResources,
    surface_scratch: Vec<SurfaceVertex>,
    line_scratch: Vec<LineInstance>,
    colour_scratch: Vec<[f32; 3]>,
    /// What every frame shares, and the tiles each frame is drawn in (made
    /// with the renderer, by `PreparedRenderer::complete`).
    backdrop: Option<Backdrop>,
    /// The whole image's targets, while something is drawn whole: the
    /// backdrop, or a reference image (see `render_targets`).
    whole_image: Option<WholeImageTargets>,
}

/// A 2D frame's body as its tile draws it (see `body_coverage`).
struct Body {
    topology: BodyTopology,
    vertices: Vec<BodyVertex>,
    fringes: Vec<FringeInstance>,
}

/// The fixed part of a run's frames, and the tiles drawn over it.
struct Backdrop {
    /// The whole image without the body (and in 3D its shadow) and the legend.
    image: RgbaImage,
    /// The backdrop with the legend: every frame is this with its tile pasted in.
    base: RgbaImage,
    tiles: FrameTiles,
}

/// How a frame's tile is drawn.
enum FrameTiles {
    /// 2D: the body alone, one sample per pixel, over the backdrop's pixels
    /// (`body_tile`).
    Body { tiles: BodyTiles, body: Body },
    /// 3D: everything around the body and its shadow, multisampled
    /// (`scene_tile`).
    Scene(SceneTiles),
}

impl FrameTiles {
    /// The tile just drawn at `rect`, if any.
    fn read_back(&self, gpu: &Gpu, rect: Option<PixelRect>) -> Result<Option<Patch>, RenderError> {
        match self {
            FrameTiles::Body { tiles, .. } => tiles.read_back(gpu, rect),
            FrameTiles::Scene(tiles) => tiles.read_back(gpu, rect),
        }
    }
}

/// The part of a [`Renderer`] that needs no frames: the device and the
/// run's pipelines, buffers and render targets. [`Renderer::prepare`] makes
/// it, on any thread (a run makes it while it simulates), and
/// [`PreparedRenderer::with_frames`] completes it.
pub struct PreparedRenderer {
    gpu: Arc<Gpu>,
    settings: RenderSettings,
    mesh: RenderMesh,
    resources: GpuResources,
}

impl PreparedRenderer {
    /// The settings it was prepared for.
    pub fn settings(&self) -> &RenderSettings {
        &self.settings
    }

    /// Draws the run's first frame, twice and thrown away, through the
    /// run's own pipelines, so that a software rasteriser compiles its
    /// shaders now rather than when the first real frame is drawn: llvmpipe
    /// compiles each pipeline's shader variants at its first draw (about
    /// 0.2 s for a 2D run, the backdrop's pass and the tile's), and a second
    /// variant of the 2D tile's vertex shaders at the second draw. `first`
    /// is drawn framed on its own (with the automatic camera, the body fills
    /// the image) in an image a quarter of the run's width and height
    /// (`warm_up_size`): the variants do not depend on the image's size,
    /// and the raster work is a sixteenth. A frame this renderer cannot draw
    /// is left for the run to report: the renderer comes back as it was,
    /// not warmed up.
    pub fn warmed_up(self, first: &RenderFrame) -> Result<Self, RenderError> {
        // The legend is drawn on the CPU: the throwaway frames go without.
        let settings = self.settings.clone();
        let (width, height) = warm_up_size(settings.width, settings.height);
        let throwaway_settings = RenderSettings {
            draw_legend: false,
            width,
            height,
            ..settings.clone()
        };
        let throwaway = std::slice::from_ref(first);
        let Ok(shape) = FrameShape::of_run(&throwaway_settings, &self.mesh, throwaway) else {
            return Ok(self);
        };
        let mut renderer = PreparedRenderer {
            settings: throwaway_settings,
            ..self
        }
        .complete(shape, throwaway)?;
        for _ in 0..2 {
            renderer.render_timed(first)?;
        }
        Ok(PreparedRenderer {
            gpu: renderer.gpu,
            settings,
            mesh: renderer.mesh,
            resources: renderer.resources,
        })
    }

    /// The renderer for a run of `frames` (see [`Renderer::new`]).
    pub fn with_frames(self, frames: &[RenderFrame]) -> Result<Renderer, RenderError> {
        let shape = FrameShape::of_run(&self.settings, &self.mesh, frames)?;
        self.complete(shape, frames)
    }

    /// The renderer for a run of `frames`, of `shape` (checked).
    fn complete(self, shape: FrameShape, frames: &[RenderFrame]) -> Result<Renderer, RenderError> {
        let look = Look::new(&self.settings, &self.mesh, frames)?;
        let mut renderer = self.into_renderer(shape, look);
        let (image, tiles) = if renderer.mesh.dimension == 2 {
            let image = renderer.draw_backdrop()?;
            let drawn = &renderer.whole_image.as_ref().expect("just drawn").targets;
            (image, renderer.body_tiles(&drawn.resolved)?)
        } else {
            let image = renderer.draw_scene_backdrop()?;
            (image, FrameTiles::Scene(SceneTiles::new(renderer.size())))
        };
        // Frames are drawn in tiles: the 2D backdrop's whole-image targets
        // are not needed again unless a reference image is asked for (and
        // then made anew). The 2D tiles' bind group keeps the backdrop's
        // texture alive, so nothing draws over it.
        renderer.whole_image = None;
        let mut base = image.clone();
        renderer.look.draw_overlay(&mut base);
        renderer.backdrop = Some(Backdrop { image, base, tiles });
        Ok(renderer)
    }

    /// A renderer with `shape` and `look`, its backdrop still to be made.
    fn into_renderer(self, shape: FrameShape, look: Look) -> Renderer {
        let PreparedRenderer {
            gpu,
            settings,
            mesh,
            resources,
        } = self;
        Renderer {
            gpu,
            shape,
            look,
            resources,
            surface_scratch: Vec::with_capacity(mesh.triangles.len() * 3),
            line_scratch: Vec::with_capacity(mesh.edges.len() + 1),
            colour_scratch: Vec::with_capacity(mesh.element_count),
            backdrop: None,
            whole_image: None,
            settings,
            mesh,
        }
    }
}

impl Renderer {
    /// Prepares to draw `mesh`. The automatic camera frames all of `frames`
    /// and the automatic colour range spans all of them, so neither changes
    /// from frame to frame: with either, `frames` must be the whole run
    /// ([`RenderSettings::needs_whole_run`]). Everything else (a fixed
    /// camera's depth range, the 3D ground's extent, edge fading) depends on
    /// the first frame only, so a fixed-camera run draws the same images
    /// whether it is given up front or frame by frame.
    pub fn new(
        settings: &RenderSettings,
        mesh: &RenderMesh,
        frames: &[RenderFrame],
    ) -> Result<Renderer, RenderError> {
        // Bad frames are reported before the device is opened.
        let shape = FrameShape::of_run(settings, mesh, frames)?;
        Self::prepare(settings, mesh)?.complete(shape, frames)
    }

    /// Opens the device and makes what drawing `mesh` with `settings` needs
    /// before any frame is known.
    pub fn prepare(
        settings: &RenderSettings,
        mesh: &RenderMesh,
    ) -> Result<PreparedRenderer, RenderError> {
        let gpu = shared_gpu()?;
        if settings.width > gpu.max_texture_side || settings.height > gpu.max_texture_side {
            return Err(RenderError::ImageTooLarge {
                width: settings.width,
                height: settings.height,
                max: gpu.max_texture_side,
            });
        }
        let resources = GpuResources::new(&gpu, settings, mesh)?;
        Ok(PreparedRenderer {
            gpu,
            settings: settings.clone(),
            mesh: mesh.clone(),
            resources,
        })
    }

    /// Whether the whole image's render targets are held. A 2D renderer
    /// makes them for its backdrop and drops them once that is read back, a
    /// 3D one draws its backdrop in strips; only the reference path
    /// ([`Renderer::render_multisampled`]) makes them again. For tests.
    #[doc(hidden)]
    pub fn holds_whole_image_targets(&self) -> bool {
        self.whole_image.is_some()
    }

    /// The adapter this renderer draws with (name, backend, driver, type).
    pub fn adapter_description(&self) -> &str {
        &self.gpu.description
    }

    /// The colour range, fixed for the run (for the legend or a caption).
    pub fn colour_range(&self) -> [f32; 2] {
        self.look.range()
    }

    /// The settings it draws with.
    pub fn settings(&self) -> &RenderSettings {
        &self.settings
    }

    /// Image width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.settings.width, self.settings.height)
    }

    /// Draws one frame as a whole image.
    pub fn render(&mut self, frame: &RenderFrame) -> Result<RgbaImage, RenderError> {
        self.render_timed(frame).map(|(image, _)| image)
    }

    /// Draws one frame as one whole image, the way its frames are drawn:
    /// in one tile the size of the image, where [`Renderer::render`] draws
    /// only the tile around the body (in 3D, and its shadow; see
    /// `body_tile` and `scene_tile`). This is the reference the tiles are
    /// checked against, and slower.
    pub fn render_whole_image(&mut self, frame: &RenderFrame) -> Result<RgbaImage, RenderError> {
        self.shape.check(frame)?;
        self.fill_buffers(frame);
        let (width, height) = self.size();
        let rect = self.draw_tile(Some(PixelRect::new(0, 0, width, height)))?;
        let backdrop = self.backdrop.as_ref().expect("made with the renderer");
        let mut image = RgbaImage::clone(&backdrop.image);
        if let Some(patch) = backdrop.tiles.read_back(&self.gpu, rect)? {
            patch.paste_into(&mut image);
        }
        self.look.draw_overlay(&mut image);
        Ok(image)
    }

    /// Draws one frame as one whole image with 4x MSAA (when the adapter
    /// has it) for everything, the body included, in one pass: in 2D the
    /// reference that the body's own anti-aliasing (`body_coverage`) is
    /// measured against, in 3D the reference for the tiles' rounding.
    pub fn render_multisampled(&mut self, frame: &RenderFrame) -> Result<RgbaImage, RenderError> {
        self.shape.check(frame)?;
        self.fill_buffers(frame);
        self.upload_lines();
        self.fill_surface(frame);
        self.upload_surface();
        self.hold_whole_image(self.gpu.sample_count)?;
        self.draw_whole_image(&self.layers(self.surface_scratch.len()))?;
        let mut image = self.read_whole_image()?;
        self.look.draw_overlay(&mut image);
        Ok(image)
    }

    /// Draws one frame as a whole image (the run's base with the frame's
    /// tile pasted in), and says how long each stage took.
    pub fn render_timed(
        &mut self,
        frame: &RenderFrame,
    ) -> Result<(RgbaImage, FrameTimings), RenderError> {
        let start = Instant::now();
        self.shape.check(frame)?;
        self.fill_buffers(frame);
        let (width, height) = self.size();
        let globals = self.look.globals();
        let view_proj = Matrix4::from(globals.view_proj);
        let body = body_rect(
            &view_proj,
            &frame.positions,
            self.look.edge_width(),
            width,
            height,
        );
        let rect = if self.mesh.dimension == 2 {
            body
        } else {
            let shadow = self
                .resources
                .ground
                .as_ref()
                .and_then(|_| shadow_rect(globals, width, height));
            scene_rect(body, shadow)
        };
        let rect = self.draw_tile(rect)?;
        let drawn = Instant::now();
        let backdrop = self.backdrop.as_ref().expect("made with the renderer");
        let patch = backdrop.tiles.read_back(&self.gpu, rect)?;
        let read = Instant::now();
        let image = match patch {
            None => backdrop.base.clone(),
            // Where the tile meets the legend, the legend is drawn over it.
            Some(patch) => match self.look.overlay_footprint() {
                Some(footprint) if footprint.intersects(&patch.rect) => {
                    let mut image = backdrop.image.clone();
                    patch.paste_into(&mut image);
                    self.look.draw_overlay(&mut image);
                    image
                }
                _ => {
                    let mut image = backdrop.base.clone();
                    patch.paste_into(&mut image);
                    image
                }
            },
        };
        let timings = FrameTimings {
            draw: drawn - start,
            readback: read - drawn,
            overlay: read.elapsed(),
        };
        Ok((image, timings))
    }

    /// Draws the frame whose buffers are filled in the tile at `rect` and
    /// waits for it (see `body_tile`, `scene_tile`); returns the tile's
    /// place, or `None` when the frame is the backdrop.
    fn draw_tile(&mut self, rect: Option<PixelRect>) -> Result<Option<PixelRect>, RenderError> {
        let backdrop = self.backdrop.as_mut().expect("made with the renderer");
        match &mut backdrop.tiles {
            FrameTiles::Body { tiles, body } => {
                let inputs = tile_inputs(&self.resources, &self.look, body, &self.line_scratch);
                tiles.draw(&self.gpu, &inputs, rect)
            }
            FrameTiles::Scene(tiles) => {
                let layers = Layers {
                    resources: &self.resources,
                    background: self.look.has_gradient(),
                    surface_vertices: self.surface_scratch.len() as u32,
                    ground_lines: self.look.ground_lines(),
                    lines: self.line_scratch.len() as u32,
                };
                let clear = self.look.clear_colour();
                tiles.draw(&self.gpu, &layers, self.look.globals(), clear, rect)
            }
        }
    }

    /// The 3D backdrop: the whole image without the body and its shadow (no
    /// legend), multisampled. It is drawn in strips of
    /// [`BACKDROP_STRIP_ROWS`] rows, each a tile (`scene_tile`) in a target
    /// of its own that is dropped afterwards: the whole image's
    /// multisampled colour and depth targets would be about 30 MB at
    /// 1280x720, and 270 MB at 3840x2160.
    fn draw_scene_backdrop(&mut self) -> Result<RgbaImage, RenderError> {
        let mut globals = *self.look.globals();
        globals.shadow_params[0] = 0.0;
        let layers = Layers {
            resources: &self.resources,
            background: self.look.has_gradient(),
            surface_vertices: 0,
            ground_lines: 0,
            lines: 0,
        };
        let (width, height) = self.size();
        let mut strips = SceneTiles::new((width, height));
        let mut image = RgbaImage::from_pixel(width, height, image::Rgba([0, 0, 0, 255]));
        let clear = self.look.clear_colour();
        for y in (0..height).step_by(BACKDROP_STRIP_ROWS as usize) {
            let strip = PixelRect::new(0, y, width, BACKDROP_STRIP_ROWS.min(height - y));
            let drawn = strips.draw(&self.gpu, &layers, &globals, clear, Some(strip))?;
            if let Some(patch) = strips.read_back(&self.gpu, drawn)? {
                patch.paste_into(&mut image);
            }
        }
        Ok(image)
    }

    /// The 2D tiles over the backdrop in `backdrop`, with room for the body.
    fn body_tiles(&self, backdrop: &wgpu::Texture) -> Result<FrameTiles, RenderError> {
        let tiles = BodyTiles::new(&self.gpu, &self.resources, backdrop)?;
        let triangles = self.mesh.triangles.len();
        let topology = BodyTopology::new(&self.mesh);
        let body = Body {
            vertices: Vec::with_capacity(3 * triangles),
            fringes: Vec::with_capacity(topology.boundary_edges()),
            topology,
        };
        Ok(FrameTiles::Body { tiles, body })
    }

    /// The 2D backdrop: the whole image without the body (no legend),
    /// single-sampled: the ground anti-aliases its edge in its shader, and
    /// the ground line is drawn by coverage like the body's edges.
    fn draw_backdrop(&mut self) -> Result<RgbaImage, RenderError> {
        self.look.lines(&[], &[], &mut self.line_scratch);
        self.upload_lines();
        self.hold_whole_image(1)?;
        let targets = &self.whole_image.as_ref().expect("just made").targets;
        let device = &self.gpu.device;
        let r = &self.resources;
        let tile = r.tile.as_ref().expect("a 2D renderer has tiles");
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("backdrop encoder"),
        });
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("backdrop pass"),
                color_attachments: &[Some(targets.colour_attachment(self.look.clear_colour()))],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &r.bind_group, &[]);
            // A plain background is the clear colour already.
            if self.look.has_gradient() {
                pass.set_pipeline(&tile.background);
                pass.draw(0..3, 0..1);
            }
            if let Some(ground) = &tile.ground {
                pass.set_pipeline(ground);
                pass.draw(0..6, 0..1);
            }
            let ground_lines = self.look.ground_lines();
            if ground_lines > 0 {
                pass.set_pipeline(&tile.line);
                pass.set_vertex_buffer(0, r.line_instances.slice(..));
                pass.draw(0..6, 0..ground_lines);
            }
        }
        self.gpu.queue.submit([encoder.finish()]);
        check_scope(validation, "drawing the backdrop")?;
        wait(device, "drawing the backdrop")?;
        self.read_whole_image()
    }

    /// Makes the whole image's targets with `samples` samples per pixel,
    /// unless they are made already.
    fn hold_whole_image(&mut self, samples: u32) -> Result<(), RenderError> {
        if self.whole_image.as_ref().map(WholeImageTargets::samples) != Some(samples) {
            // The old targets go first: both need not fit at once.
            self.whole_image = None;
            self.whole_image = Some(WholeImageTargets::new(
                &self.gpu,
                self.size(),
                samples,
                self.mesh.dimension == 3,
            )?);
        }
        Ok(())
    }

    /// Draws `layers` over the whole image, into the targets the caller
    /// holds ([`Renderer::hold_whole_image`]), and waits for it.
    fn draw_whole_image(&self, layers: &Layers<'_>) -> Result<(), RenderError> {
        let targets = &self
            .whole_image
            .as_ref()
            .expect("held by the caller")
            .targets;
        let device = &self.gpu.device;
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out_of_memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("frame encoder"),
        });
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("frame pass"),
                color_attachments: &[Some(targets.colour_attachment(self.look.clear_colour()))],
                depth_stencil_attachment: targets.depth_attachment(),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            record_layers(&mut pass, layers);
        }
        self.gpu.queue.submit([encoder.finish()]);
        check_scope(out_of_memory, "drawing a frame")?;
        check_scope(validation, "drawing a frame")?;
        wait(device, "drawing a frame")
    }

    /// Everything this frame's filled buffers hold, with `surface_vertices`
    /// of the surface.
    fn layers(&self, surface_vertices: usize) -> Layers<'_> {
        Layers {
            resources: &self.resources,
            background: self.look.has_gradient(),
            surface_vertices: surface_vertices as u32,
            ground_lines: self.look.ground_lines(),
            lines: self.line_scratch.len() as u32,
        }
    }

    /// Reads the whole image just drawn back from the GPU.
    fn read_whole_image(&self) -> Result<RgbaImage, RenderError> {
        self.whole_image
            .as_ref()
            .expect("drawn by the caller")
            .read(&self.gpu)
    }

    /// Builds this frame's colours, body, edges and uniforms and uploads
    /// the vertices: the body as its 2D tile draws it, or the 3D surface. A
    /// tile's draw uploads the uniforms itself, with its tile transform.
    fn fill_buffers(&mut self, frame: &RenderFrame) {
        self.look
            .element_colours(frame, self.mesh.element_count, &mut self.colour_scratch);
        self.look
            .lines(&self.mesh.edges, &frame.positions, &mut self.line_scratch);
        self.look.follow_body(&frame.positions);
        self.upload_line_instances();
        match &mut self.backdrop {
            Some(Backdrop {
                tiles: FrameTiles::Body { body, .. },
                ..
            }) => {
                body.topology.fill(
                    &self.mesh,
                    &frame.positions,
                    &self.colour_scratch,
                    &mut body.vertices,
                    &mut body.fringes,
                );
                let tile = self
                    .resources
                    .tile
                    .as_ref()
                    .expect("a 2D renderer has tiles");
                let queue = &self.gpu.queue;
                queue.write_buffer(&tile.body_vertices, 0, bytemuck::cast_slice(&body.vertices));
                queue.write_buffer(
                    &tile.fringe_instances,
                    0,
                    bytemuck::cast_slice(&body.fringes),
                );
            }
            _ => {
                self.fill_surface(frame);
                self.upload_surface();
            }
        }
    }

    /// Builds the flat-shaded surface triangles of a frame (with the
    /// element colours already made).
    fn fill_surface(&mut self, frame: &RenderFrame) {
        let x = &frame.positions;
        self.surface_scratch.clear();
        for (t, &element) in self.mesh.triangles.iter().zip(&self.mesh.triangle_element) {
            let p = t.map(|i| Vector3::from(x[i as usize]));
            let n = (p[1] - p[0]).cross(&(p[2] - p[0]));
            let normal = if n.norm() > 0.0 && n.iter().all(|c| c.is_finite()) {
                n.normalize()
            } else {
                Vector3::y()
            };
            let colour = self.colour_scratch[element as usize];
            for corner in p {
                self.surface_scratch.push(SurfaceVertex {
                    position: corner.into(),
                    normal: normal.into(),
                    colour,
                });
            }
        }
    }

    /// Uploads the uniforms and lines built for the next draw.
    fn upload_lines(&self) {
        let globals = bytemuck::bytes_of(self.look.globals());
        self.gpu
            .queue
            .write_buffer(&self.resources.uniforms, 0, globals);
        self.upload_line_instances();
    }

    /// Uploads the lines built for the next draw.
    fn upload_line_instances(&self) {
        self.gpu.queue.write_buffer(
            &self.resources.line_instances,
            0,
            bytemuck::cast_slice(&self.line_scratch),
        );
    }

    /// Uploads the surface triangles built for the next draw.
    fn upload_surface(&self) {
        self.gpu.queue.write_buffer(
            &self.resources.surface_vertices,
            0,
            bytemuck::cast_slice(&self.surface_scratch),
        );
    }
}

/// The image size a renderer warms up at for a run of `width` x `height`:
/// a quarter of each side, unless that is under 64 x 36 pixels. Preparing
/// and warming up drop-3d's renderer took 0.33 s on one llvmpipe thread at
/// the full size and 0.17 s at a quarter (mostly the multisampled backdrop
/// and the two frames' raster work, done while the run simulates, on the
/// core it shares with the simulation when that uses both); the real
/// frames' tile targets then grow to their size at the first frames.
fn warm_up_size(width: u32, height: u32) -> (u32, u32) {
    const SHRINK: u32 = 4;
    let (small_width, small_height) = (width.div_ceil(SHRINK), height.div_ceil(SHRINK));
    if small_width >= 64 && small_height >= 36 {
        (small_width, small_height)
    } else {
        (width, height)
    }
}

/// What a 2D frame's tile is drawn with, from the buffers filled for it.
fn tile_inputs<'a>(
    resources: &'a GpuResources,
    look: &'a Look,
    body: &Body,
    lines: &[LineInstance],
) -> TileInputs<'a> {
    TileInputs {
        resources,
        globals: look.globals(),
        body_vertices: body.vertices.len() as u32,
        fringes: body.fringes.len() as u32,
        body_lines: look.ground_lines()..lines.len() as u32,
    }
}
