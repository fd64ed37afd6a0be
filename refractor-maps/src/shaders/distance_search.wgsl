// ---------------------------------------------------------------------------------------------
// The per-object search of scene's many-object drivers (the tracer, the section-5 impostors)
// with refractor distance maps (Dancsik and Minarik, sections 3-4.1): one cube map per kind of
// piece (outward normal + distance of its own surface from its centre), searched from inside
// by Hit() for a chord's exit and from outside by hit_from_outside (section 4.1), both in the
// layered form of Hit(): kind k's map is cube k of one cube-map array. It overrides
// scene::pieces' piece_hit, piece_hit_normal and chord; its bindings follow the driver's in
// @group(2), from SEARCH_FIRST_BINDING (scene::pieces).
// ---------------------------------------------------------------------------------------------
#define_import_path refractor_maps::distance_search

#import gpu::distance_map
#import gpu::layered_distance_map
#import scene::pieces::{Chord, SEARCH_FIRST_BINDING, from_map, piece_kind, pieces, to_map}

struct DistanceSearch {
    // Refinement steps of Hit() in the refractor maps.
    iterations: u32,
    // A search from outside is accepted within this distance of the ray (metres).
    epsilon: f32,
    _pad_a: u32,
    _pad_b: u32,
};

@group(2) @binding(SEARCH_FIRST_BINDING) var<uniform> distance_search: DistanceSearch;
@group(2) @binding(SEARCH_FIRST_BINDING + 1u) var map_sampler: sampler;
// Kind k's refractor map is cube k of the array.
@group(2) @binding(SEARCH_FIRST_BINDING + 2u) var kind_maps: texture_cube_array<f32>;

fn kind_sample(kind: u32, dir: vec3f) -> vec4f {
    return textureSampleLevel(kind_maps, map_sampler, dir, i32(kind), 0.0);
}

// Hit() from inside a piece: x and R in the map's frame, relative to its centre.
fn kind_hit(kind: u32, x: vec3f, R: vec3f) -> vec4f {
    return layered_distance_map::hit_layered(x, R, kind_maps, i32(kind), map_sampler, 3u,
                                             distance_map::HIT_FALSE_POSITION,
                                             distance_search.iterations);
}

// The search from outside (section 4.1) in the kind's map.
fn kind_hit_outside(kind: u32, y: vec3f, R: vec3f, bmin: vec3f, bmax: vec3f) -> vec4f {
    return layered_distance_map::hit_from_outside_layered(y, R, kind_maps, i32(kind),
        map_sampler, 3u, bmin, bmax, distance_map::HIT_FALSE_POSITION,
        distance_search.iterations, distance_search.epsilon);
}

// The search from outside: (hit point in the map's frame, ray parameter) or w < 0.
override fn scene::pieces::piece_hit(p: u32, o: vec3f, d: vec3f) -> vec4f {
    let pc = pieces[p];
    return kind_hit_outside(piece_kind(p), to_map(p, o - pc.centre.xyz), to_map(p, d),
                            pc.box_min.xyz, pc.box_max.xyz);
}

// The outward unit normal (world) stored by piece p's map in map-frame direction `l`,
// `fallback` where the map holds none.
fn piece_normal(p: u32, l: vec3f, fallback: vec3f) -> vec3f {
    let n = from_map(p, kind_sample(piece_kind(p), l).xyz);
    let len = length(n);
    return select(fallback, n / len, len > 1e-6);
}

// The normal at piece_hit's answer: the map's normal in the direction of the hit point.
override fn scene::pieces::piece_hit_normal(p: u32, o: vec3f, d: vec3f, hit: vec4f) -> vec3f {
    return piece_normal(p, hit.xyz, -d);
}

// One chord inside piece p from `origin` along `dir`: the exit point by Hit() in the piece's
// refractor map and the outward normal stored there (turned to agree with the leaving ray).
override fn scene::pieces::chord(p: u32, origin: vec3f, dir: vec3f) -> Chord {
    let pc = pieces[p];
    let R = to_map(p, dir);
    let h = kind_hit(piece_kind(p), to_map(p, origin - pc.centre.xyz), R);
    var l = h.xyz;
    if (dot(l, l) < 1e-12) { l = R; }
    var c: Chord;
    c.exit_point = origin + dir * h.w;
    c.normal = piece_normal(p, l, dir);
    if (dot(c.normal, dir) < 0.0) { c.normal = -c.normal; }
    return c;
}
