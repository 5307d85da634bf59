// Per-run uniforms shared by every shader: src/render/pipelines.rs prepends
// this file to each of them. Matches `Globals` there.
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
    // Frame tile (src/render/frame_target.rs): clip-space scale (xy) and
    // offset (zw) from the whole image to the tile's target; (1, 1, 0, 0)
    // when the whole image is drawn.
    tile: vec4<f32>,
    // The tile's top-left pixel in the whole image (xy).
    tile_origin: vec4<f32>,
};

@group(0) @binding(0) var<uniform> g: Globals;

// A clip-space position of the whole image moved into the tile's target
// (unchanged, bit for bit, when the whole image is drawn).
fn to_tile(clip: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(clip.xy * g.tile.xy + g.tile.zw * clip.w, clip.zw);
}
