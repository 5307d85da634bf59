// The 2D body without multisampling, anti-aliased analytically: each pixel
// is shaded once, at its centre, with the colour a box filter over the
// pixel sees (src/render/body_coverage.rs; the edge lines are in
// line.wgsl, `vs_coverage`).
//
// Triangles (`vs_surface`, `fs_surface`) are opaque. Corner i carries the
// unit vector e_i, so the fragment gets the barycentric coordinates λ. The
// distance in pixels from the pixel's centre to the edge opposite corner i
// is d_i = λ_i / |∇λ_i| (positive inside; ∇ in pixels, from dpdx and
// dpdy), and the part of the pixel beyond that edge is
// o_i = clamp(1/2 − d_i, 0, 1) (exact for a straight edge and a box
// filter). Across an edge shared with another triangle that part takes the
// neighbour's colour.
//
// Fringes (`vs_fringe`, `fs_fringe`), one per boundary edge, cover the
// pixels within half a pixel of it on both sides. At signed distance s
// outwards from the edge's line, a pixel outside (s ≥ 0) gets the body's
// colour over clamp(1/2 − s, 0, 1) of it, and a pixel inside gets the
// backdrop (what lies behind the body) over clamp(1/2 + s, 0, 1) of it.
// A pixel centred on the edge is the rasteriser's to give to the triangle
// or not; the triangle discards it, so that the fringe always blends it as
// an outside one.
// Where two boundary edges meet at a convex corner, both fringes blend, and
// the body's share is the product of the two, as a box filter gives. The
// fringes of neighbouring edges meet along the normal at their common
// vertex, so a straight run of edges is blended once.

// `Globals` and its binding `g` come from globals.wgsl, prepended when loaded.

struct SurfaceIn {
    @location(0) position: vec2<f32>,
    @location(1) corner: vec3<f32>,
    @location(2) colour: vec3<f32>,
    // The colour across the edge opposite each corner (w = 1), or none: the
    // edge is on the boundary (w = 0).
    @location(3) across_0: vec4<f32>,
    @location(4) across_1: vec4<f32>,
    @location(5) across_2: vec4<f32>,
};

struct SurfaceOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(linear) corner: vec3<f32>,
    @location(1) @interpolate(flat) colour: vec3<f32>,
    @location(2) @interpolate(flat) across_0: vec4<f32>,
    @location(3) @interpolate(flat) across_1: vec4<f32>,
    @location(4) @interpolate(flat) across_2: vec4<f32>,
};

@vertex
fn vs_surface(in: SurfaceIn) -> SurfaceOut {
    var out: SurfaceOut;
    out.clip = to_tile(g.view_proj * vec4<f32>(in.position, 0.0, 1.0));
    out.corner = in.corner;
    out.colour = in.colour;
    out.across_0 = in.across_0;
    out.across_1 = in.across_1;
    out.across_2 = in.across_2;
    return out;
}

// Pixels this close to a boundary edge's line count as on it, in
// triangles and fringes alike.
const ON_THE_EDGE: f32 = 1.0 / 1024.0;

// The pixel's colour so far with the part `beyond` of it past one edge
// given to the colour across that edge (a boundary edge's fringe does that
// part).
fn across_edge(colour: vec3<f32>, beyond: f32, across: vec4<f32>) -> vec3<f32> {
    return mix(colour, across.rgb, beyond * across.w);
}

@fragment
fn fs_surface(in: SurfaceOut) -> @location(0) vec4<f32> {
    let dx = dpdx(in.corner);
    let dy = dpdy(in.corner);
    let gradient = max(sqrt(dx * dx + dy * dy), vec3<f32>(1e-20));
    let inside = in.corner / gradient;
    // A pixel centred on a boundary edge (or within rounding of it) is the
    // fringe's, whichever triangle the rasteriser gave it to.
    let interior = vec3<f32>(in.across_0.w, in.across_1.w, in.across_2.w);
    if any((inside <= vec3<f32>(ON_THE_EDGE)) & (interior < vec3<f32>(0.5))) {
        discard;
    }
    let beyond = clamp(vec3<f32>(0.5) - inside, vec3<f32>(0.0), vec3<f32>(1.0));
    var colour = in.colour;
    colour = across_edge(colour, beyond.x, in.across_0);
    colour = across_edge(colour, beyond.y, in.across_1);
    colour = across_edge(colour, beyond.z, in.across_2);
    return vec4<f32>(colour, 1.0);
}

struct FringeIn {
    @location(0) start: vec2<f32>,
    @location(1) end: vec2<f32>,
    // Any point on the body's side of the edge (the triangle's third corner).
    @location(2) inside: vec2<f32>,
    @location(3) colour: vec3<f32>,
};

struct FringeOut {
    @builtin(position) clip: vec4<f32>,
    // Signed pixels outwards from the edge's line.
    @location(0) @interpolate(linear) outward: f32,
    @location(1) @interpolate(flat) colour: vec3<f32>,
};

// How far the fringe reaches from its edge on either side, in pixels: past
// 1/2 nothing changes.
const FRINGE_REACH: f32 = 0.75;

// A whole-image position in pixels from the image's centre, y up.
fn centred_pixels(p: vec2<f32>) -> vec2<f32> {
    let clip = g.view_proj * vec4<f32>(p, 0.0, 1.0);
    return clip.xy / clip.w * 0.5 * g.viewport.xy;
}

@vertex
fn vs_fringe(@builtin(vertex_index) index: u32, fringe: FringeIn) -> FringeOut {
    // (end?, side) per corner of the two triangles.
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(0.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(0.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(0.0, 1.0),
    );
    let corner = corners[index];
    let a = centred_pixels(fringe.start);
    let b = centred_pixels(fringe.end);
    let inside = centred_pixels(fringe.inside);
    let delta = b - a;
    let length_px = length(delta);
    var normal = vec2<f32>(0.0, 0.0);
    if length_px > 1e-6 {
        normal = vec2<f32>(-delta.y, delta.x) / length_px;
    }
    if dot(inside - a, normal) > 0.0 {
        normal = -normal;
    }
    let outward = corner.y * FRINGE_REACH;
    let p = mix(a, b, corner.x) + normal * outward;
    var out: FringeOut;
    out.clip = to_tile(vec4<f32>(p / (0.5 * g.viewport.xy), 0.0, 1.0));
    out.outward = outward;
    out.colour = fringe.colour;
    return out;
}

// The run's backdrop (the image without the bodies), read where a fringe
// gives a pixel back to what lies behind the body.
@group(0) @binding(1) var backdrop: texture_2d<f32>;

@fragment
fn fs_fringe(in: FringeOut) -> @location(0) vec4<f32> {
    if in.outward > -ON_THE_EDGE {
        return vec4<f32>(in.colour, clamp(0.5 - in.outward, 0.0, 1.0));
    }
    // In the fragment stage `clip` holds the pixel's framebuffer position.
    let pixel = vec2<i32>(floor(in.clip.xy)) + vec2<i32>(g.tile_origin.xy);
    let behind = textureLoad(backdrop, pixel, 0).rgb;
    return vec4<f32>(behind, clamp(0.5 + in.outward, 0.0, 1.0));
}
