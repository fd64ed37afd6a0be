// Light-map charts of the caustic receivers (scene's lightmap.rs explains the atlas): the module
// impostors::lightmap, its chart tables at the caustic passes' @group(3), bindings 2 and 3.
// A diffuse object's triangle belongs to the chart of the signed dominant axis of its
// object-space normal and is projected onto the two other axes.
#define_import_path impostors::lightmap

#import scene::chart::{Chart, signed_axis, chart_uv}
#import scene::receiver::{world_to_local, normal_to_local}

@group(3) @binding(2) var<storage, read> charts: array<Chart>;
@group(3) @binding(3) var<storage, read> chart_of: array<i32>;

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
