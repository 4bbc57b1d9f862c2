// Shared by every Talas shader: the per-frame uniform block (camera and viewport settings).
// Prepended to each shader source by `render::shaders` before compilation.

struct Frame {
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    view: mat4x4<f32>,
    // xyz: eye position in world space; w: 1 for perspective, 0 for orthographic.
    eye: vec4<f32>,
    background_top: vec4<f32>,
    background_bottom: vec4<f32>,
    // x: grid plane z, y: minor spacing, z: major spacing, w: fade distance (0 = no grid).
    grid: vec4<f32>,
    grid_minor_colour: vec4<f32>,
    grid_major_colour: vec4<f32>,
    // x: line depth offset (NDC), yz: centre of the grid's fade (world xy).
    params: vec4<f32>,
};

@group(0) @binding(0) var<uniform> frame: Frame;

// A triangle covering the whole viewport, for full-screen passes (vertex_index 0..3).
fn fullscreen_position(vertex_index: u32) -> vec4<f32> {
    let x = f32((vertex_index << 1u) & 2u);
    let y = f32(vertex_index & 2u);
    return vec4<f32>(x * 2.0 - 1.0, 1.0 - y * 2.0, 0.0, 1.0);
}

// sRGB-encoded channel (0..1) to linear.
fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    let lo = c / 12.92;
    let hi = pow((c + vec3<f32>(0.055)) / 1.055, vec3<f32>(2.4));
    return select(hi, lo, c <= vec3<f32>(0.04045));
}
