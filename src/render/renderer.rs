//! [`Renderer`]: draws the frames of one run into whole images, 2D and 3D
//! by one path.
//!
//! A renderer is made once per run. What needs no frame — the device, the
//! pipelines and buffers — is made first ([`PreparedRenderer`], on a thread
//! of its own while the run simulates). Then, given the run's frames (all
//! of them for an automatic camera or colour range, the first otherwise),
//! the run's look is fixed ([`Look`]: camera, colours, ground, shadow,
//! edges, legend), and the backdrop is drawn: the image without the bodies
//! and obstacles (in 3D without the contact shadow), in strips of
//! [`BACKDROP_STRIP_ROWS`] rows through the frame target; the base every
//! frame is pasted into is the backdrop with the legend.
//!
//! Each frame then reads as one straight line: check it, build its
//! colours, vertices and lines on the CPU and upload them, draw the tile
//! around it (`frame_target`) in one pass (`pipelines`), read the tile back,
//! paste it into the base, and draw the legend again only where the tile
//! meets it. Drawing and reading back are two calls,
//! [`Renderer::start`] and [`Renderer::finish`], so that a caller can read
//! frame `N` back while frame `N + 1` is drawn ([`FRAMES_IN_FLIGHT`] at
//! most); [`Renderer::render`] does both.
//!
//! Colours are computed on the CPU (viridis in sRGB, converted to linear);
//! shaders work in linear light and the sRGB target encodes on write, so an
//! unlit 2D pixel reads back as the colour map's own sRGB value. In 2D the
//! fringes read the backdrop where they give a pixel back to what lies
//! behind the bodies: the backdrop image is uploaded as a texture for them.

use super::body_coverage::{BodyTopology, BodyVertex, FringeInstance};
use super::frame_shape::FrameShape;
use super::frame_target::{FRAMES_IN_FLIGHT, FrameTarget};
use super::gpu::{Gpu, shared_gpu};
use super::look::Look;
use super::pipelines::{COLOR_FORMAT, Contents, Globals, LineInstance, Pipelines, SurfaceVertex};
use super::pixel_rect::{Patch, PixelRect};
use super::{RenderError, RenderFrame, RenderMesh, RenderSettings};
use image::RgbaImage;
use nalgebra::Vector3;
use std::collections::VecDeque;
use std::sync::Arc;
use std::time::{Duration, Instant};
use wgpu::util::DeviceExt;

/// Rows per strip of the backdrop: a whole image's 4x multisampled colour
/// and depth targets would be about 30 MB at 1280x720, and 270 MB at
/// 3840x2160. Even, so that every strip starts on an even row.
const BACKDROP_STRIP_ROWS: u32 = 64;

/// How long the stages of one frame took.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FrameTimings {
    /// Building and uploading vertices, encoding and submitting the draw.
    pub draw: Duration,
    /// Waiting for the tile to be drawn and mapped, and copying it out.
    pub readback: Duration,
    /// Pasting the tile into the base image, and the legend where it meets it.
    pub overlay: Duration,
}

/// The part of a [`Renderer`] that needs no frames: the device and the
/// run's pipelines and buffers. [`Renderer::prepare`] makes it, on any
/// thread (a run makes it while it simulates), and
/// [`PreparedRenderer::with_frames`] completes it.
pub struct PreparedRenderer {
    gpu: Arc<Gpu>,
    settings: RenderSettings,
    mesh: RenderMesh,
    pipelines: Pipelines,
}

/// Draws frames of one mesh with fixed settings, camera and colour range.
pub struct Renderer {
    gpu: Arc<Gpu>,
    settings: RenderSettings,
    mesh: RenderMesh,
    shape: FrameShape,
    look: Look,
    pipelines: Pipelines,
    /// The uniforms and, in 2D, the backdrop the fringes read.
    bind_group: wgpu::BindGroup,
    target: FrameTarget,
    /// 2D: the triangles' adjacency, for their anti-aliasing.
    topology: Option<BodyTopology>,
    scratch: Scratch,
    /// The image without the bodies, and with the legend (the base).
    backdrop: RgbaImage,
    base: RgbaImage,
    /// Frames started and not finished, oldest first: the ring slot their
    /// tile is read through (`None`: nothing of them is in the image), and
    /// how long drawing took.
    in_flight: VecDeque<(Option<usize>, Duration)>,
}

