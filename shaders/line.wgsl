// Lines (tool paths, edges): per-vertex sRGB colour, pulled slightly toward the viewer so that
// lines lying on a shaded surface stay visible.

struct Object {
    model: mat4x4<f32>,
    normal_matrix: mat4x4<f32>,
    colour: vec4<f32>,
    scalar: vec4<f32>,
};

@group(1) @binding(0) var<uniform> object: Object;

struct LineIn {
    @location(0) position: vec3<f32>,
    @location(1) colour: vec4<f32>,
};

struct LineOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec4<f32>,
};

@vertex
fn vs_main(in: LineIn) -> LineOut {
    var out: LineOut;
    var clip = frame.view_proj * object.model * vec4<f32>(in.position, 1.0);
    clip.z = clip.z - frame.params.x * clip.w;
    out.clip = clip;
    out.colour = vec4<f32>(srgb_to_linear(in.colour.rgb), in.colour.a);
    return out;
}

@fragment
fn fs_main(in: LineOut) -> @location(0) vec4<f32> {
    return in.colour;
}
