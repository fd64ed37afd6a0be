// ---------------------------------------------------------------------------------------------
// The per-object search of scene's many-object drivers (the tracer, the section-5 impostors)
// with refractor height maps: section 6's "in the algorithm described in 5.2, the refractor
// distance map can be replaced by the refractor height map". It overrides scene::pieces'
// piece_hit, piece_hit_normal and chord with height_maps::search's searches; its bindings follow
// the driver's in @group(2), from SEARCH_FIRST_BINDING (scene::pieces).
//
// A piece's billboard faces the ray's origin (the search from outside) or, for a ray inside
// the piece, the point it came from (origin - dir): the eye-facing billboard of the
// entering ray, near enough, since refraction bends a ray by less than its angle of incidence.
// ---------------------------------------------------------------------------------------------
#define_import_path height_maps::object_search

#import scene::pieces::{Chord, SEARCH_FIRST_BINDING, piece_kind, pieces}
#import height_maps::search::{Steps, HeightBounds, billboard_facing, dir_to_plane, to_plane, dir_to_world, search_from_outside, exit_from_inside}

struct HeightSearchParams {
    linear_steps: u32,
    binary_steps: u32,
    _pad_a: u32,
    _pad_b: u32,
};

@group(2) @binding(SEARCH_FIRST_BINDING) var<uniform> height_search: HeightSearchParams;
@group(2) @binding(SEARCH_FIRST_BINDING + 1u) var height_maps: texture_2d_array<f32>;
// Each kind's bounds: half width, v min, v max, height.
@group(2) @binding(SEARCH_FIRST_BINDING + 2u) var<storage, read> kind_bounds: array<vec4f>;

fn kind_height_bounds(kind: u32) -> HeightBounds {
    let b = kind_bounds[kind];
    return HeightBounds(b.x, b.y, b.z, b.w);
}

fn height_search_steps() -> Steps {
    return Steps(height_search.linear_steps, height_search.binary_steps);
}

// The search from outside: (outward world normal at the hit, t), t < 0 when missed.
override fn scene::pieces::piece_hit(p: u32, o: vec3f, d: vec3f) -> vec4f {
    let kind = piece_kind(p);
    let b = billboard_facing(pieces[p].centre.xyz, o);
    let h = search_from_outside(height_maps, i32(kind), kind_height_bounds(kind), to_plane(b, o),
                                dir_to_plane(b, d), height_search_steps());
    if (!h.found) { return vec4f(0.0, 0.0, 0.0, -1.0); }
    return vec4f(dir_to_world(b, h.normal), h.t);
}

override fn scene::pieces::piece_hit_normal(p: u32, o: vec3f, d: vec3f, hit: vec4f) -> vec3f {
    return hit.xyz;
}

// The exit of a ray inside piece p and the outward normal there (agreeing with the ray).
override fn scene::pieces::chord(p: u32, origin: vec3f, dir: vec3f) -> Chord {
    let kind = piece_kind(p);
    let b = billboard_facing(pieces[p].centre.xyz, origin - dir);
    let e = exit_from_inside(height_maps, i32(kind), kind_height_bounds(kind), to_plane(b, origin),
                             dir_to_plane(b, dir), height_search_steps());
    var c: Chord;
    c.exit_point = origin;
    c.normal = dir;
    if (e.found) {
        c.exit_point = origin + dir * e.t;
        c.normal = dir_to_world(b, e.normal);
        if (dot(c.normal, dir) < 0.0) { c.normal = -c.normal; }
    }
    return c;
}
