// Composite: copies the resolved scene texture into the egui render pass (the viewport rect).
// The scene texture is sRGB; when egui's target is not, the shader encodes to sRGB itself.

@group(0) @binding(0) var scene: texture_2d<f32>;
@group(0) @binding(1) var scene_sampler: sampler;
// x: 1 to encode linear -> sRGB in the shader (non-sRGB target).
@group(0) @binding(2) var<uniform> settings: vec4<f32>;

struct CompositeOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32) -> CompositeOut {
    var out: CompositeOut;
    let x = f32((vertex_index << 1u) & 2u);
    let y = f32(vertex_index & 2u);
    out.clip = vec4<f32>(x * 2.0 - 1.0, 1.0 - y * 2.0, 0.0, 1.0);
    out.uv = vec2<f32>(x, y);
    return out;
}

fn linear_to_srgb(c: vec3<f32>) -> vec3<f32> {
    let lo = c * 12.92;
    let hi = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - vec3<f32>(0.055);
    return select(hi, lo, c <= vec3<f32>(0.0031308));
}

@fragment
fn fs_main(in: CompositeOut) -> @location(0) vec4<f32> {
    let c = textureSampleLevel(scene, scene_sampler, in.uv, 0.0);
    if settings.x > 0.5 {
        return vec4<f32>(linear_to_srgb(c.rgb), 1.0);
    }
    return vec4<f32>(c.rgb, 1.0);
}
