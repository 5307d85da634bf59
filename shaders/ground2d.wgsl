// 2D ground: the half-plane below the ground line, filled, with engineering
// hatching just under the surface. Drawn in screen space from the ground's
// pixel row in the whole image (a tile's pixel is moved there by its
// origin); the surface line itself is drawn by the line pipeline.

// `Globals` and its binding `g` come from globals.wgsl, prepended when loaded.

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    // A screen-wide rectangle from one pixel above the ground row down to the
    // bottom of the image: only pixels that can be ground are shaded.
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, 0.0), vec2<f32>(1.0, 0.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, 0.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    let c = corners[index];
    let top = clamp(1.0 - 2.0 * (g.ground_center.w - 1.0) / g.viewport.y, -1.0, 1.0);
    return to_tile(vec4<f32>(c.x, mix(-1.0, top, c.y), 1.0, 1.0));
}

@fragment
fn fs_main(@builtin(position) tile_frag: vec4<f32>) -> @location(0) vec4<f32> {
    // The pixel's centre in the whole image.
    let frag = tile_frag.xy + g.tile_origin.xy;
    let s = g.viewport.z;
    let below = frag.y - g.ground_center.w;
    if below < -0.5 {
        discard;
    }
    // Anti-aliased top edge (hidden under the surface line anyway).
    let cover = clamp(below + 0.5, 0.0, 1.0);
    // Diagonal stripes: distance in pixels to the nearest stripe centre.
    let spacing = 11.0 * s;
    let along = (frag.x + frag.y) / spacing;
    let distance = abs(fract(along) - 0.5) * spacing * 0.70710678;
    let half_width = max(0.75 * s, 0.6);
    let stripe = 1.0 - smoothstep(half_width - 0.6, half_width + 0.6, distance);
    let band = 16.0 * s;
    let fade = 1.0 - smoothstep(0.45 * band, band, below);
    let colour = mix(g.ground_light.rgb, g.ground_dark.rgb, stripe * fade);
    return vec4<f32>(colour, cover);
}
