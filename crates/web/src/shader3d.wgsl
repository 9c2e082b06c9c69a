// The 3D view: lit, vertex-coloured triangles with a headlight and two-sided shading.

struct Globals {
    view_proj: mat4x4f,
    eye: vec4f,
};

@group(0) @binding(0) var<uniform> globals: Globals;

struct MeshIn {
    @location(0) position: vec3f,
    @location(1) normal: vec3f,
    @location(2) color: vec4f,
};

struct MeshOut {
    @builtin(position) clip: vec4f,
    @location(0) world: vec3f,
    @location(1) normal: vec3f,
    @location(2) color: vec4f,
};

@vertex
fn vs_mesh(in: MeshIn) -> MeshOut {
    var out: MeshOut;
    out.clip = globals.view_proj * vec4f(in.position, 1.0);
    out.world = in.position;
    out.normal = in.normal;
    out.color = in.color;
    return out;
}

@fragment
fn fs_mesh(in: MeshOut) -> @location(0) vec4f {
    let to_eye = normalize(globals.eye.xyz - in.world);
    let n = normalize(in.normal);
    let diffuse = abs(dot(n, to_eye));
    let shade = 0.38 + 0.62 * diffuse;
    return vec4f(in.color.rgb * shade, in.color.a);
}
