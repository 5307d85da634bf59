//! [`Layers`]: what one multisampled pass draws from the renderer's filled
//! buffers, and [`record_layers`], the order it draws them in.

use super::gpu_resources::GpuResources;

/// What one multisampled pass draws, from the renderer's filled buffers:
/// the whole image ([`Renderer::render_multisampled`], the backdrops) or a
/// 3D tile (`scene_tile`).
pub(super) struct Layers<'a> {
    pub resources: &'a GpuResources,
    /// Whether the background is a gradient (a plain one is the clear colour).
    pub background: bool,
    pub surface_vertices: u32,
    /// The first line instances, drawn behind the body (the 2D ground line).
    pub ground_lines: u32,
    /// All line instances, the ground lines included.
    pub lines: u32,
}

/// Records `layers` into `pass`. 3D: the opaque layers nearest first, so
/// that hidden samples are rejected before they are shaded (see
/// `DepthTest`), then the edges. 2D: painted back to front.
pub(super) fn record_layers(pass: &mut wgpu::RenderPass<'_>, layers: &Layers<'_>) {
    let r = layers.resources;
    pass.set_bind_group(0, &r.bind_group, &[]);
    let draw_layer = |pass: &mut wgpu::RenderPass<'_>, pipeline, vertices| {
        pass.set_pipeline(pipeline);
        pass.draw(0..vertices, 0..1);
    };
    let draw_surface = |pass: &mut wgpu::RenderPass<'_>| {
        if layers.surface_vertices > 0 {
            pass.set_pipeline(&r.surface);
            pass.set_vertex_buffer(0, r.surface_vertices.slice(..));
            pass.draw(0..layers.surface_vertices, 0..1);
        }
    };
    let draw_lines = |pass: &mut wgpu::RenderPass<'_>, instances: std::ops::Range<u32>| {
        if !instances.is_empty() {
            pass.set_pipeline(&r.line);
            pass.set_vertex_buffer(0, r.line_instances.slice(..));
            pass.draw(0..6, instances);
        }
    };
    let background = layers.background.then_some(&r.background);
    if r.depth {
        draw_surface(pass);
        if let Some(ground) = &r.ground {
            draw_layer(pass, ground, 6);
        }
        if let Some(background) = background {
            draw_layer(pass, background, 3);
        }
    } else {
        if let Some(background) = background {
            draw_layer(pass, background, 3);
        }
        if let Some(ground) = &r.ground {
            draw_layer(pass, ground, 6);
        }
        draw_lines(pass, 0..layers.ground_lines);
        draw_surface(pass);
    }
    draw_lines(
        pass,
        layers.ground_lines..layers.lines.max(layers.ground_lines),
    );
}
