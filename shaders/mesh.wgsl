// Shaded triangle meshes: smooth normals, a headlight plus a key light, Blinn-Phong highlights,
// two-sided lighting, and an optional per-vertex scalar shown through a colour-map texture.

struct Object {
    model: mat4x4<f32>,
    normal_matrix: mat4x4<f32>,
    // Linear RGBA base colour.
    colour: vec4<f32>,
    // x: scalar at the start of the colour map, y: 1 / (scalar range), z: 1 to use the scalar,
    // w: texture v coordinate of the colour map's row.
    scalar: vec4<f32>,
};

@group(1) @binding(0) var<uniform> object: Object;
@group(0) @binding(1) var colour_map: texture_2d<f32>;
@group(0) @binding(2) var colour_map_sampler: sampler;

struct MeshIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) scalar: f32,
};

struct MeshOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal_view: vec3<f32>,
    @location(1) position_view: vec3<f32>,
    @location(2) scalar: f32,
};

@vertex
fn vs_main(in: MeshIn) -> MeshOut {
    var out: MeshOut;
    let world = object.model * vec4<f32>(in.position, 1.0);
    out.clip = frame.view_proj * world;
    let normal_world = (object.normal_matrix * vec4<f32>(in.normal, 0.0)).xyz;
    out.normal_view = (frame.view * vec4<f32>(normal_world, 0.0)).xyz;
    out.position_view = (frame.view * world).xyz;
    out.scalar = in.scalar;
    return out;
}

@fragment
fn fs_main(in: MeshOut) -> @location(0) vec4<f32> {
    // Direction to the viewer in view space.
    var to_eye = vec3<f32>(0.0, 0.0, 1.0);
    if frame.eye.w > 0.5 {
        to_eye = normalize(-in.position_view);
    }
    var n = in.normal_view;
    let len = length(n);
    if len > 1e-20 {
        n = n / len;
    } else {
        n = to_eye;
    }
    // Two-sided: light the side that faces the viewer.
    if dot(n, to_eye) < 0.0 {
        n = -n;
    }

    var base = object.colour.rgb;
    if object.scalar.z > 0.5 {
        let t = clamp((in.scalar - object.scalar.x) * object.scalar.y, 0.0, 1.0);
        base = textureSampleLevel(colour_map, colour_map_sampler, vec2<f32>(t, object.scalar.w), 0.0).rgb;
    }

    let key = normalize(vec3<f32>(-0.45, 0.65, 0.6));
    let head_diffuse = max(dot(n, to_eye), 0.0);
    let key_diffuse = max(dot(n, key), 0.0);
    let hemisphere = 0.5 + 0.5 * n.y;
    let ambient = mix(0.10, 0.20, hemisphere);
    let diffuse = 0.55 * head_diffuse + 0.35 * key_diffuse + ambient;
    let key_half = normalize(key + to_eye);
    let specular = 0.22 * pow(max(dot(n, key_half), 0.0), 48.0)
        + 0.10 * pow(head_diffuse, 24.0);
    return vec4<f32>(base * diffuse + vec3<f32>(specular), object.colour.a);
}
