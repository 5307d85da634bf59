//! [`Renderer`]: owns the device, pipelines and targets, and draws one
//! [`RenderFrame`] into an RGBA8 image.
//!
//! One frame reads as one straight line: fill the vertex and uniform
//! buffers, encode the pass (background, ground, surface, edges) into a 4x
//! MSAA target resolved to `Rgba8UnormSrgb`, submit and wait; copy the
//! resolved texture to a buffer with rows padded to
//! `COPY_BYTES_PER_ROW_ALIGNMENT`, map it, wait, strip the padding; then draw
//! the legend on the CPU. (Two submissions instead of one cost next to
//! nothing and let [`Renderer::render_timed`] time drawing and readback
//! apart.)
//!
//! Colours are computed on the CPU (viridis in sRGB, converted to linear);
//! shaders work in linear light and the sRGB target encodes on write, so an
//! unlit 2D pixel reads back as the colour map's own sRGB value.

use super::camera::{self, Bounds, Framing, View};
use super::colormap::{srgb_to_linear3, viridis};
use super::gpu::{Gpu, shared_gpu};
use super::legend::Legend;
use super::{Camera, Colouring, RenderError, RenderFrame, RenderMesh, RenderSettings};
use bytemuck::{Pod, Zeroable};
use image::RgbaImage;
use nalgebra::{Vector3, Vector4};
use std::sync::Arc;
use std::time::{Duration, Instant};

const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Colour of mesh edges, sRGB.
const EDGE_SRGB: [f32; 3] = [0.08, 0.08, 0.10];
/// Colour of elements whose value is NaN, sRGB.
const NAN_SRGB: [f32; 3] = [0.55, 0.55, 0.55];

/// Per-run uniforms (see `Globals` in the shaders). Every field is a 16-byte
/// vector or a matrix of them, so the layout has no implicit padding.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct Globals {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    light: [f32; 4],
    viewport: [f32; 4],
    ground: [f32; 4],
    ground_center: [f32; 4],
    shadow: [f32; 4],
    shadow_params: [f32; 4],
    sky_top: [f32; 4],
    sky_bottom: [f32; 4],
    ground_light: [f32; 4],
    ground_dark: [f32; 4],
}

/// One corner of a filled triangle.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct SurfaceVertex {
    position: [f32; 3],
    normal: [f32; 3],
    colour: [f32; 3],
}

/// One line segment (instanced).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct LineInstance {
    start: [f32; 3],
    end: [f32; 3],
    colour: [f32; 4],
    width: f32,
}

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
    vertex_count: usize,
    range: [f32; 2],
    legend: Option<Legend>,
    globals: Globals,
    ground_line: Option<LineInstance>,
    edge_colour: [f32; 4],
    edge_width: f32,
    resources: Resources,
    surface_scratch: Vec<SurfaceVertex>,
    line_scratch: Vec<LineInstance>,
    colour_scratch: Vec<[f32; 3]>,
}

/// A shader module from `shaders/NAME.wgsl` with `shaders/globals.wgsl`
/// (the uniform block every shader shares) prepended, at compile time.
macro_rules! shader {
    ($name:literal) => {
        wgpu::ShaderModuleDescriptor {
            label: Some($name),
            source: wgpu::ShaderSource::Wgsl(std::borrow::Cow::Borrowed(concat!(
                include_str!("../../shaders/globals.wgsl"),
                include_str!(concat!("../../shaders/", $name, ".wgsl"))
            ))),
        }
    };
}

struct Resources {
    bind_group: wgpu::BindGroup,
    uniforms: wgpu::Buffer,
    background: wgpu::RenderPipeline,
    ground: Option<wgpu::RenderPipeline>,
    surface: wgpu::RenderPipeline,
    line: wgpu::RenderPipeline,
    surface_vertices: wgpu::Buffer,
    line_instances: wgpu::Buffer,
    /// Multisampled colour target (`None` without MSAA).
    msaa_view: Option<wgpu::TextureView>,
    resolved: wgpu::Texture,
    resolved_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
    readback: wgpu::Buffer,
    padded_bytes_per_row: u32,
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
        let vertex_count = validate(settings, mesh, frames)?;
        let gpu = shared_gpu()?;
        if settings.width > gpu.max_texture_side || settings.height > gpu.max_texture_side {
            return Err(RenderError::ImageTooLarge {
                width: settings.width,
                height: settings.height,
                max: gpu.max_texture_side,
            });
        }
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
        let first_bounds = Bounds::of_points(frames[0].positions.iter()).unwrap_or(bounds);
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
        let edge_colour = {
            let c = srgb_to_linear3(EDGE_SRGB);
            [c[0], c[1], c[2], edge_alpha]
        };

