//! [`Pipelines`]: the pipelines and buffers of one
//! [`Renderer`](super::Renderer), the data layouts they consume, and
//! [`Pipelines::record`], the order a pass draws them in.
//!
//! Everything here is made once per run, sized for the mesh: one uniform
//! buffer of [`Globals`] shared by every shader, a pipeline per layer and
//! vertex buffers for what a frame fills in. Every pipeline has one bind
//! group layout: the uniforms, and the run's backdrop texture, which only
//! the 2D fringes read. The target they draw into is a tile of the image
//! (`frame_target`), the same for 2D and 3D but for its samples:
//!
//! - **3D**: 4x MSAA with a depth target. The opaque layers are drawn
//!   nearest first — surface (bodies and obstacles), ground, background —
//!   so that a software rasteriser shades each sample about once; each
//!   pipeline's depth test ([`DepthTest`]) gives the image that painting
//!   them back to front would. The edge lines come last.
//! - **2D**: one sample per pixel, no depth (everything lies in the plane
//!   z = 0 and is painted back to front): background, ground, ground line,
//!   the obstacles' translucent fill and outlines, then the bodies, whose
//!   triangles, boundary fringes and edge lines are anti-aliased in their
//!   shaders (`body_coverage`, which says why not 4x MSAA).
//!
//! The uniform and vertex types are `#[repr(C)]` `bytemuck::Pod` and match
//! the WGSL structs in `shaders/` field for field.

use super::body_coverage::{BodyVertex, FringeInstance};
use super::gpu::{Gpu, check_scope};
use super::{RenderError, RenderMesh, RenderSettings};
use bytemuck::{Pod, Zeroable};
use std::ops::Range;

/// Format of the colour targets: shaders write linear light, the target
/// encodes sRGB.
pub(super) const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
pub(super) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Per-run uniforms (see `Globals` in the shaders). Every field is a 16-byte
/// vector or a matrix of them, so the layout has no implicit padding.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(super) struct Globals {
    pub view_proj: [[f32; 4]; 4],
    pub eye: [f32; 4],
    pub light: [f32; 4],
    pub viewport: [f32; 4],
    pub ground: [f32; 4],
    pub ground_center: [f32; 4],
    pub shadow: [f32; 4],
    pub shadow_params: [f32; 4],
    pub sky_top: [f32; 4],
    pub sky_bottom: [f32; 4],
    pub ground_light: [f32; 4],
    pub ground_dark: [f32; 4],
    pub tile: [f32; 4],
    pub tile_origin: [f32; 4],
}

impl Globals {
    /// `tile` for drawing the whole image: clip positions unchanged.
    pub const WHOLE_IMAGE: [f32; 4] = [1.0, 1.0, 0.0, 0.0];
}

/// One corner of a shaded triangle (3D bodies and obstacles, the 2D
/// obstacles' fill): colour linear, with alpha.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(super) struct SurfaceVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub colour: [f32; 4],
}

/// One line segment (instanced).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(super) struct LineInstance {
    pub start: [f32; 3],
    pub end: [f32; 3],
    pub colour: [f32; 4],
    pub width: f32,
}

/// What one pass draws from the filled buffers: vertex and instance counts.
/// The line instances are the ground line, then the obstacles' edges, then
/// the bodies'.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct Contents {
    /// Whether the background is a gradient (a plain one is the clear colour).
    pub background: bool,
    /// Whether the ground is drawn.
    pub ground: bool,
    /// The surface's vertices: the 2D bodies', or 3D bodies and obstacles.
    pub surface: u32,
    /// 2D: the bodies' boundary fringes, and the obstacles' fill vertices.
    pub fringes: u32,
    pub obstacle_fill: u32,
    /// The ground line, the obstacles' edges and the bodies' edges.
    pub ground_lines: Range<u32>,
    pub obstacle_lines: Range<u32>,
    pub body_lines: Range<u32>,
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

/// The GPU objects a renderer draws with, fixed for its run.
pub(super) struct Pipelines {
    /// The bind group layout: uniforms (binding 0), backdrop (binding 1).
    pub layout: wgpu::BindGroupLayout,
    pub uniforms: wgpu::Buffer,
    /// Samples per pixel of the target, and whether it has depth (3D).
    pub samples: u32,
    pub depth: bool,
    background: wgpu::RenderPipeline,
    ground: Option<wgpu::RenderPipeline>,
    surface: wgpu::RenderPipeline,
    line: wgpu::RenderPipeline,
    /// 2D: the fringes and the obstacles' translucent fill.
    fringe: Option<wgpu::RenderPipeline>,
    obstacle_fill: Option<wgpu::RenderPipeline>,
    /// 2D: [`BodyVertex`]; 3D: [`SurfaceVertex`].
    pub surface_vertices: wgpu::Buffer,
    pub fringe_instances: wgpu::Buffer,
    pub obstacle_vertices: wgpu::Buffer,
    pub line_instances: wgpu::Buffer,
}

