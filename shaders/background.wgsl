// Background: a vertical gradient from `frame.background_top` to `frame.background_bottom`.

struct BackgroundOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) t: f32,
};

@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32) -> BackgroundOut {
    var out: BackgroundOut;
    out.clip = fullscreen_position(vertex_index);
    out.t = out.clip.y * 0.5 + 0.5;
    return out;
}

@fragment
fn fs_main(in: BackgroundOut) -> @location(0) vec4<f32> {
    let t = clamp(in.t, 0.0, 1.0);
    return vec4<f32>(mix(frame.background_bottom.rgb, frame.background_top.rgb, t), 1.0);
}