        let resources = Resources::new(&gpu, settings, dimension, mesh)?;
        Ok(Renderer {
            gpu,
            settings: settings.clone(),
            mesh: mesh.clone(),
            vertex_count,
            range,
            legend,
            globals,
            ground_line,
            edge_colour,
            edge_width,
            resources,
            surface_scratch: Vec::with_capacity(mesh.triangles.len() * 3),
            line_scratch: Vec::with_capacity(mesh.edges.len() + 1),
            colour_scratch: Vec::with_capacity(mesh.element_count),
        })
    }

    /// The adapter this renderer draws with (name, backend, driver, type).
    pub fn adapter_description(&self) -> &str {
        &self.gpu.description
    }

    /// The colour range, fixed for the run (for the legend or a caption).
    pub fn colour_range(&self) -> [f32; 2] {
        self.range
    }

    /// Image width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.settings.width, self.settings.height)
    }

    /// Draws one frame.
    pub fn render(&mut self, frame: &RenderFrame) -> Result<RgbaImage, RenderError> {
        self.render_timed(frame).map(|(image, _)| image)
    }

    /// Draws one frame and says how long each stage took (for benchmarks).
    pub fn render_timed(
        &mut self,
        frame: &RenderFrame,
    ) -> Result<(RgbaImage, FrameTimings), RenderError> {
        let start = Instant::now();
        self.check_frame(frame)?;
        self.fill_buffers(frame);
        let device = &self.gpu.device;
        let queue = &self.gpu.queue;
        let r = &self.resources;
        let (width, height) = (self.settings.width, self.settings.height);

        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out_of_memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("frame encoder"),
        });
        {
            let (view, resolve_target) = match &r.msaa_view {
                Some(msaa) => (msaa, Some(&r.resolved_view)),
                None => (&r.resolved_view, None),
            };
            let sky = self.globals.sky_top;
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("frame pass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: sky[0] as f64,
                            g: sky[1] as f64,
                            b: sky[2] as f64,
                            a: 1.0,
                        }),
                        store: wgpu::StoreOp::Discard,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &r.depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &r.bind_group, &[]);
            // A plain background is the clear colour already.
            if self.globals.sky_top != self.globals.sky_bottom {
                pass.set_pipeline(&r.background);
                pass.draw(0..3, 0..1);
            }
            if let Some(ground) = &r.ground {
                pass.set_pipeline(ground);
                pass.draw(0..6, 0..1);
            }
            // Instance 0 is the 2D ground line when there is one: behind the body.
            let ground_lines = u32::from(self.ground_line.is_some());
            if ground_lines > 0 {
                pass.set_pipeline(&r.line);
                pass.set_vertex_buffer(0, r.line_instances.slice(..));
                pass.draw(0..6, 0..ground_lines);
            }
            if !self.surface_scratch.is_empty() {
                pass.set_pipeline(&r.surface);
                pass.set_vertex_buffer(0, r.surface_vertices.slice(..));
                pass.draw(0..self.surface_scratch.len() as u32, 0..1);
            }
            if self.line_scratch.len() as u32 > ground_lines {
                pass.set_pipeline(&r.line);
                pass.set_vertex_buffer(0, r.line_instances.slice(..));
                pass.draw(0..6, ground_lines..self.line_scratch.len() as u32);
            }
        }
        queue.submit([encoder.finish()]);
        check_scope(out_of_memory, "drawing a frame")?;
        check_scope(validation, "drawing a frame")?;
        wait(device, "drawing a frame")?;
        let drawn = Instant::now();

        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("readback encoder"),
        });
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &r.resolved,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &r.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(r.padded_bytes_per_row),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        queue.submit([encoder.finish()]);
        check_scope(validation, "copying a frame")?;

        let (sender, receiver) = std::sync::mpsc::channel();
        r.readback
            .map_async(wgpu::MapMode::Read, .., move |result| {
                let _ = sender.send(result);
            });
        wait(device, "reading a frame back")?;
        receiver
            .recv()
            .map_err(|_| RenderError::Gpu {
                during: "reading a frame back",
                message: "the map callback never ran".into(),
            })?
            .map_err(|e| RenderError::Gpu {
                during: "reading a frame back",
                message: e.to_string(),
            })?;
        let mut pixels = Vec::with_capacity((width * height * 4) as usize);
        {
            let mapped = r
                .readback
                .get_mapped_range(..)
                .map_err(|e| RenderError::Gpu {
                    during: "reading a frame back",
                    message: e.to_string(),
                })?;
            let row_bytes = (width * 4) as usize;
            for row in mapped
                .chunks_exact(r.padded_bytes_per_row as usize)
                .take(height as usize)
            {
                pixels.extend_from_slice(&row[..row_bytes]);
            }
        }
        r.readback.unmap();
        let mut image = RgbaImage::from_raw(width, height, pixels)
            .expect("the readback holds width x height pixels");
        let read = Instant::now();
        if let Some(legend) = &self.legend {
            legend.draw(&mut image);
        }
        let timings = FrameTimings {
            draw: drawn - start,
            readback: read - drawn,
            overlay: read.elapsed(),
        };
        Ok((image, timings))
    }

    fn check_frame(&self, frame: &RenderFrame) -> Result<(), RenderError> {
        if frame.positions.len() != self.vertex_count {
            return Err(RenderError::InvalidInput(format!(
                "a frame has {} vertex positions, the run has {}",
                frame.positions.len(),
                self.vertex_count
            )));
        }
        if matches!(self.settings.colouring, Colouring::Scalar { .. })
            && frame.element_values.len() != self.mesh.element_count
        {
            return Err(RenderError::InvalidInput(format!(
                "a frame has {} element values, the mesh has {} elements",
                frame.element_values.len(),
                self.mesh.element_count
            )));
        }
        Ok(())
    }

    /// Builds this frame's triangles, edges and uniforms and uploads them.
    fn fill_buffers(&mut self, frame: &RenderFrame) {
        let [lo, hi] = self.range;
        self.colour_scratch.clear();
        match self.settings.colouring {
            Colouring::Flat(colour) => self.colour_scratch.resize(self.mesh.element_count, colour),
            Colouring::Scalar { .. } => {
                self.colour_scratch
                    .extend(frame.element_values.iter().map(|&v| {
                        if v.is_nan() {
                            srgb_to_linear3(NAN_SRGB)
                        } else {
                            srgb_to_linear3(viridis((v - lo) / (hi - lo)))
                        }
                    }))
            }
        }

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

        self.line_scratch.clear();
        self.line_scratch.extend(self.ground_line);
        if self.settings.draw_edges && self.edge_colour[3] > 0.0 {
            self.line_scratch
                .extend(self.mesh.edges.iter().map(|&[a, b]| LineInstance {
                    start: x[a as usize],
                    end: x[b as usize],
                    colour: self.edge_colour,
                    width: self.edge_width,
                }));
        }

        if self.mesh.dimension == 3 {
            if let (Some(ground), Some(bounds)) =
                (self.settings.ground_height, Bounds::of_points(x.iter()))
            {
                let (shadow, params) = contact_shadow(&bounds, ground);
                self.globals.shadow = shadow;
                self.globals.shadow_params = params;
            }
        }

        let queue = &self.gpu.queue;
        let r = &self.resources;
        queue.write_buffer(&r.uniforms, 0, bytemuck::bytes_of(&self.globals));
        queue.write_buffer(
            &r.surface_vertices,
            0,
            bytemuck::cast_slice(&self.surface_scratch),
        );
        queue.write_buffer(
            &r.line_instances,
            0,
            bytemuck::cast_slice(&self.line_scratch),
        );
    }
}

