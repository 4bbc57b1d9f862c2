// Ground grid: an infinite plane z = frame.grid.x drawn as a full-screen pass. Each pixel's view
// ray is intersected with the plane; minor and major lines are anti-aliased with screen-space
// derivatives and fade with distance. Writes the plane's depth so parts hide the grid.

struct GridOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) ndc: vec2<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) vertex_index: u32) -> GridOut {
    var out: GridOut;
    out.clip = fullscreen_position(vertex_index);
    out.ndc = out.clip.xy;
    return out;
}

struct GridFragment {
    @location(0) colour: vec4<f32>,
    @builtin(frag_depth) depth: f32,
};

fn unproject(ndc: vec2<f32>, z: f32) -> vec3<f32> {
    let p = frame.inv_view_proj * vec4<f32>(ndc, z, 1.0);
    return p.xyz / p.w;
}

// Coverage (0..1) of grid lines of the given spacing at planar point `p`.
fn line_coverage(p: vec2<f32>, spacing: f32) -> f32 {
    let coord = p / spacing;
    let width = max(fwidth(coord), vec2<f32>(1e-6));
    let g = abs(fract(coord - 0.5) - 0.5) / width;
    return 1.0 - min(min(g.x, g.y), 1.0);
}

@fragment
fn fs_main(in: GridOut) -> GridFragment {
    var out: GridFragment;
    // The view ray: from the eye in perspective (so the plane shows in front of the near plane
    // too), from the near plane in orthographic, where it may extend both ways.
    var near = unproject(in.ndc, 0.0);
    let far = unproject(in.ndc, 1.0);
    var t_min = -1e30;
    if frame.eye.w > 0.5 {
        near = frame.eye.xyz;
        t_min = 0.0;
    }
    let dir = far - near;
    let plane_z = frame.grid.x;
    var t = -2e30;
    if abs(dir.z) > 1e-12 {
        t = (plane_z - near.z) / dir.z;
    }
    let hit = near + dir * max(t, t_min);
    let minor = line_coverage(hit.xy, frame.grid.y);
    let major = line_coverage(hit.xy, frame.grid.z);
    let clip = frame.view_proj * vec4<f32>(hit, 1.0);
    let fade = 1.0 - smoothstep(0.45, 1.0, length(hit.xy - frame.params.yz) / max(frame.grid.w, 1e-6));
    var colour = frame.grid_minor_colour * minor;
    colour = mix(colour, frame.grid_major_colour, major);
    var alpha = colour.a * fade;
    if t < t_min || frame.grid.w <= 0.0 {
        alpha = 0.0;
    }
    // Grazing views: thin the grid out where lines would alias into a solid sheet.
    let facing = abs(normalize(dir).z);
    alpha = alpha * smoothstep(0.02, 0.15, facing);
    out.colour = vec4<f32>(colour.rgb, alpha);
    out.depth = clamp(clip.z / clip.w, 0.0, 1.0);
    if alpha <= 0.002 {
        out.depth = 1.0;
    }
    return out;
}