/// The vectors a frame's buffers are built in, kept between frames.
#[derive(Default)]
struct Scratch {
    colours: Vec<[f32; 3]>,
    body: Vec<BodyVertex>,
    fringes: Vec<FringeInstance>,
    surface: Vec<SurfaceVertex>,
    lines: Vec<LineInstance>,
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
    /// 0.2 s for a 2D run), and a second variant of the 2D vertex shaders
    /// at the second draw. `first` is drawn framed on its own (with the
    /// automatic camera, the body fills the image) in an image a quarter of
    /// the run's width and height (`warm_up_size`): the variants do not
    /// depend on the image's size, and the raster work is a sixteenth. A
    /// frame this renderer cannot draw is left for the run to report: the
    /// renderer comes back as it was, not warmed up.
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
            renderer.render(first)?;
        }
        Ok(PreparedRenderer {
            gpu: renderer.gpu,
            settings,
            mesh: renderer.mesh,
            pipelines: renderer.pipelines,
        })
    }

    /// The renderer for a run of `frames` (see [`Renderer::new`]).
    pub fn with_frames(self, frames: &[RenderFrame]) -> Result<Renderer, RenderError> {
        let shape = FrameShape::of_run(&self.settings, &self.mesh, frames)?;
        self.complete(shape, frames)
    }

    /// The renderer for a run of `frames`, of `shape` (checked): its look,
    /// backdrop and base.
    fn complete(self, shape: FrameShape, frames: &[RenderFrame]) -> Result<Renderer, RenderError> {
        let look = Look::new(&self.settings, &self.mesh, frames)?;
        let PreparedRenderer {
            gpu,
            settings,
            mesh,
            pipelines,
        } = self;
        // The backdrop's own pass reads no backdrop: a placeholder stands in.
        let placeholder = texture_of(&gpu, &RgbaImage::new(1, 1));
        let size = (settings.width, settings.height);
        let mut renderer = Renderer {
            bind_group: bind_group(&gpu, &pipelines, &placeholder),
            target: FrameTarget::new(size, pipelines.samples, pipelines.depth),
            topology: (mesh.dimension == 2).then(|| BodyTopology::new(&mesh)),
            scratch: Scratch::default(),
            backdrop: RgbaImage::new(0, 0),
            base: RgbaImage::new(0, 0),
            in_flight: VecDeque::with_capacity(FRAMES_IN_FLIGHT),
            gpu,
            settings,
            mesh,
            shape,
            look,
            pipelines,
        };
        let backdrop = renderer.draw_backdrop()?;
        if renderer.topology.is_some() {
            let texture = texture_of(&renderer.gpu, &backdrop);
            renderer.bind_group = bind_group(&renderer.gpu, &renderer.pipelines, &texture);
        }
        let mut base = backdrop.clone();
        renderer.look.draw_overlay(&mut base);
        (renderer.backdrop, renderer.base) = (backdrop, base);
        Ok(renderer)
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

    /// Checks that `mesh`, the run's `frames` and `settings` fit together
    /// (what [`Renderer::new`] checks before it opens the device).
    pub fn check(
        settings: &RenderSettings,
        mesh: &RenderMesh,
        frames: &[RenderFrame],
    ) -> Result<(), RenderError> {
        FrameShape::of_run(settings, mesh, frames).map(|_| ())
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
        let pipelines = Pipelines::new(&gpu, settings, mesh)?;
        Ok(PreparedRenderer {
            gpu,
            settings: settings.clone(),
            mesh: mesh.clone(),
            pipelines,
        })
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

    /// The size of the target tiles are drawn in, if one is held: a frame
    /// draws around its bodies, not the whole image. For tests.
    #[doc(hidden)]
    pub fn tile_capacity(&self) -> Option<(u32, u32)> {
        self.target.capacity()
    }

    /// Draws one frame as a whole image.
    pub fn render(&mut self, frame: &RenderFrame) -> Result<RgbaImage, RenderError> {
        self.render_timed(frame).map(|(image, _)| image)
    }

    /// Draws one frame as a whole image, and says how long each stage took.
    /// No other frame may be in flight.
    pub fn render_timed(
        &mut self,
        frame: &RenderFrame,
    ) -> Result<(RgbaImage, FrameTimings), RenderError> {
        if !self.in_flight.is_empty() {
            return Err(RenderError::InvalidInput(
                "a frame is drawn while others are in flight".into(),
            ));
        }
        self.start(frame)?;
        Ok(self.finish()?.expect("started above"))
    }

    /// Starts drawing `frame`: its image comes from [`Renderer::finish`],
    /// frames in the order they were started. At most
    /// [`FRAMES_IN_FLIGHT`] frames may be started and not finished.
    pub fn start(&mut self, frame: &RenderFrame) -> Result<(), RenderError> {
        let began = Instant::now();
        if self.in_flight.len() == FRAMES_IN_FLIGHT {
            return Err(RenderError::InvalidInput(format!(
                "more than {FRAMES_IN_FLIGHT} frames started and not finished"
            )));
        }
        self.shape.check(frame)?;
        let contents = self.fill_buffers(frame);
        let slot = match self.look.tile_rect(&frame.positions) {
            Some(rect) => Some(self.draw(rect, &contents, *self.look.globals())?),
            None => None,
        };
        self.in_flight.push_back((slot, began.elapsed()));
        Ok(())
    }

    /// The image of the oldest frame started and not finished (`None`
    /// without one), and the times of its stages.
    pub fn finish(&mut self) -> Result<Option<(RgbaImage, FrameTimings)>, RenderError> {
        let Some((slot, draw)) = self.in_flight.pop_front() else {
            return Ok(None);
        };
        let began = Instant::now();
        let patch = match slot {
            Some(slot) => Some(self.target.receive(&self.gpu, slot)?),
            None => None,
        };
        let read = Instant::now();
        let image = self.compose(patch);
        let timings = FrameTimings {
            draw,
            readback: read - began,
            overlay: read.elapsed(),
        };
        Ok(Some((image, timings)))
    }

    /// How many frames are started and not finished.
    pub fn frames_in_flight(&self) -> usize {
        self.in_flight.len()
    }

    /// Draws one frame in one tile the size of the image, where
    /// [`Renderer::render`] draws only the tile around what changed: the
    /// reference the tiles are checked against. No other frame may be in
    /// flight.
    pub fn render_whole_image(&mut self, frame: &RenderFrame) -> Result<RgbaImage, RenderError> {
        self.shape.check(frame)?;
        let contents = self.fill_buffers(frame);
        let (width, height) = self.size();
        let slot = self.draw(
            PixelRect::new(0, 0, width, height),
            &contents,
            *self.look.globals(),
        )?;
        let patch = self.target.receive(&self.gpu, slot)?;
        let mut image = self.backdrop.clone();
        patch.paste_into(&mut image);
        self.look.draw_overlay(&mut image);
        Ok(image)
    }

    /// The frame whose tile is `patch` (none: it is the base): the base
    /// with the tile pasted in, and the legend drawn over it again where
    /// the tile meets it.
    fn compose(&self, patch: Option<Patch>) -> RgbaImage {
        let Some(patch) = patch else {
            return self.base.clone();
        };
        let under_legend = self
            .look
            .overlay_footprint()
            .is_some_and(|footprint| footprint.intersects(&patch.rect));
        let mut image = if under_legend {
            self.backdrop.clone()
        } else {
            self.base.clone()
        };
        patch.paste_into(&mut image);
        if under_legend {
            self.look.draw_overlay(&mut image);
        }
        image
    }

    /// Draws `contents` in the tile `rect` with `globals`; returns the ring
    /// slot it is read back through.
    fn draw(
        &mut self,
        rect: PixelRect,
        contents: &Contents,
        globals: Globals,
    ) -> Result<usize, RenderError> {
        let (pipelines, bind_group) = (&self.pipelines, &self.bind_group);
        self.target.draw(
            &self.gpu,
            &pipelines.uniforms,
            &globals,
            self.look.clear_colour(),
            rect,
            |pass| pipelines.record(pass, bind_group, contents),
        )
    }

    /// The backdrop: the whole image without the bodies, the obstacles and
    /// the shadow (no legend), drawn in strips of [`BACKDROP_STRIP_ROWS`]
    /// rows; the target is then let go, for the frames' tiles.
    fn draw_backdrop(&mut self) -> Result<RgbaImage, RenderError> {
        let mut globals = *self.look.globals();
        globals.shadow_params[0] = 0.0;
        self.scratch.lines.clear();
        self.scratch.lines.extend(self.look.ground_line());
        self.upload_lines();
        let contents = Contents {
            background: self.look.has_gradient(),
            ground: self.settings.ground_height.is_some(),
            ground_lines: 0..self.scratch.lines.len() as u32,
            ..Contents::default()
        };
        let (width, height) = self.size();
        let mut image = RgbaImage::new(width, height);
        for y in (0..height).step_by(BACKDROP_STRIP_ROWS as usize) {
            let strip = PixelRect::new(0, y, width, BACKDROP_STRIP_ROWS.min(height - y));
            let slot = self.draw(strip, &contents, globals)?;
            self.target.receive(&self.gpu, slot)?.paste_into(&mut image);
        }
        self.target.shrink();
        Ok(image)
    }

    /// Builds this frame's colours, surfaces and lines and uploads them;
    /// moves the contact shadow under its bodies. Returns what its pass
    /// draws.
    fn fill_buffers(&mut self, frame: &RenderFrame) -> Contents {
        let (mesh, look, s) = (&self.mesh, &mut self.look, &mut self.scratch);
        let x = &frame.positions;
        look.element_colours(frame, mesh.element_count, &mut s.colours);
        let lines = look.lines(mesh, x, &mut s.lines);
        look.follow_bodies(&x[..mesh.body_vertices(x.len())]);
        let obstacle = look.obstacle_colour();
        let queue = &self.gpu.queue;
        let p = &self.pipelines;
        s.surface.clear();
        let (surface, fringes, obstacle_fill) = match &self.topology {
            Some(topology) => {
                topology.fill(mesh, x, &s.colours, &mut s.body, &mut s.fringes);
                push_triangles(&mut s.surface, &mesh.obstacle_triangles, x, |_| obstacle);
                queue.write_buffer(&p.surface_vertices, 0, bytemuck::cast_slice(&s.body));
                queue.write_buffer(&p.fringe_instances, 0, bytemuck::cast_slice(&s.fringes));
                queue.write_buffer(&p.obstacle_vertices, 0, bytemuck::cast_slice(&s.surface));
                (s.body.len(), s.fringes.len(), s.surface.len())
            }
            None => {
                let colours = &s.colours;
                push_triangles(&mut s.surface, &mesh.triangles, x, |t| {
                    let [r, g, b] = colours[mesh.triangle_element[t] as usize];
                    [r, g, b, 1.0]
                });
                push_triangles(&mut s.surface, &mesh.obstacle_triangles, x, |_| obstacle);
                queue.write_buffer(&p.surface_vertices, 0, bytemuck::cast_slice(&s.surface));
                (s.surface.len(), 0, 0)
            }
        };
        self.upload_lines();
        let ground = lines.ground;
        let obstacles = ground + lines.obstacles;
        Contents {
            background: self.look.has_gradient(),
            ground: self.settings.ground_height.is_some(),
            surface: surface as u32,
            fringes: fringes as u32,
            obstacle_fill: obstacle_fill as u32,
            ground_lines: 0..ground,
            obstacle_lines: ground..obstacles,
            body_lines: obstacles..obstacles + lines.bodies,
        }
    }

    /// Uploads the lines built for the next draw.
    fn upload_lines(&self) {
        self.gpu.queue.write_buffer(
            &self.pipelines.line_instances,
            0,
            bytemuck::cast_slice(&self.scratch.lines),
        );
    }
}

/// Appends the corners of `triangles` at `positions`, flat shaded (one
/// normal per triangle), the triangle `t` in `colour(t)`.
fn push_triangles(
    vertices: &mut Vec<SurfaceVertex>,
    triangles: &[[u32; 3]],
    positions: &[[f32; 3]],
    colour: impl Fn(usize) -> [f32; 4],
) {
    for (t, triangle) in triangles.iter().enumerate() {
        let p = triangle.map(|i| Vector3::from(positions[i as usize]));
        let n = (p[1] - p[0]).cross(&(p[2] - p[0]));
        let normal = if n.norm() > 0.0 && n.iter().all(|c| c.is_finite()) {
            n.normalize()
        } else {
            Vector3::y()
        };
        let colour = colour(t);
        vertices.extend(p.map(|corner| SurfaceVertex {
            position: corner.into(),
            normal: normal.into(),
            colour,
        }));
    }
}

/// A texture holding `image`, for the fringes to read.
fn texture_of(gpu: &Gpu, image: &RgbaImage) -> wgpu::TextureView {
    let texture = gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("backdrop texture"),
            size: wgpu::Extent3d {
                width: image.width(),
                height: image.height(),
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: COLOR_FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        image.as_raw(),
    );
    texture.create_view(&Default::default())
}

/// The bind group of the uniforms and the backdrop texture `backdrop`.
fn bind_group(gpu: &Gpu, pipelines: &Pipelines, backdrop: &wgpu::TextureView) -> wgpu::BindGroup {
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("globals and backdrop bind group"),
        layout: &pipelines.layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: pipelines.uniforms.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(backdrop),
            },
        ],
    })
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