/// Checks that mesh, frames and settings fit together; returns the vertex count.
fn validate(
    settings: &RenderSettings,
    mesh: &RenderMesh,
    frames: &[RenderFrame],
) -> Result<usize, RenderError> {
    let invalid = |message: String| Err(RenderError::InvalidInput(message));
    if settings.width == 0 || settings.height == 0 {
        return invalid(format!(
            "image size {}x{} has a zero side",
            settings.width, settings.height
        ));
    }
    if mesh.dimension != 2 && mesh.dimension != 3 {
        return invalid(format!(
            "meshes are 2D or 3D, this one says {}D",
            mesh.dimension
        ));
    }
    let Some(first) = frames.first() else {
        return invalid("there are no frames".into());
    };
    let vertex_count = first.positions.len();
    if mesh.triangle_element.len() != mesh.triangles.len() {
        return invalid(format!(
            "the mesh has {} triangles but {} triangle elements",
            mesh.triangles.len(),
            mesh.triangle_element.len()
        ));
    }
    if let Some(t) = mesh
        .triangles
        .iter()
        .flatten()
        .chain(mesh.edges.iter().flatten())
        .find(|&&v| v as usize >= vertex_count)
    {
        return invalid(format!(
            "the mesh refers to vertex {t}, but frames have {vertex_count} vertices"
        ));
    }
    if let Some(e) = mesh
        .triangle_element
        .iter()
        .find(|&&e| e as usize >= mesh.element_count)
    {
        return invalid(format!(
            "a triangle refers to element {e}, but the mesh has {} elements",
            mesh.element_count
        ));
    }
    let scalar = matches!(settings.colouring, Colouring::Scalar { .. });
    for (i, frame) in frames.iter().enumerate() {
        if frame.positions.len() != vertex_count {
            return invalid(format!(
                "frame {i} has {} vertex positions, frame 0 has {vertex_count}",
                frame.positions.len()
            ));
        }
        if scalar && frame.element_values.len() != mesh.element_count {
            return invalid(format!(
                "frame {i} has {} element values, the mesh has {} elements",
                frame.element_values.len(),
                mesh.element_count
            ));
        }
    }
    if let Colouring::Scalar {
        range: Some([lo, hi]),
        ..
    } = settings.colouring
    {
        if !(lo < hi && lo.is_finite() && hi.is_finite()) {
            return invalid(format!(
                "colour range [{lo}, {hi}] must be finite and increasing"
            ));
        }
    }
    if let Colouring::Flat(c) = settings.colouring {
        if !c.iter().all(|v| v.is_finite()) {
            return invalid(format!("flat colour {c:?} is not finite"));
        }
    }
    if let Some(ground) = settings.ground_height {
        if !ground.is_finite() {
            return invalid(format!("ground height {ground} is not finite"));
        }
    }
    Ok(vertex_count)
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

/// Blocks until the GPU has finished all submitted work.
fn wait(device: &wgpu::Device, during: &'static str) -> Result<(), RenderError> {
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map(|_| ())
        .map_err(|e| RenderError::Gpu {
            during,
            message: e.to_string(),
        })
}

fn check_scope(scope: wgpu::ErrorScopeGuard, during: &'static str) -> Result<(), RenderError> {
    match pollster::block_on(scope.pop()) {
        None => Ok(()),
        Some(error) => Err(RenderError::Gpu {
            during,
            message: error.to_string(),
        }),
    }
}

impl Resources {
    fn new(
        gpu: &Gpu,
        settings: &RenderSettings,
        dimension: usize,
        mesh: &RenderMesh,
    ) -> Result<Self, RenderError> {
        let device = &gpu.device;
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out_of_memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let (width, height) = (settings.width, settings.height);
        let samples = gpu.sample_count;

        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("globals uniform buffer"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals bind group layout"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<Globals>() as u64),
                },
                count: None,
            }],
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals bind group"),
            layout: &bind_group_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("render pipeline layout"),
            bind_group_layouts: &[Some(&bind_group_layout)],
            immediate_size: 0,
        });

        let builder = PipelineBuilder {
            device,
            layout: &layout,
            samples,
        };
        let background = builder.build(
            "background pipeline",
            &device.create_shader_module(shader!("background")),
            &[],
            None,
            false,
        );
        let ground = settings.ground_height.map(|_| {
            if dimension == 2 {
                builder.build(
                    "2D ground pipeline",
                    &device.create_shader_module(shader!("ground2d")),
                    &[],
                    Some(wgpu::BlendState::ALPHA_BLENDING),
                    false,
                )
            } else {
                builder.build(
                    "3D ground pipeline",
                    &device.create_shader_module(shader!("ground3d")),
                    &[],
                    None,
                    true,
                )
            }
        });
        let surface = builder.build(
            "surface pipeline",
            &device.create_shader_module(shader!("surface")),
            &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<SurfaceVertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x3],
            })],
            None,
            true,
        );
        let line = builder.build(
            "line pipeline",
            &device.create_shader_module(shader!("line")),
            &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<LineInstance>() as u64,
                step_mode: wgpu::VertexStepMode::Instance,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Float32],
            })],
            Some(wgpu::BlendState::ALPHA_BLENDING),
            true,
        );

        let buffer = |label: &'static str, size: usize, usage: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: (size as u64)
                    .max(64)
                    .next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT),
                usage,
                mapped_at_creation: false,
            })
        };
        let vertex_usage = wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST;
        let surface_vertices = buffer(
            "surface vertex buffer",
            mesh.triangles.len() * 3 * std::mem::size_of::<SurfaceVertex>(),
            vertex_usage,
        );
        let line_instances = buffer(
            "line instance buffer",
            (mesh.edges.len() + 1) * std::mem::size_of::<LineInstance>(),
            vertex_usage,
        );

        let size = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        let texture = |label: &'static str, format, sample_count, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let msaa_view = (samples > 1).then(|| {
            texture(
                "multisampled colour target",
                COLOR_FORMAT,
                samples,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            )
            .create_view(&wgpu::TextureViewDescriptor {
                label: Some("multisampled colour view"),
                ..Default::default()
            })
        });
        let resolved = texture(
            "resolved colour target",
            COLOR_FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let resolved_view = resolved.create_view(&wgpu::TextureViewDescriptor {
            label: Some("resolved colour view"),
            ..Default::default()
        });
        let depth_view = texture(
            "depth target",
            DEPTH_FORMAT,
            samples,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        )
        .create_view(&wgpu::TextureViewDescriptor {
            label: Some("depth view"),
            ..Default::default()
        });

        let padded_bytes_per_row = (width * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback buffer"),
            size: padded_bytes_per_row as u64 * height as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });

        check_scope(out_of_memory, "creating render targets")?;
        check_scope(validation, "creating pipelines and targets")?;
        Ok(Resources {
            bind_group,
            uniforms,
            background,
            ground,
            surface,
            line,
            surface_vertices,
            line_instances,
            msaa_view,
            resolved,
            resolved_view,
            depth_view,
            readback,
            padded_bytes_per_row,
        })
    }
}

struct PipelineBuilder<'a> {
    device: &'a wgpu::Device,
    layout: &'a wgpu::PipelineLayout,
    samples: u32,
}

impl PipelineBuilder<'_> {
    /// A triangle-list pipeline. Depth-tested ones test `LessEqual` and
    /// write depth; the others (background, 2D ground) are painted in order.
    fn build(
        &self,
        label: &'static str,
        module: &wgpu::ShaderModule,
        buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
        blend: Option<wgpu::BlendState>,
        depth_tested: bool,
    ) -> wgpu::RenderPipeline {
        self.device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(self.layout),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(depth_tested),
                    depth_compare: Some(if depth_tested {
                        wgpu::CompareFunction::LessEqual
                    } else {
                        wgpu::CompareFunction::Always
                    }),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: self.samples,
                    ..Default::default()
                },
                fragment: Some(wgpu::FragmentState {
                    module,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: COLOR_FORMAT,
                        blend,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
    }
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

    #[test]
    fn globals_layout_has_no_padding() {
        assert_eq!(std::mem::size_of::<Globals>(), 64 + 11 * 16);
        assert_eq!(std::mem::size_of::<LineInstance>(), 44);
        assert_eq!(std::mem::size_of::<SurfaceVertex>(), 36);
    }
}