impl Pipelines {
    /// Creates pipelines and buffers for `mesh`, with a ground pipeline when
    /// the settings have a ground; `samples` per pixel in 3D.
    pub fn new(
        gpu: &Gpu,
        settings: &RenderSettings,
        mesh: &RenderMesh,
    ) -> Result<Self, RenderError> {
        let device = &gpu.device;
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out_of_memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let depth = mesh.dimension == 3;
        let samples = if depth { gpu.sample_count } else { 1 };

        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("globals uniform buffer"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let visible = wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals and backdrop bind group layout"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: visible,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: wgpu::BufferSize::new(
                            std::mem::size_of::<Globals>() as u64
                        ),
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("render pipeline layout"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let builder = PipelineBuilder {
            device,
            layout: &pipeline_layout,
            samples,
            depth,
        };
        let blend = Some(wgpu::BlendState::ALPHA_BLENDING);
        let surface_module = device.create_shader_module(shader!("surface"));
        let surface_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<SurfaceVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4],
        };
        let line_module = device.create_shader_module(shader!("line"));
        let line_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<LineInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Float32],
        };
        let background = builder.build(
            "background pipeline",
            &device.create_shader_module(shader!("background")),
            MAIN,
            &[],
            None,
            DepthTest::FarPlaneOnly,
        );
        let ground = settings.ground_height.map(|_| {
            if depth {
                let module = device.create_shader_module(shader!("ground3d"));
                let test = DepthTest::NearestDrawnBehindSurface;
                builder.build("3D ground pipeline", &module, MAIN, &[], None, test)
            } else {
                let module = device.create_shader_module(shader!("ground2d"));
                let test = DepthTest::None;
                builder.build("2D ground pipeline", &module, MAIN, &[], blend, test)
            }
        });
        let (surface, line, fringe, obstacle_fill);
        if depth {
            surface = builder.build(
                "surface pipeline",
                &surface_module,
                MAIN,
                &[Some(surface_layout)],
                None,
                DepthTest::Nearest,
            );
            line = builder.build(
                "line pipeline",
                &line_module,
                MAIN,
                &[Some(line_layout)],
                blend,
                DepthTest::Nearest,
            );
            (fringe, obstacle_fill) = (None, None);
        } else {
            let body2d = device.create_shader_module(shader!("body2d"));
            surface = builder.build(
                "2D body surface pipeline",
                &body2d,
                ("vs_surface", "fs_surface"),
                &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<BodyVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![
                        0 => Float32x2, 1 => Float32x3, 2 => Float32x3,
                        3 => Float32x4, 4 => Float32x4, 5 => Float32x4
                    ],
                })],
                None,
                DepthTest::None,
            );
            fringe = Some(builder.build(
                "2D body fringe pipeline",
                &body2d,
                ("vs_fringe", "fs_fringe"),
                &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<FringeInstance>() as u64,
                    step_mode: wgpu::VertexStepMode::Instance,
                    attributes: &wgpu::vertex_attr_array![
                        0 => Float32x2, 1 => Float32x2, 2 => Float32x2, 3 => Float32x3
                    ],
                })],
                blend,
                DepthTest::None,
            ));
            line = builder.build(
                "2D line pipeline",
                &line_module,
                ("vs_coverage", "fs_coverage"),
                &[Some(line_layout)],
                blend,
                DepthTest::None,
            );
            obstacle_fill = Some(builder.build(
                "2D obstacle fill pipeline",
                &surface_module,
                MAIN,
                &[Some(surface_layout)],
                blend,
                DepthTest::None,
            ));
        }

        let (triangles, obstacles) = (mesh.triangles.len(), mesh.obstacle_triangles.len());
        let (surface_vertices, fringe_instances, obstacle_vertices) = if depth {
            let surface = 3 * (triangles + obstacles);
            (
                vertex_buffer::<SurfaceVertex>(device, "surface vertex buffer", surface),
                vertex_buffer::<u8>(device, "unused fringe buffer", 0),
                vertex_buffer::<u8>(device, "unused obstacle buffer", 0),
            )
        } else {
            (
                vertex_buffer::<BodyVertex>(device, "2D body vertex buffer", 3 * triangles),
                // At most every edge of every triangle is on the boundary.
                vertex_buffer::<FringeInstance>(device, "2D fringe buffer", 3 * triangles),
                vertex_buffer::<SurfaceVertex>(device, "2D obstacle buffer", 3 * obstacles),
            )
        };
        let lines = 1 + mesh.obstacle_edges.len() + mesh.edges.len();
        let line_instances = vertex_buffer::<LineInstance>(device, "line instance buffer", lines);

        check_scope(out_of_memory, "creating pipelines and buffers")?;
        check_scope(validation, "creating pipelines and buffers")?;
        Ok(Pipelines {
            layout,
            uniforms,
            samples,
            depth,
            background,
            ground,
            surface,
            line,
            fringe,
            obstacle_fill,
            surface_vertices,
            fringe_instances,
            obstacle_vertices,
            line_instances,
        })
    }

    /// Records `contents` into `pass` (see the module documentation for the
    /// order).
    pub fn record(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        bind_group: &wgpu::BindGroup,
        c: &Contents,
    ) {
        pass.set_bind_group(0, bind_group, &[]);
        // Each layer: its pipeline (none: not drawn), vertex buffer, vertices, instances.
        type Layer<'a> = (
            Option<&'a wgpu::RenderPipeline>,
            Option<&'a wgpu::Buffer>,
            Range<u32>,
            Range<u32>,
        );
        let surface: Layer = (
            Some(&self.surface),
            Some(&self.surface_vertices),
            0..c.surface,
            0..1,
        );
        let ground: Layer = (self.ground.as_ref().filter(|_| c.ground), None, 0..6, 0..1);
        let background: Layer = (c.background.then_some(&self.background), None, 0..3, 0..1);
        let lines = |instances: Range<u32>| -> Layer {
            (
                Some(&self.line),
                Some(&self.line_instances),
                0..6,
                instances,
            )
        };
        let layers = if self.depth {
            let edges = c.obstacle_lines.start..c.body_lines.end;
            vec![surface, ground, background, lines(edges)]
        } else {
            let fill = &self.obstacle_fill;
            let fringes = &self.fringe;
            vec![
                background,
                ground,
                lines(c.ground_lines.clone()),
                (
                    fill.as_ref(),
                    Some(&self.obstacle_vertices),
                    0..c.obstacle_fill,
                    0..1,
                ),
                lines(c.obstacle_lines.clone()),
                surface,
                (
                    fringes.as_ref(),
                    Some(&self.fringe_instances),
                    0..6,
                    0..c.fringes,
                ),
                lines(c.body_lines.clone()),
            ]
        };
        for (pipeline, buffer, vertices, instances) in layers {
            if let Some(pipeline) = pipeline
                && !vertices.is_empty()
                && !instances.is_empty()
            {
                pass.set_pipeline(pipeline);
                if let Some(buffer) = buffer {
                    pass.set_vertex_buffer(0, buffer.slice(..));
                }
                pass.draw(vertices, instances);
            }
        }
    }
}

