#define_import_path scene::chart
// Light-map charts (src/lightmap.rs): the atlas rectangle and projection of one chart, and the
// pure functions shared by every pass that addresses the light-map atlas. No bindings.

struct Chart {
    // Atlas rectangle (u0, v0, u1, v1) the chart may write and read.
    rect: vec4f,
    // Object-space lower corner on the projection axes (x, y), the side mapped onto the
    // rectangle's longer edge (z) and the object-space edge of one (square) texel (w).
    bounds: vec4f,
    // Projection axes a and b, signed axis (0..6: +x -x +y -y +z -z), object index.
    axes: vec4u,
};

// Same rule as lightmap::signed_axis (ties to the lower axis).
fn signed_axis(n: vec3f) -> u32 {
    let a = abs(n);
    var i = 2u;
    if (a.x >= a.y && a.x >= a.z) { i = 0u; } else if (a.y >= a.z) { i = 1u; }
    return 2u * i + select(0u, 1u, n[i] < 0.0);
}

// Atlas uv of object-space point `local` in chart `c` (lightmap::Chart::uv).
fn chart_uv(c: Chart, local: vec3f) -> vec2f {
    let s = clamp((vec2f(local[c.axes.x], local[c.axes.y]) - c.bounds.xy) / c.bounds.z,
                  vec2f(0.0), vec2f(1.0));
    return mix(c.rect.xy, c.rect.zw, s);
}

