// ---------------------------------------------------------------------------------------------
// The scene's triangles as every traversal of the ray tracer sees them (raytracer::bvh): their
// intersection data in `bvh_triangles` (obvhs' RtTriangle layout), their shading attributes in
// `bvh_attributes`, a query's result (`TraceHit`) and the hit with what shading needs
// (`surface_hit`). A traversal (raytracer::bvh: the BVH in software; raytracer::ray_query: the
// hardware's) answers `trace` with a TraceHit (raytracer::queries). The traversal's structure is
// bound at @group(0) @binding(#{TRACE_FIRST_BINDING}) (the tracer: 1, raytracer::tracer::TRACE_FIRST_BINDING), the
// triangles, their attributes and the alpha cut-outs (with the tracer's texels) at the next three
// bindings.
//
// The fields are obvhs' under names without a trailing digit (naga_oil's modules cannot keep
// those): the vertices v0, v1, v2 are a, b, c, so v0 is `va`, e1 = v0 - v1 is `a_minus_b`,
// e2 = v2 - v0 is `c_minus_a`, n0 is `na` and uv01 is `uv_ab` (raytracer::bvh's TriangleGpu and
// AttributesGpu keep obvhs' names).
// ---------------------------------------------------------------------------------------------
#define_import_path raytracer::triangles

struct BvhTriangle {
    va: vec3f,
    // a - b, c - a and ng = (a - b) x (c - a) (computed on the CPU).
    a_minus_b: vec3f,
    c_minus_a: vec3f,
    ng: vec3f,
};

struct BvhAttributes {
    na: vec3f,
    object: u32,
    nb: vec3f,
    triangle: u32,
    nc: vec3f,
    geometric_normal: vec3f,
    uv_ab: vec4f,
    uv_c: vec2f,
};

@group(0) @binding(#{TRACE_FIRST_BINDING} + 1u) var<storage, read> bvh_triangles: array<BvhTriangle>;
@group(0) @binding(#{TRACE_FIRST_BINDING} + 2u) var<storage, read> bvh_attributes: array<BvhAttributes>;
// The objects' alpha cut-outs (raytracer::bvh::cutout_table: word 0 the number of object
// records, 0 for no cut-out; then per object its threshold's bits or 0, its first alpha word,
// width and height; then the alphas, one byte per texel, four to a word), followed by whatever
// the traversal's user stores after them (the tracer: every texture's RGBA8 texels).
@group(0) @binding(#{TRACE_FIRST_BINDING} + 3u) var<storage, read> texture_data: array<u32>;

const NO_HIT: u32 = 0xffffffffu;

struct TraceHit {
    // Triangle index in leaf order, NO_HIT for none.
    triangle: u32,
    t: f32,
};

// Barycentrics (u, v), weights (1 - u - v, u, v) of (v0, v1, v2): obvhs'
// RtTriangle::compute_barycentric.
fn hit_barycentrics(tri: BvhTriangle, o: vec3f, d: vec3f) -> vec2f {
    let r = cross(d, tri.va - o);
    return vec2f(dot(r, tri.c_minus_a), dot(r, tri.a_minus_b)) / dot(tri.ng, d);
}

// A hit with what shading needs (scene::bvh::Hit).
struct SurfaceHit {
    t: f32,
    object: u32,
    position: vec3f,
    // Interpolated shading normal, as authored.
    normal: vec3f,
    geometric_normal: vec3f,
    uv: vec2f,
};

// TriangleInfo::hit: the interpolation the reference does.
fn surface_hit(h: TraceHit, o: vec3f, d: vec3f) -> SurfaceHit {
    let a = bvh_attributes[h.triangle];
    let b = hit_barycentrics(bvh_triangles[h.triangle], o, d);
    let w = 1.0 - b.x - b.y;
    let n = a.na * w + a.nb * b.x + a.nc * b.y;
    var s: SurfaceHit;
    s.t = h.t;
    s.object = a.object;
    s.position = o + d * h.t;
    s.normal = select(a.geometric_normal, normalize(n), dot(n, n) > 0.0);
    s.geometric_normal = a.geometric_normal;
    s.uv = a.uv_ab.xy * w + a.uv_ab.zw * b.x + a.uv_c * b.y;
    return s;
}

// The alpha of texel (i, j), wrapping, of the cut-out texture whose alphas start at `first`.
fn cutout_alpha(first: u32, size: vec2i, i: i32, j: i32) -> f32 {
    let x = ((i % size.x) + size.x) % size.x;
    let y = ((j % size.y) + size.y) % size.y;
    let k = u32(y * size.x + x);
    return f32((texture_data[first + k / 4u] >> (8u * (k % 4u))) & 0xffu) / 255.0;
}

// glam's Vec3::lerp, as scene::Texture::sample_alpha filters.
fn lerp_alpha(a: f32, b: f32, t: f32) -> f32 {
    return a * (1.0 - t) + b * t;
}

// Whether the hit at barycentrics b of `triangle` lies where its object's cut-out texture
// (bilinear, wrapping) has alpha below the threshold: the surface is not there, the ray goes
// on (raytracer::bvh::in_hole, its twin).
fn in_hole(triangle: u32, b: vec2f) -> bool {
    if (texture_data[0] == 0u) { return false; }
    let a = bvh_attributes[triangle];
    let record = 1u + 4u * a.object;
    let threshold = bitcast<f32>(texture_data[record]);
    if (threshold <= 0.0) { return false; }
    let first = texture_data[record + 1u];
    let size = vec2i(i32(texture_data[record + 2u]), i32(texture_data[record + 3u]));
    let uv = a.uv_ab.xy * (1.0 - b.x - b.y) + a.uv_ab.zw * b.x + a.uv_c * b.y;
    let p = uv * vec2f(size) - 0.5;
    let p0 = floor(p);
    let f = p - p0;
    let i = i32(p0.x);
    let j = i32(p0.y);
    let top = lerp_alpha(cutout_alpha(first, size, i, j), cutout_alpha(first, size, i + 1, j), f.x);
    let bottom = lerp_alpha(cutout_alpha(first, size, i, j + 1), cutout_alpha(first, size, i + 1, j + 1), f.x);
    return lerp_alpha(top, bottom, f.y) < threshold;
}
