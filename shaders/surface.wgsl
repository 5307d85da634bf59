// Filled triangles: per-element colour, flat shaded with a key light, a
// hemispherical ambient and a faint highlight in 3D (bodies and obstacles,
// lit on either side); unlit in 2D (the obstacles' translucent fill). The
// colour's alpha is written out for the 2D fill to blend with.

// `Globals` and its binding `g` come from globals.wgsl, prepended when loaded.

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) colour: vec4<f32>,
};

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) colour: vec4<f32>,
};

@vertex
fn vs_main(in: VertexIn) -> VsOut {
    var out: VsOut;
    out.clip = to_tile(g.view_proj * vec4<f32>(in.position, 1.0));
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
    let lit = in.colour.rgb * (ambient + 0.58 * diffuse) + vec3<f32>(highlight);
    return vec4<f32>(mix(in.colour.rgb, lit, g.light.w), in.colour.a);
}
