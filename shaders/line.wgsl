// Thin lines as screen-space quads: each instance is one segment, expanded
// to a rectangle of its width in pixels (with square caps), pulled slightly
// towards the eye so that edges win the depth test against their own faces.

// `Globals` and its binding `g` come from globals.wgsl, prepended when loaded.

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

// Where a quad corner lies: (end?, side) per corner of the two triangles.
fn quad_corner(index: u32) -> vec2<f32> {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(0.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(0.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(0.0, 1.0),
    );
    return corners[index];
}

// A segment on the screen: its pulled clip-space ends, the same in pixels
// from the image's centre (y up), and its unit direction and normal there.
struct ScreenSegment {
    a: vec4<f32>,
    b: vec4<f32>,
    pa: vec2<f32>,
    pb: vec2<f32>,
    length_px: f32,
    direction: vec2<f32>,
    normal: vec2<f32>,
};

fn screen_segment(line: LineIn) -> ScreenSegment {
    var s: ScreenSegment;
    s.a = pulled(line.start);
    s.b = pulled(line.end);
    let half_size = 0.5 * g.viewport.xy;
    s.pa = s.a.xy / s.a.w * half_size;
    s.pb = s.b.xy / s.b.w * half_size;
    let delta = s.pb - s.pa;
    s.length_px = length(delta);
    s.direction = vec2<f32>(1.0, 0.0);
    if s.length_px > 1e-6 {
        s.direction = delta / s.length_px;
    }
    s.normal = vec2<f32>(-s.direction.y, s.direction.x);
    return s;
}

@vertex
fn vs_main(@builtin(vertex_index) index: u32, line: LineIn) -> VsOut {
    let corner = quad_corner(index);
    let s = screen_segment(line);
    let half_size = 0.5 * g.viewport.xy;
    let half_width = 0.5 * line.width;
    var base = s.a;
    var cap = -half_width;
    if corner.x > 0.5 {
        base = s.b;
        cap = half_width;
    }
    let offset_px = s.normal * (corner.y * half_width) + s.direction * cap;
    var out: VsOut;
    out.clip = to_tile(vec4<f32>(base.xy + offset_px / half_size * base.w, base.zw));
    out.colour = line.colour;
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    return in.colour;
}

// 2D body tiles draw without multisampling (body2d.wgsl): the same segment
// as a quad one pixel larger all round, each pixel covered by the share of
// it the segment's rectangle (square caps included) covers. Per axis of the
// segment the share is the overlap of the pixel's span [x − 1/2, x + 1/2]
// with the rectangle's [−h, h], exact for segments along the pixel grid.

struct CoverageOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) colour: vec4<f32>,
    // The pixel's centre from the segment's midpoint, along and across it, in pixels.
    @location(1) @interpolate(linear) local: vec2<f32>,
    // Half the rectangle's extent along (length and caps) and across, in pixels.
    @location(2) @interpolate(flat) half_extent: vec2<f32>,
};

@vertex
fn vs_coverage(@builtin(vertex_index) index: u32, line: LineIn) -> CoverageOut {
    let corner = quad_corner(index);
    let s = screen_segment(line);
    let half_width = 0.5 * line.width;
    let half_extent = vec2<f32>(0.5 * s.length_px + half_width, half_width);
    let local = vec2<f32>(corner.x * 2.0 - 1.0, corner.y) * (half_extent + 1.0);
    let p = 0.5 * (s.pa + s.pb) + s.direction * local.x + s.normal * local.y;
    var out: CoverageOut;
    out.clip = to_tile(vec4<f32>(p / (0.5 * g.viewport.xy) * s.a.w, s.a.zw));
    out.colour = line.colour;
    out.local = local;
    out.half_extent = half_extent;
    return out;
}

// The length of [x − 1/2, x + 1/2] ∩ [−h, h].
fn overlap(h: f32, x: f32) -> f32 {
    return clamp(min(h, x + 0.5) - max(-h, x - 0.5), 0.0, 1.0);
}

@fragment
fn fs_coverage(in: CoverageOut) -> @location(0) vec4<f32> {
    let coverage = overlap(in.half_extent.x, in.local.x) * overlap(in.half_extent.y, in.local.y);
    return vec4<f32>(in.colour.rgb, in.colour.a * coverage);
}
