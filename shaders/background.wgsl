// Background: a full-screen triangle shaded from sky_top to sky_bottom.

// Per-run uniforms, identical in every shader (see `Globals` in src/render/renderer.rs).
struct Globals {
    view_proj: mat4x4<f32>,
    // Eye position (w = 1) or unit direction towards the viewer (w = 0).
    eye: vec4<f32>,
    // Direction towards the key light; w: how much lighting applies (0 in 2D).
    light: vec4<f32>,
    // Image width and height in pixels, pixel scale (height / 720), line pull towards the eye.
    viewport: vec4<f32>,
    // Ground height, checker tile size, fade start and end distance (3D).
    ground: vec4<f32>,
    // Ground centre x and z, quad half extent, ground surface pixel row (2D).
    ground_center: vec4<f32>,
    // Contact shadow centre x and z, radius x and z.
    shadow: vec4<f32>,
    // Contact shadow strength and softness.
    shadow_params: vec4<f32>,
    // Background at the top and bottom of the image, linear RGB.
    sky_top: vec4<f32>,
    sky_bottom: vec4<f32>,
    // The two ground colours (fill and hatching in 2D, checker in 3D), linear RGB.
    ground_light: vec4<f32>,
    ground_dark: vec4<f32>,
};

@group(0) @binding(0) var<uniform> g: Globals;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    // 0 at the top of the image, 1 at the bottom.
    @location(0) v: f32,
};

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> VsOut {
    // (-1, -1), (3, -1), (-1, 3): covers the whole viewport.
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    let ndc = uv * 2.0 - 1.0;
    var out: VsOut;
    out.clip = vec4<f32>(ndc, 1.0, 1.0);
    out.v = 0.5 - 0.5 * ndc.y;
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    let t = clamp(in.v, 0.0, 1.0);
    return vec4<f32>(mix(g.sky_top.rgb, g.sky_bottom.rgb, t * t * (3.0 - 2.0 * t)), 1.0);
}
