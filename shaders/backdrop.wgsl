// 2D body tile: the run's fixed backdrop (background, ground and ground
// line, drawn once) drawn into the tile's target under the body, pixel for
// pixel from the tile's place in the whole image (the pass is scissored to
// the tile; see src/render/body_tile.rs for why this is not a texture copy).

// `Globals` and its binding `g` come from globals.wgsl, prepended when loaded.

@group(1) @binding(0) var backdrop: texture_2d<f32>;

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    // (-1, -1), (3, -1), (-1, 3): covers the whole target.
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 1.0, 1.0);
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(floor(frag.xy)) + vec2<i32>(g.tile_origin.xy);
    return textureLoad(backdrop, pixel, 0);
}
