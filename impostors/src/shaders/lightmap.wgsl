// Light-map charts of the caustic receivers (src/lightmap.rs explains the atlas), after the
// gpu prelude + scene.wgsl + chart.wgsl. A diffuse object's triangle belongs to the chart of
// the signed dominant axis of its object-space normal and is projected onto the two other
// axes.

@group(3) @binding(2) var<storage, read> charts: array<Chart>;
@group(3) @binding(3) var<storage, read> chart_of: array<i32>;

// World point -> object space: the linear part's inverse is the normal matrix transposed.
fn world_to_local(object: u32, p: vec3f) -> vec3f {
    let o = objects[object];
    let n3 = mat3x3f(o.normal_matrix[0].xyz, o.normal_matrix[1].xyz, o.normal_matrix[2].xyz);
    return transpose(n3) * (p - o.model[3].xyz);
}

// Object-space normal (up to scale) from a world normal: the model's linear part transposed.
fn normal_to_local(object: u32, n: vec3f) -> vec3f {
    let o = objects[object];
    let m3 = mat3x3f(o.model[0].xyz, o.model[1].xyz, o.model[2].xyz);
    return transpose(m3) * n;
}

// Chart index of `object`'s surface facing `local_normal` (object space), or -1.
fn chart_index(object: u32, local_normal: vec3f) -> i32 {
    let i = 6u * object + signed_axis(local_normal);
    if (i >= arrayLength(&chart_of)) { return -1; }
    return chart_of[i];
}

// The chart under a fragment of a diffuse object: its index (-1: none) and the atlas uv.
// The interpolated authored normal, taken to object space, picks the axis: for the flat
// faces of our receivers it is the geometric normal that lightmap.rs uses. (Screen-space
// derivatives of the position would give the geometric normal itself, but on lavapipe they
// degenerate on some quads along triangle edges, which showed as bright lines.)
struct ChartHit {
    index: i32,
    uv: vec2f,
    // Object-space normal (unnormalised).
    local_normal: vec3f,
};

fn fragment_chart(object: u32, world: vec3f, normal: vec3f) -> ChartHit {
    let local = world_to_local(object, world);
    let n = normal_to_local(object, normal);
    var hit: ChartHit;
    hit.index = chart_index(object, n);
    hit.local_normal = n;
    hit.uv = vec2f(0.0);
    if (hit.index >= 0) { hit.uv = chart_uv(charts[hit.index], local); }
    return hit;
}

// Area on the surface of one texel of chart `c`, where the surface's object-space normal is
// `local_normal`: the texel's projected square t^2 in object space, divided by the cosine to
// the chart's axis (the surface is tilted against the projection plane), scaled to world
// space. A surface element dA with unit normal n maps to |det M| |M^-T n| dA under the
// model's linear part M; the normal matrix N = M^-T gives |det M| = 1 / |det N|.
fn texel_area(c: Chart, object: u32, local_normal: vec3f) -> f32 {
    let n = normalize(local_normal);
    let o = objects[object];
    let nm = mat3x3f(o.normal_matrix[0].xyz, o.normal_matrix[1].xyz, o.normal_matrix[2].xyz);
    let axis = c.axes.z / 2u;
    let cos_axis = max(abs(n[axis]), 1e-3);
    let t = c.bounds.w;
    return t * t / cos_axis * length(nm * n) / abs(determinant(nm));
}
