// Thin lines as screen-space quads: each instance is one segment, expanded
// to a rectangle of its width in pixels (with square caps), pulled slightly
// towards the eye so that edges win the depth test against their own faces.

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

struct LineIn {
    @location(0) start: vec3<f32>,
    @location(1) end: vec3<f32>,
    @location(2) colour: vec4<f32>,
    @location(3) width: f32,
};

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec4<f32>,
};

fn pulled(p: vec3<f32>) -> vec4<f32> {
    let towards_eye = g.eye.xyz - p * g.eye.w;
    return g.view_proj * vec4<f32>(p + towards_eye * g.viewport.w, 1.0);
}

@vertex
fn vs_main(@builtin(vertex_index) index: u32, line: LineIn) -> VsOut {
    // (end?, side) per corner of the two triangles.
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(0.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(0.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(0.0, 1.0),
    );
    let corner = corners[index];
    let a = pulled(line.start);
    let b = pulled(line.end);
    let half_size = 0.5 * g.viewport.xy;
    let pa = a.xy / a.w * half_size;
    let pb = b.xy / b.w * half_size;
    let delta = pb - pa;
    let length_px = length(delta);
    var direction = vec2<f32>(1.0, 0.0);
    if length_px > 1e-6 {
        direction = delta / length_px;
    }
    let normal = vec2<f32>(-direction.y, direction.x);
    let half_width = 0.5 * line.width;
    var base = a;
    var cap = -half_width;
    if corner.x > 0.5 {
        base = b;
        cap = half_width;
    }
    let offset_px = normal * (corner.y * half_width) + direction * cap;
    var out: VsOut;
    out.clip = vec4<f32>(base.xy + offset_px / half_size * base.w, base.zw);
    out.colour = line.colour;
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    return in.colour;
}
