// Filled triangles: per-element colour, flat shaded with a key light, a
// hemispherical ambient and a faint highlight in 3D; unlit in 2D.

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

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) colour: vec3<f32>,
};

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) colour: vec3<f32>,
};

@vertex
fn vs_main(in: VertexIn) -> VsOut {
    var out: VsOut;
    out.clip = g.view_proj * vec4<f32>(in.position, 1.0);
    out.world = in.position;
    out.normal = in.normal;
    out.colour = in.colour;
    return out;
}

@fragment
fn fs_main(in: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var n = normalize(in.normal);
    if !front {
        n = -n;
    }
    let l = normalize(g.light.xyz);
    let v = normalize(g.eye.xyz - in.world * g.eye.w);
    let h = normalize(l + v);
    let diffuse = max(dot(n, l), 0.0);
    let ambient = mix(0.30, 0.50, 0.5 + 0.5 * n.y);
    let highlight = 0.10 * pow(max(dot(n, h), 0.0), 40.0);
    let lit = in.colour * (ambient + 0.58 * diffuse) + vec3<f32>(highlight);
    return vec4<f32>(mix(in.colour, lit, g.light.w), 1.0);
}
