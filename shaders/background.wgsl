// Background: a full-screen triangle shaded from sky_top to sky_bottom.

// `Globals` and its binding `g` come from globals.wgsl, prepended when loaded.

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    // 0 at the top of the image, 1 at the bottom.
    @location(0) v: f32,
};

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> VsOut {
    // (-1, -1), (3, -1), (-1, 3): covers the whole viewport, the tile's
    // target when a tile is drawn (see `to_tile`).
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    let ndc = uv * 2.0 - 1.0;
    // The same point in the whole image (`ndc` itself when the whole image
    // is drawn).
    let whole_y = (ndc.y - g.tile.w) / g.tile.y;
    var out: VsOut;
    out.clip = vec4<f32>(ndc, 1.0, 1.0);
    out.v = 0.5 - 0.5 * whole_y;
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    let t = clamp(in.v, 0.0, 1.0);
    return vec4<f32>(mix(g.sky_top.rgb, g.sky_bottom.rgb, t * t * (3.0 - 2.0 * t)), 1.0);
}
