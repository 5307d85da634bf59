//! [`GpuResources`]: the pipelines and buffers of one
//! [`Renderer`](super::Renderer), and the data layouts they consume.
//!
//! Everything here is created once per run, sized for the mesh: one uniform
//! buffer of [`Globals`] shared by every shader, a pipeline per layer
//! (background, ground, surface, lines) drawing into 4x MSAA
//! `Rgba8UnormSrgb` targets (with a depth target in 3D), and vertex buffers
//! for the surface's triangle corners and the instanced line segments. In
//! 2D also the single-sampled pipelines and buffers of the body tiles
//! ([`TileResources`]: the backdrop under a tile, surface, fringes, edge
//! lines). The targets themselves are sized for a tile or the whole image
//! and made where they are drawn into (`render_targets`).
//!
//! 2D has no depth target: everything lies in the plane z = 0 under an
//! orthographic camera and edges are not pulled towards the eye, so every
//! fragment has the same depth and the `LessEqual` test passed them all, in
//! draw order. Without it the image is the same (painter's order), and the
//! software rasteriser saves clearing and testing four depth samples per
//! pixel. In 3D each pipeline's depth test ([`DepthTest`]) lets the opaque
//! layers be drawn nearest first and still give the painter's image.
//! The uniform and vertex types are `#[repr(C)]` `bytemuck::Pod` and match
//! the WGSL structs in `shaders/` field for field.

use super::body_coverage::{BodyVertex, FringeInstance};
use super::gpu::{Gpu, check_scope};
use super::{RenderError, RenderMesh, RenderSettings};
use bytemuck::{Pod, Zeroable};

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

/// One corner of a filled triangle.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(super) struct SurfaceVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub colour: [f32; 3],
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
pub(super) struct GpuResources {
    pub bind_group: wgpu::BindGroup,
    pub uniforms: wgpu::Buffer,
    pub background: wgpu::RenderPipeline,
    /// The ground's pipeline, when the settings have a ground.
    pub ground: Option<wgpu::RenderPipeline>,
    pub surface: wgpu::RenderPipeline,
    pub line: wgpu::RenderPipeline,
    /// 2D: what body tiles are drawn with.
    pub tile: Option<TileResources>,
    pub surface_vertices: wgpu::Buffer,
    pub line_instances: wgpu::Buffer,
    /// 3D: the pipelines test and write depth (see [`DepthTest`]).
    pub depth: bool,
}

/// 2D: the single-sampled pipelines and buffers of the body tiles
/// (`body_tile`), anti-aliased in their shaders (`body_coverage`).
pub(super) struct TileResources {
    /// The backdrop's layers, drawn once per run into the single-sampled
    /// whole-image target: the background, the ground (anti-aliased in its
    /// shader) and the ground line (with `line`).
    pub background: wgpu::RenderPipeline,
    pub ground: Option<wgpu::RenderPipeline>,
    /// Draws the backdrop texture's pixels (bind group 1, laid out as
    /// `backdrop_layout`) into a tile, under the body.
    pub backdrop: wgpu::RenderPipeline,
    /// The backdrop texture's bind group layout (group 1), read by the
    /// fringes.
    pub backdrop_layout: wgpu::BindGroupLayout,
    /// The body's triangles, opaque.
    pub surface: wgpu::RenderPipeline,
    /// The fringes along the boundary; they read the backdrop texture too.
    pub fringe: wgpu::RenderPipeline,
    /// The edge lines, from `line_instances`.
    pub line: wgpu::RenderPipeline,
    pub body_vertices: wgpu::Buffer,
    pub fringe_instances: wgpu::Buffer,
}

