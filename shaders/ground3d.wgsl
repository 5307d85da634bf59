// 3D ground: a large quad on y = ground height with an anti-aliased checker
// (box-filtered, so it does not shimmer in the distance), fading into the
// background colour far away, darkened under the body by a soft contact
// shadow.

// `Globals` and its binding `g` come from globals.wgsl, prepended when loaded.

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> VsOut {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    let c = corners[index];
    let extent = g.ground_center.z;
    let world = vec3<f32>(g.ground_center.x + c.x * extent, g.ground.x, g.ground_center.y + c.y * extent);
    var out: VsOut;
    out.clip = to_tile(g.view_proj * vec4<f32>(world, 1.0));
    out.world = world;
    return out;
}

// Box-filtered checker in [0, 1] over a pixel footprint `w` (in tiles).
fn filtered_checker(p: vec2<f32>, w: vec2<f32>) -> f32 {
    let i = 2.0 * (abs(fract((p - 0.5 * w) * 0.5) - 0.5) - abs(fract((p + 0.5 * w) * 0.5) - 0.5)) / w;
    return 0.5 - 0.5 * i.x * i.y;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    let p = in.world.xz / g.ground.y;
    let w = fwidth(p) + vec2<f32>(1e-4);
    let checker = filtered_checker(p, w);
    var colour = mix(g.ground_light.rgb, g.ground_dark.rgb, checker);

    // Contact shadow: a soft rounded rectangle under the body.
    let q = abs(in.world.xz - g.shadow.xy) / max(g.shadow.zw, vec2<f32>(1e-6));
    let r = pow(pow(q.x, 3.0) + pow(q.y, 3.0), 1.0 / 3.0);
    let softness = g.shadow_params.y;
    let shadow = g.shadow_params.x * (1.0 - smoothstep(1.0 - softness, 1.0 + softness, r));
    colour = colour * (1.0 - shadow);

    // Fade into the background with distance from the scene.
    let distance = length(in.world.xz - g.ground_center.xy);
    let fade = smoothstep(g.ground.z, g.ground.w, distance);
    colour = mix(colour, g.sky_bottom.rgb, fade);
    return vec4<f32>(colour, 1.0);
}
