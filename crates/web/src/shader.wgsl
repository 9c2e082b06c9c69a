// The contour view's two pipelines: the function field as a filtered image over the whole target, and
// flat-coloured triangles (grid, contour, control points) blended over it.

struct FieldOut {
    @builtin(position) position: vec4f,
    @location(0) uv: vec2f,
};

// One triangle that covers the target: vertices (−1, −1), (3, −1), (−1, 3).
@vertex
fn vs_field(@builtin(vertex_index) index: u32) -> FieldOut {
    let p = vec2f(f32((index << 1u) & 2u), f32(index & 2u));
    var out: FieldOut;
    out.position = vec4f(p * 2.0 - 1.0, 0.0, 1.0);
    out.uv = vec2f(p.x, 1.0 - p.y);
    return out;
}

@group(0) @binding(0) var field: texture_2d<f32>;
@group(0) @binding(1) var field_sampler: sampler;

@fragment
fn fs_field(in: FieldOut) -> @location(0) vec4f {
    return textureSample(field, field_sampler, in.uv);
}

struct ShapeIn {
    @location(0) position: vec2f,
    @location(1) color: vec4f,
};

struct ShapeOut {
    @builtin(position) position: vec4f,
    @location(0) color: vec4f,
};

@vertex
fn vs_shape(in: ShapeIn) -> ShapeOut {
    var out: ShapeOut;
    out.position = vec4f(in.position, 0.0, 1.0);
    out.color = in.color;
    return out;
}

@fragment
fn fs_shape(in: ShapeOut) -> @location(0) vec4f {
    return in.color;
}
