// ---------------------------------------------------------------------------------------------
// Pieces shaded with per-piece environment distance impostors (Dancsik and Minarik, section
// 5): the section-5 driver's bindings (@group(2), 0..6) and its shading, for the entry points
// that import it (environment_piece_fs.wgsl; a proxy's, such as a height map's billboard).
// The per-object search is scene::pieces' piece_hit, piece_hit_normal and chord, which the
// search's module overrides (scene::multi_object::ObjectSearch).
//
// Piece p's environment impostor (rgb radiance, alpha distance from env_centres[p]) is cube p
// of `impostors`. A piece's first hit (rasterized from its mesh by environment_piece_fs, or
// found by a proxy's entry points, PieceSurface::Proxy, such as a height map's billboard) is
// shaded by
// shade_piece: reflection -> Hit() in its impostor; refraction -> through the piece (the
// search's chord() for the exit, up to EXIT_CHORDS internal reflections), each exit ray ->
// Hit() in the impostor. These are the paper's "three intersections"; the impostor holds
// multi-bounce radiance because the pieces were drawn into it env_depth times with this same
// shading (section 5.1). With a mover set (section 5.2), each lookup ray of another piece is
// also searched from outside in the moving piece's map (the search's piece_hit()); when it
// meets the moving piece before the environment surface, the moving piece is shaded there:
// its reflection and the refraction through it looked up in the moving piece's own impostor
// (the searches 5-7 of the paper's figure 5; the reflected ray ignores the moving piece
// itself: figure 9's error 2). The same shading draws pieces into other pieces' impostors
// (camera.eye = the cube's centre): alpha is the distance from the eye, as a distance
// impostor needs.
// ---------------------------------------------------------------------------------------------
#define_import_path scene::environment_pieces

#import gpu::prelude::{fresnel_dielectric, fresnel_nk, reflect_dir, refract_dir}
#import gpu::distance_map
#import gpu::layered_distance_map
#import scene::shading::{MATERIAL_METAL, objects, specular_event, specular_shade}
#import scene::pieces::{chord, piece_hit, piece_hit_normal, piece_object}

const NO_PIECE: u32 = 0xffffffffu;

struct EnvParams {
    // The moving piece other pieces search for, or NO_PIECE.
    mover: u32,
    // Hit() refinement steps in the impostors.
    env_iterations: u32,
    _pad_a: u32,
    _pad_b: u32,
};

@group(2) @binding(0) var<uniform> env: EnvParams;
// @binding(1): the piece table (scene::pieces).
// Reference point of each piece's impostor (world; w unused).
@group(2) @binding(2) var<storage, read> env_centres: array<vec4f>;
@group(2) @binding(3) var<storage, read> piece_of_object: array<u32>;
@group(2) @binding(4) var impostor_sampler: sampler;
@group(2) @binding(5) var impostors: texture_cube_array<f32>;

const SURFACE_OFFSET: f32 = 1e-4;
const EXIT_CHORDS: u32 = 3u;

// Radiance and ray parameter of the surface piece p's impostor shows along o + t d.
fn impostor_lookup(p: u32, o: vec3f, d: vec3f) -> vec4f {
    let h = layered_distance_map::hit_layered(o - env_centres[p].xyz, d, impostors, i32(p), impostor_sampler, 3u,
                        distance_map::HIT_FALSE_POSITION, env.env_iterations);
    var l = h.xyz;
    if (dot(l, l) < 1e-12) { l = d; }
    return vec4f(textureSampleLevel(impostors, impostor_sampler, l, i32(p), 0.0).rgb, h.w);
}

// The moving piece m met at `at` (outward normal n_out) by a ray along d: its reflection and
// the refraction through it, both looked up in its own impostor.
fn shade_mover(m: u32, at: vec3f, n_out: vec3f, d: vec3f) -> vec3f {
    let o = objects[piece_object(m)];
    let n = select(-n_out, n_out, dot(d, n_out) < 0.0);
    let cos_i = -dot(d, n);
    let reflected = impostor_lookup(m, at + n * SURFACE_OFFSET, reflect_dir(d, n)).rgb;
    if (o.material.x == MATERIAL_METAL) {
        return fresnel_nk(cos_i, o.n.xyz, o.k.xyz) * reflected;
    }
    let ior = o.material.y;
    let f = fresnel_dielectric(cos_i, ior);
    let into = refract_dir(d, n, 1.0 / ior);
    if (into.w < 0.5) { return reflected; }
    let e = chord(m, at - n * SURFACE_OFFSET, into.xyz);
    let out = refract_dir(into.xyz, -e.normal, ior);
    var through = vec3f(0.0);
    if (out.w > 0.5) {
        let g = fresnel_dielectric(dot(into.xyz, e.normal), 1.0 / ior);
        through = (1.0 - g) * impostor_lookup(m, e.exit_point + e.normal * SURFACE_OFFSET,
                                              out.xyz).rgb;
    }
    return f * reflected + (1.0 - f) * through;
}

// Radiance arriving at o from direction d, seen from piece p: its impostor, or the moving
// piece when one is set and the ray meets it first.
fn lookup(p: u32, o: vec3f, d: vec3f) -> vec3f {
    let seen = impostor_lookup(p, o, d);
    let m = env.mover;
    if (m == NO_PIECE || m == p) { return seen.rgb; }
    let h = piece_hit(m, o, d);
    if (h.w < 0.0 || h.w >= seen.w) { return seen.rgb; }
    return shade_mover(m, o + d * h.w, piece_hit_normal(m, o, d, h), d);
}

// Radiance carried out of piece p along the refracted ray entering at x with direction t.
fn through_piece(p: u32, x: vec3f, t: vec3f, ior: f32) -> vec3f {
    var origin = x;
    var dir = t;
    var share = 1.0;
    var color = vec3f(0.0);
    for (var s = 0u; s < EXIT_CHORDS; s++) {
        let e = chord(p, origin, dir);
        let out = refract_dir(dir, -e.normal, ior);
        let f = select(1.0, fresnel_dielectric(dot(dir, e.normal), 1.0 / ior), out.w > 0.5);
        if (out.w > 0.5) {
            color += share * (1.0 - f) * lookup(p, e.exit_point + e.normal * SURFACE_OFFSET,
                                                out.xyz);
        }
        share *= f;
        dir = reflect_dir(dir, -e.normal);
        origin = e.exit_point - e.normal * SURFACE_OFFSET;
    }
    return color;
}

// Piece p seen from `eye` at its first hit `world` (outward normal `normal`): the shaded
// radiance, and in alpha the distance from the eye (what an impostor stores).
fn shade_piece(p: u32, world: vec3f, normal: vec3f, eye: vec3f) -> vec4f {
    let object = piece_object(p);
    let v = normalize(world - eye);
    let e = specular_event(object, normal, world, eye, v);
    let reflected = lookup(p, world + e.normal * SURFACE_OFFSET, e.reflected);
    var refracted = reflected;
    if (e.refracted.w > 0.5) {
        if (e.entering) {
            refracted = through_piece(p, world - e.normal * SURFACE_OFFSET, e.refracted.xyz,
                                      objects[object].material.y);
        } else {
            refracted = lookup(p, world - e.normal * SURFACE_OFFSET, e.refracted.xyz);
        }
    }
    return vec4f(specular_shade(e, reflected, refracted), distance(world, eye));
}