/// A vertex buffer for `items` values of `T`, written each frame.
fn vertex_buffer<T>(device: &wgpu::Device, label: &str, items: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: ((items * std::mem::size_of::<T>()) as u64)
            .max(64)
            .next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT),
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// The vertex and fragment entry points of most shaders.
const MAIN: (&str, &str) = ("vs_main", "fs_main");

/// How a pipeline meets the depth target. Only 3D has one; in 2D every
/// pipeline paints in draw order and this is ignored.
///
/// In 3D the opaque layers are drawn nearest first — surface, ground,
/// background — so that a software rasteriser shades and writes each sample
/// about once: the early depth test rejects the ground behind the body and
/// the background behind either. The tests are chosen so that the image is
/// the one painting background, ground and surface in that order would give.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum DepthTest {
    /// No test, no write (2D layers).
    None,
    /// Tested `LessEqual` and written: on a tie the later draw wins.
    Nearest,
    /// Tested `Less` and written, for the ground drawn after the surface: on
    /// a tie the surface keeps the sample, as when it was drawn over the
    /// ground.
    NearestDrawnBehindSurface,
    /// Tested `LessEqual` at the far plane, not written: the background,
    /// drawn after every opaque layer, fills only samples none of them
    /// covered (still at the cleared depth 1).
    FarPlaneOnly,
}

impl DepthTest {
    fn state(self) -> wgpu::DepthStencilState {
        let (write, compare) = match self {
            DepthTest::None => (false, wgpu::CompareFunction::Always),
            DepthTest::Nearest => (true, wgpu::CompareFunction::LessEqual),
            DepthTest::NearestDrawnBehindSurface => (true, wgpu::CompareFunction::Less),
            DepthTest::FarPlaneOnly => (false, wgpu::CompareFunction::LessEqual),
        };
        wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(write),
            depth_compare: Some(compare),
            stencil: Default::default(),
            bias: Default::default(),
        }
    }
}

#[derive(Clone, Copy)]
struct PipelineBuilder<'a> {
    device: &'a wgpu::Device,
    layout: &'a wgpu::PipelineLayout,
    samples: u32,
    /// Whether the pass has a depth target.
    depth: bool,
}

impl PipelineBuilder<'_> {
    /// A triangle-list pipeline with the named vertex and fragment entry
    /// points, meeting the depth target (3D) as `depth` says.
    fn build(
        &self,
        label: &'static str,
        module: &wgpu::ShaderModule,
        (vertex_entry, fragment_entry): (&str, &str),
        buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
        blend: Option<wgpu::BlendState>,
        depth: DepthTest,
    ) -> wgpu::RenderPipeline {
        self.device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(self.layout),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some(vertex_entry),
                    compilation_options: Default::default(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: self.depth.then(|| depth.state()),
                multisample: wgpu::MultisampleState {
                    count: self.samples,
                    ..Default::default()
                },
                fragment: Some(wgpu::FragmentState {
                    module,
                    entry_point: Some(fragment_entry),
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

    #[test]
    fn globals_layout_has_no_padding() {
        assert_eq!(std::mem::size_of::<Globals>(), 64 + 13 * 16);
        assert_eq!(std::mem::size_of::<LineInstance>(), 44);
        assert_eq!(std::mem::size_of::<SurfaceVertex>(), 40);
    }
}