impl GpuResources {
    /// Creates pipelines and buffers for `mesh`, with a ground pipeline when
    /// the settings have a ground.
    pub fn new(
        gpu: &Gpu,
        settings: &RenderSettings,
        mesh: &RenderMesh,
    ) -> Result<Self, RenderError> {
        let device = &gpu.device;
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out_of_memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
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

        let depth = mesh.dimension == 3;
        let builder = PipelineBuilder {
            device,
            layout: &layout,
            samples,
            depth,
        };
        let background_module = device.create_shader_module(shader!("background"));
        let background = builder.build(
            "background pipeline",
            &background_module,
            &[],
            None,
            DepthTest::FarPlaneOnly,
        );
        let ground = settings.ground_height.map(|_| {
            if mesh.dimension == 2 {
                builder.build(
                    "2D ground pipeline",
                    &device.create_shader_module(shader!("ground2d")),
                    &[],
                    Some(wgpu::BlendState::ALPHA_BLENDING),
                    DepthTest::None,
                )
            } else {
                builder.build(
                    "3D ground pipeline",
                    &device.create_shader_module(shader!("ground3d")),
                    &[],
                    None,
                    DepthTest::NearestDrawnBehindSurface,
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
            DepthTest::Nearest,
        );
        let line_module = device.create_shader_module(shader!("line"));
        let line_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<LineInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Float32],
        };
        let line = builder.build(
            "line pipeline",
            &line_module,
            &[Some(line_layout.clone())],
            Some(wgpu::BlendState::ALPHA_BLENDING),
            DepthTest::Nearest,
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
        let tile = (mesh.dimension == 2).then(|| {
            let single_sampled = PipelineBuilder {
                samples: 1,
                ..builder
            };
            let (backdrop_layout, with_backdrop) = backdrop_layouts(device, &bind_group_layout);
            let reading_backdrop = PipelineBuilder {
                layout: &with_backdrop,
                ..single_sampled
            };
            let backdrop = reading_backdrop.build(
                "backdrop pipeline",
                &device.create_shader_module(shader!("backdrop")),
                &[],
                None,
                DepthTest::None,
            );
            let body2d = device.create_shader_module(shader!("body2d"));
            let surface = single_sampled.build_entries(
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
            let fringe = reading_backdrop.build_entries(
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
                Some(wgpu::BlendState::ALPHA_BLENDING),
                DepthTest::None,
            );
            let line = single_sampled.build_entries(
                "2D body line pipeline",
                &line_module,
                ("vs_coverage", "fs_coverage"),
                &[Some(line_layout.clone())],
                Some(wgpu::BlendState::ALPHA_BLENDING),
                DepthTest::None,
            );
            TileResources {
                background: single_sampled.build(
                    "single-sampled background pipeline",
                    &background_module,
                    &[],
                    None,
                    DepthTest::None,
                ),
                ground: settings.ground_height.map(|_| {
                    single_sampled.build(
                        "single-sampled 2D ground pipeline",
                        &device.create_shader_module(shader!("ground2d")),
                        &[],
                        Some(wgpu::BlendState::ALPHA_BLENDING),
                        DepthTest::None,
                    )
                }),
                backdrop,
                backdrop_layout,
                surface,
                fringe,
                line,
                body_vertices: buffer(
                    "2D body vertex buffer",
                    mesh.triangles.len() * 3 * std::mem::size_of::<BodyVertex>(),
                    vertex_usage,
                ),
                // At most every edge of every triangle is on the boundary.
                fringe_instances: buffer(
                    "2D body fringe buffer",
                    mesh.triangles.len() * 3 * std::mem::size_of::<FringeInstance>(),
                    vertex_usage,
                ),
            }
        });

        check_scope(out_of_memory, "creating pipelines and buffers")?;
        check_scope(validation, "creating pipelines and buffers")?;
        Ok(GpuResources {
            bind_group,
            uniforms,
            background,
            ground,
            surface,
            line,
            tile,
            surface_vertices,
            line_instances,
            depth,
        })
    }
}

/// Bytes per row of an RGBA8 image `width` pixels wide copied to a buffer:
/// rows start at multiples of `COPY_BYTES_PER_ROW_ALIGNMENT`.
pub(super) fn padded_row_bytes(width: u32) -> u32 {
    (width * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
}

/// A mappable buffer that an RGBA8 image of `(width, height)` pixels is
/// copied into and read back from, rows [`padded_row_bytes`] apart.
pub(super) fn readback_buffer(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: u64::from(padded_row_bytes(width)) * u64::from(height),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

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

/// The bind group layout of the 2D backdrop texture (group 1), and the
/// layout of the tile pipelines that read it (group 0 is the globals').
fn backdrop_layouts(
    device: &wgpu::Device,
    globals_layout: &wgpu::BindGroupLayout,
) -> (wgpu::BindGroupLayout, wgpu::PipelineLayout) {
    let texture_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("backdrop bind group layout"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        }],
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("backdrop pipeline layout"),
        bind_group_layouts: &[Some(globals_layout), Some(&texture_layout)],
        immediate_size: 0,
    });
    (texture_layout, layout)
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
    /// A triangle-list pipeline meeting the depth target (3D) as `depth`
    /// says. Without a depth target (2D) every pipeline paints in order.
    fn build(
        &self,
        label: &'static str,
        module: &wgpu::ShaderModule,
        buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
        blend: Option<wgpu::BlendState>,
        depth: DepthTest,
    ) -> wgpu::RenderPipeline {
        self.build_entries(label, module, ("vs_main", "fs_main"), buffers, blend, depth)
    }

    /// [`PipelineBuilder::build`] with the vertex and fragment entry points
    /// named.
    fn build_entries(
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
        assert_eq!(std::mem::size_of::<SurfaceVertex>(), 36);
    }
}
